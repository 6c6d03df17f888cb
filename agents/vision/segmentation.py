"""Colour segmentation (thesis section 4.1): RGB thresholds in priority order, as a lookup table.

Each colour class has an RGB range (a box, inclusive bounds); a pixel takes the first
class of :data:`~agents.vision.colors.PRIORITY` whose range holds it, and white when none
does. The ranges are not typed in by hand: ``robotstadium calibrate-colors`` measures them
on frames of our renderer whose true classes are known, and writes
``agents/vision/data/color_thresholds.json``, which :func:`load_thresholds` reads.

Classification is one table lookup per pixel (64 levels per channel, 256 KiB table),
followed by the thesis' neighbour-based cleaning of isolated pixels.
"""

from __future__ import annotations

import json
import logging
from dataclasses import dataclass
from functools import cached_property
from importlib import resources
from pathlib import Path

import numpy as np

from agents.vision.colors import PRIORITY, UNFITTED, ColorClass
from agents.vision.errors import ColorTableError
from agents.vision.kernels import LEVEL_SHIFT, classify_pixels, clean_isolated

LOG = logging.getLogger(__name__)

LEVELS = 256 >> LEVEL_SHIFT
DEFAULT_THRESHOLDS_RESOURCE = "color_thresholds.json"
MAX_THRESHOLDS_BYTES = 1 << 20  # a threshold file is under a kilobyte


@dataclass(frozen=True)
class ColorBox:
    """The RGB range of one colour class: ``low <= (r, g, b) <= high``, channel by channel."""

    color: ColorClass
    low: tuple[int, int, int]
    high: tuple[int, int, int]

    def __post_init__(self) -> None:
        for name, value in (("low", self.low), ("high", self.high)):
            if len(value) != 3 or not all(isinstance(v, int) and 0 <= v <= 255 for v in value):
                raise ColorTableError(f"{self.color.name.lower()} {name} must be three integers in [0, 255]; got {value!r}")
        if any(lo > hi for lo, hi in zip(self.low, self.high)):
            raise ColorTableError(f"{self.color.name.lower()} range is empty: low {self.low} > high {self.high}")

    def contains(self, rgb: np.ndarray) -> np.ndarray:
        """Boolean mask of the RGB values (..., 3) inside this range."""
        rgb = np.asarray(rgb)
        return np.all((rgb >= np.asarray(self.low)) & (rgb <= np.asarray(self.high)), axis=-1)


@dataclass(frozen=True)
class ColorThresholds:
    """One RGB range per colour class, and a note of how they were obtained."""

    boxes: tuple[ColorBox, ...]
    source: str = ""

    def __post_init__(self) -> None:
        colors = [box.color for box in self.boxes]
        if len(set(colors)) != len(colors):
            raise ColorTableError(f"each colour class may have one range; got {[c.name.lower() for c in colors]}")

    def box(self, color: ColorClass) -> ColorBox | None:
        return next((b for b in self.boxes if b.color is color), None)

    def classify(self, rgb: np.ndarray) -> np.ndarray:
        """Class labels (uint8) of RGB values (..., 3), first fitting class in priority order."""
        rgb = np.asarray(rgb)
        labels = np.full(rgb.shape[:-1], int(UNFITTED), np.uint8)
        undecided = np.ones(rgb.shape[:-1], bool)
        for color in PRIORITY:
            box = self.box(color)
            if box is None:
                continue
            hit = undecided & box.contains(rgb)
            labels[hit] = int(color)
            undecided &= ~hit
        return labels

    def to_json(self) -> dict:
        return {
            "source": self.source,
            "priority": [c.name.lower() for c in PRIORITY],
            "classes": {b.color.name.lower(): {"low": list(b.low), "high": list(b.high)} for b in self.boxes},
        }

    @classmethod
    def from_json(cls, data: object, origin: str = "thresholds") -> ColorThresholds:
        if not isinstance(data, dict) or not isinstance(data.get("classes"), dict):
            raise ColorTableError(f"{origin}: expected an object with a 'classes' object; got {type(data).__name__}")
        boxes = []
        for name, entry in data["classes"].items():
            try:
                color = ColorClass[str(name).upper()]
            except KeyError:
                raise ColorTableError(
                    f"{origin}: unknown colour class {name!r}; expected one of {[c.name.lower() for c in ColorClass]}"
                ) from None
            if (not isinstance(entry, dict) or set(entry) != {"low", "high"}
                    or not all(isinstance(entry[end], list) for end in ("low", "high"))):
                raise ColorTableError(f"{origin}: class {name!r} needs exactly 'low' and 'high', each a list of three "
                                      f"integers; got {_cut(repr(entry))}")
            boxes.append(ColorBox(color, tuple(entry["low"]), tuple(entry["high"])))
        return cls(tuple(boxes), str(data.get("source", "")))

    def save(self, path: Path) -> None:
        Path(path).write_text(json.dumps(self.to_json(), indent=2) + "\n")


def load_thresholds(path: Path | None = None) -> ColorThresholds:
    """Read a threshold file; without ``path``, the calibrated thresholds shipped with the package."""
    if path is None:
        text = resources.files("agents.vision").joinpath("data", DEFAULT_THRESHOLDS_RESOURCE).read_text()
        origin = f"agents/vision/data/{DEFAULT_THRESHOLDS_RESOURCE}"
    else:
        text = _read_thresholds_file(Path(path))
        origin = str(path)
    try:
        data = json.loads(text)
    except (ValueError, RecursionError) as exc:  # not JSON, a number of thousands of digits, nested too deep
        raise ColorTableError(f"{origin}: not valid JSON ({_cut(str(exc))})") from None
    return ColorThresholds.from_json(data, origin)


def _read_thresholds_file(path: Path) -> str:
    """The text of a threshold file: a regular file of at most :data:`MAX_THRESHOLDS_BYTES` (a link to a
    device or a pipe is refused before it is opened)."""
    try:
        if not path.is_file():
            raise ColorTableError(f"cannot read colour thresholds {path}: not an existing regular file")
        with path.open("rb") as handle:
            raw = handle.read(MAX_THRESHOLDS_BYTES + 1)
        if len(raw) > MAX_THRESHOLDS_BYTES:
            raise ColorTableError(f"cannot read colour thresholds {path}: more than {MAX_THRESHOLDS_BYTES} bytes")
        return raw.decode("utf-8")
    except (OSError, ValueError) as exc:  # ValueError: not UTF-8, a NUL byte in the name
        raise ColorTableError(f"cannot read colour thresholds {path}: {_cut(str(exc))}") from None


def _cut(text: str, chars: int = 200) -> str:
    return text if len(text) <= chars else text[: chars - 3] + "..."


class ColorTable:
    """The thresholds compiled into a lookup table over quantized RGB, and the segmenter."""

    def __init__(self, thresholds: ColorThresholds):
        self.thresholds = thresholds

    @cached_property
    def table(self) -> np.ndarray:
        """Labels of every quantized colour, indexed by ``(r >> 2) << 12 | (g >> 2) << 6 | (b >> 2)``."""
        level = (np.arange(LEVELS) << LEVEL_SHIFT) + (1 << LEVEL_SHIFT) // 2
        r, g, b = np.meshgrid(level, level, level, indexing="ij")
        return self.thresholds.classify(np.stack([r, g, b], axis=-1)).reshape(-1)

    def classify(self, image: np.ndarray) -> np.ndarray:
        """Raw class labels (H, W) uint8 of an RGB uint8 image (H, W, 3), before cleaning."""
        if image.dtype != np.uint8 or image.ndim != 3 or image.shape[2] != 3:
            raise ValueError(f"classify() takes an RGB uint8 image (H, W, 3); got {image.dtype} {image.shape}")
        return classify_pixels(image, self.table)

    def segment(self, image: np.ndarray) -> np.ndarray:
        """Cleaned class labels (H, W) uint8 of an RGB uint8 image: the thesis' segmented image."""
        return clean_outliers(self.classify(image))


def clean_outliers(labels: np.ndarray) -> np.ndarray:
    """The thesis' neighbour check (section 4.1), on a copy of ``labels`` (H, W) uint8.

    A non-white pixel with no 8-neighbour of its own class becomes white; a white pixel
    with no white 8-neighbour becomes orange when most of its neighbours are orange, and
    green otherwise (:func:`agents.vision.kernels.clean_isolated`).
    """
    if labels.dtype != np.uint8 or labels.ndim != 2:
        raise ValueError(f"clean_outliers() takes class labels (H, W) uint8; got {labels.dtype} {labels.shape}")
    return clean_isolated(labels)
