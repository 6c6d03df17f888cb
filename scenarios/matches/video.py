"""Camera videos of a match: what a robot's camera saw, what its vision made of it, and where it was.

:class:`VideoRecorder` watches a run (a :class:`match.runner.ObservationWatcher`) and writes one
``video_<agent>.mp4`` per recorded robot: one video frame per camera frame of that robot
(steps with its camera off are skipped), at its camera's rate, taken from the median
interval between its first :data:`RATE_FRAMES` frames (12.5 frames/s for the built-in
players, whose camera is on every other 40 ms step). A video frame, left to right:

- the camera image (160x120, enlarged :data:`SCALE` times) with the recognized landmarks
  labelled and the ball circled;
- the vision debug overlay of :mod:`agents.vision.overlay` on the segmented image: field
  border, scan lines, formed and classified lines, landmarks, the ball;
- a field map (field frame, +x to the right) with the robot's true pose (filled, in its
  team's colour), its own pose estimate (a red ring, and the error line to the truth) when
  its policy reports one, the true ball, and the robot's policy, the time, game state and
  estimate error.

Evaluation only: the recorder runs a vision pipeline of its own on the images and reads
the ground truth; nothing goes back to the policies. Encoded as H.264 by imageio's ffmpeg
plugin (the ``imageio-ffmpeg`` wheel ships the encoder).
"""

from __future__ import annotations

import logging
import math
import statistics
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from agents.observation import Observation
from agents.vision.ball import ball_in_mask, plausible
from agents.vision.colors import ColorClass
from agents.vision.frame import CameraFrame
from agents.vision.overlay import draw_overlay
from agents.vision.pipeline import VisionPipeline
from match.game import Match
from match.protocol import Action, AgentId
from match.protocol.policy import PoseTuple
from world.field import FIELD
from world.teams import TeamColor

log = logging.getLogger(__name__)

SCALE = 3  # camera pixels -> video pixels
MAP_WIDTH_PX = 480
HEADER_PX = 44  # text above the field map
MARGIN_PX = 10
POLICY_CHARS = 22  # a policy's name in a frame's caption is cut to this many characters
RATE_FRAMES = 5  # the camera rate is measured over this many first frames
MAX_FPS = 25.0  # one frame per 40 ms control step
MIN_FPS = 1.0
DEFAULT_FPS = 12.5  # a robot with one frame only: the built-in players' camera rate
QUALITY = 7  # imageio's 0-10 scale
PRESET = "veryfast"  # x264: about half the encoding time of its default for 6 % more bytes here
CARPET_RGB = (40, 130, 40)
FLOOR_RGB = (70, 70, 70)
LINE_RGB = (255, 255, 255)
GOAL_RGB = {"blue": (40, 90, 255), "yellow": (240, 220, 0)}
TEAM_RGB = {TeamColor.BLUE: (0, 190, 230), TeamColor.RED: (230, 25, 165)}
ESTIMATE_RGB = (255, 40, 40)
BALL_RGB = (255, 140, 0)
TEXT_RGB = (235, 235, 235)


def video_name(agent: str) -> str:
    """The file a robot's video is written to, in the match's output directory."""
    return f"video_{agent}.mp4"


@dataclass
class _Video:
    """One robot's video: its writer, opened once :data:`RATE_FRAMES` frames tell the camera rate."""

    path: Path
    writer: Any = None
    first: list[tuple[float, np.ndarray]] = field(default_factory=list)  # (time s, frame) until the writer opens
    frames: int = 0
    frame_ms: list[float] = field(default_factory=list)


class VideoRecorder:
    """Writes the camera videos of ``agents`` into ``out_dir`` (see the module docstring).

    The robots' own pose estimates come with each step (:meth:`observed`), as the runner
    read them. Use as a context manager, or call :meth:`close`: the files are complete only then.
    """

    def __init__(self, out_dir: Path, agents: Sequence[str], camera_model: str = "exact",
                 policies: Mapping[str, str] | None = None):
        self.out_dir = Path(out_dir)
        self.agents = tuple(agents)
        self.policies = dict(policies or {})  # each robot's policy as given, named in its frames
        self.pipeline = VisionPipeline(camera_model)
        self._videos = {agent: _Video(self.out_dir / video_name(agent)) for agent in self.agents}
        self._map = _field_map()

    def __enter__(self) -> VideoRecorder:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    # ---- the observer hooks (match.runner.ObservationWatcher) -------------------------------

    def decided(self, match: Match, actions: Mapping[str, Action | None]) -> None:
        """Nothing: the frames come with :meth:`observed`."""

    def done(self, match: Match) -> bool:
        return False

    def observed(self, match: Match, observations: Mapping[str, Mapping[str, Any]],
                 estimates: Mapping[str, PoseTuple | None]) -> None:
        """A video frame for every recorded robot whose camera gave an image this step."""
        for agent, video in self._videos.items():
            observation = observations.get(agent)
            if observation is None:
                continue
            obs = Observation.of(observation)
            if obs.image is None:
                continue
            started = time.perf_counter()
            frame = self.render(match, agent, obs, estimates.get(agent))
            self._write(video, match.world.time_s, frame)
            video.frame_ms.append((time.perf_counter() - started) * 1000.0)

    # ---- frames --------------------------------------------------------------------------

    def render(self, match: Match, agent: str, obs: Observation, estimate: PoseTuple | None) -> np.ndarray:
        """One video frame (RGB uint8, (120 * SCALE, 320 * SCALE + MAP_WIDTH_PX, 3)) of ``agent``'s camera image."""
        camera = CameraFrame.from_observation(obs)
        result = self.pipeline.process(camera)
        mask = result.segmented == int(ColorClass.ORANGE)
        ball = ball_in_mask(mask, camera.head_yaw_rad, camera.head_pitch_rad, camera.camera)
        overlay = draw_overlay(result, camera.image, SCALE, ball if ball is not None and plausible(ball) else None)
        truth = match.world.robot_truth(agent)
        true_pose = (truth.pose.x, truth.pose.y, truth.pose.theta)
        ball_state = match.world.ball()
        color = match.referee.color_of(AgentId.parse(agent).side)
        panel = self._panel(overlay.shape[0], agent, match, true_pose, TEAM_RGB[color], estimate,
                            (ball_state.x, ball_state.y))
        return np.ascontiguousarray(np.hstack([overlay, panel]))

    def _panel(self, height: int, agent: str, match: Match, truth: PoseTuple, team_rgb: tuple[int, int, int],
               estimate: PoseTuple | None, ball_xy: tuple[float, float]) -> np.ndarray:
        panel = np.zeros((height, MAP_WIDTH_PX, 3), np.uint8)
        field_map, to_px = self._map
        top = HEADER_PX
        panel[top : top + field_map.shape[0], : field_map.shape[1]] = field_map
        view = panel[top : top + field_map.shape[0], : field_map.shape[1]]
        cv2.circle(view, to_px(*ball_xy), 4, BALL_RGB, -1, cv2.LINE_AA)
        _robot(view, to_px, truth, team_rgb, filled=True)
        if estimate is not None:
            cv2.line(view, to_px(truth[0], truth[1]), to_px(estimate[0], estimate[1]), ESTIMATE_RGB, 1, cv2.LINE_AA)
            _robot(view, to_px, estimate, ESTIMATE_RGB, filled=False)
            error_cm = 100.0 * math.hypot(estimate[0] - truth[0], estimate[1] - truth[1])
            error_deg = math.degrees(abs(math.remainder(estimate[2] - truth[2], math.tau)))
            error = f"estimate off {error_cm:.0f} cm, {error_deg:.0f} deg"
        else:
            error = "no estimate"
        policy = self.policies.get(agent)
        who = agent if policy is None else f"{agent} {_cut(policy, POLICY_CHARS)}"
        line1 = f"{who}  {match.world.time_s:7.2f} s  {match.state.name}"
        cv2.putText(panel, line1, (MARGIN_PX, 18), cv2.FONT_HERSHEY_SIMPLEX, 0.5, TEXT_RGB, 1, cv2.LINE_AA)
        cv2.putText(panel, error, (MARGIN_PX, 37), cv2.FONT_HERSHEY_SIMPLEX, 0.5, TEXT_RGB, 1, cv2.LINE_AA)
        return panel

    def _write(self, video: _Video, time_s: float, frame: np.ndarray) -> None:
        if video.writer is not None:
            video.writer.append_data(frame)
            video.frames += 1
            return
        video.first.append((time_s, frame))
        if len(video.first) == RATE_FRAMES:
            self._open(video)

    def _open(self, video: _Video) -> None:
        """Open the writer at the camera rate of the buffered frames and write them."""
        import imageio.v2 as imageio  # loaded only when a video is written

        intervals = [b[0] - a[0] for a, b in zip(video.first, video.first[1:])]
        interval_s = statistics.median(intervals) if intervals else 0.0
        fps = min(MAX_FPS, max(MIN_FPS, 1.0 / interval_s)) if interval_s > 0 else DEFAULT_FPS
        self.out_dir.mkdir(parents=True, exist_ok=True)
        video.writer = imageio.get_writer(video.path, format="FFMPEG", mode="I", fps=round(fps, 3), codec="libx264",
                                          quality=QUALITY, pixelformat="yuv420p", macro_block_size=8,
                                          output_params=["-preset", PRESET])
        for _, frame in video.first:
            video.writer.append_data(frame)
            video.frames += 1
        video.first = []

    # ---- the end -------------------------------------------------------------------------

    @property
    def paths(self) -> tuple[Path, ...]:
        """The videos written (a robot whose camera never gave a frame has none)."""
        return tuple(v.path for v in self._videos.values() if v.frames > 0 or v.first)

    def frame_ms_median(self, agent: str) -> float | None:
        """The median wall time of one video frame of ``agent`` (vision, drawing, encoding), ms."""
        samples = self._videos[agent].frame_ms
        return statistics.median(samples) if samples else None

    def close(self) -> None:
        """Finish every video (one with fewer than :data:`RATE_FRAMES` frames is written now)."""
        for agent, video in self._videos.items():
            if video.first:
                self._open(video)
            if video.writer is not None:
                video.writer.close()
                video.writer = None
                log.info("%s: %d frames, %.1f ms a frame (median: vision, drawing, encoding)", video.path,
                         video.frames, self.frame_ms_median(agent) or 0.0)
            elif video.frames == 0:
                log.warning("no video of %s: its camera never gave a frame", agent)


# ---- the field map ---------------------------------------------------------------------------


def _cut(text: str, chars: int) -> str:
    return text if len(text) <= chars else text[: chars - 1] + "~"


def _field_map():
    """The static field drawing and the field-frame -> pixel mapping of the map panel."""
    width = MAP_WIDTH_PX - 2 * MARGIN_PX
    height = SCALE * 120 - HEADER_PX - MARGIN_PX
    px_per_m = min(width / (2 * FIELD.carpet_half_length), height / (2 * FIELD.carpet_half_width))
    image = np.zeros((height, MAP_WIDTH_PX, 3), np.uint8)
    image[:] = FLOOR_RGB
    cx, cy = MAP_WIDTH_PX / 2.0, height / 2.0

    def to_px(x: float, y: float) -> tuple[int, int]:
        return int(round(cx + x * px_per_m)), int(round(cy - y * px_per_m))

    cv2.rectangle(image, to_px(-FIELD.carpet_half_length, FIELD.carpet_half_width),
                  to_px(FIELD.carpet_half_length, -FIELD.carpet_half_width), CARPET_RGB, -1)
    for segment in FIELD.line_segments:
        cv2.line(image, to_px(segment.x0, segment.y0), to_px(segment.x1, segment.y1), LINE_RGB, 1, cv2.LINE_AA)
    circle = FIELD.center_circle
    cv2.circle(image, to_px(circle.cx, circle.cy), int(round(circle.radius * px_per_m)), LINE_RGB, 1, cv2.LINE_AA)
    for sign, name in ((-1.0, "blue"), (1.0, "yellow")):
        x = sign * FIELD.half_length
        cv2.line(image, to_px(x, FIELD.goal_post_y), to_px(x, -FIELD.goal_post_y), GOAL_RGB[name], 4)
    return image, to_px


def _robot(image: np.ndarray, to_px, pose: PoseTuple, rgb: tuple[int, int, int], filled: bool) -> None:
    x, y, theta = pose
    centre = to_px(x, y)
    tip = to_px(x + 0.25 * math.cos(theta), y + 0.25 * math.sin(theta))
    cv2.circle(image, centre, 7, rgb, -1 if filled else 2, cv2.LINE_AA)
    cv2.line(image, centre, tip, rgb, 2, cv2.LINE_AA)
