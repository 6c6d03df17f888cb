"""Goal posts in blurred images: the post search takes a post's edge pixels (half goal colour, half
background, labelled white by the thresholds) from the goal colour's widened range, and needs pixels of
the goal class itself.

The scenes are drawn in RGB and blurred as the camera profiles blur (a box along the image motion over
the exposure), then segmented by the shipped thresholds.
"""

from __future__ import annotations

import numpy as np
import pytest

from agents.vision.camera_models import camera_model
from agents.vision.colors import ColorClass
from agents.vision.frame import CameraFrame
from agents.vision.goals import RIM_MIN_SEED_PIXELS, GoalRims, detect_goals, find_posts
from agents.vision.head_scan import SCAN_PITCH_RAD
from agents.vision.pipeline import VisionPipeline
from world.camera_model import NAO_CAMERA
from world.field import FIELD, GoalColor, LandmarkKind

HALL_RGB = (50, 55, 70)  # the dark hall wall behind a goal
CARPET_RGB = (35, 120, 40)
YELLOW_RGB = (200, 175, 20)
HORIZON_ROW = 20
COLUMN = 80


@pytest.fixture(scope="module")
def pipeline() -> VisionPipeline:
    return VisionPipeline("exact")


def _base_row_at(distance_m: float) -> int:
    """The image row of a post base about ``distance_m`` away, the head at the scan pitch."""
    model = camera_model("exact")
    frame = CameraFrame(np.zeros((120, 160, 3), np.uint8), 0.0, SCAN_PITCH_RAD)
    rows = np.arange(HORIZON_ROW + 5, 119)
    found = model.locate(frame, np.full(rows.shape, float(COLUMN)), rows + 0.5).distance_m
    return int(rows[np.argmin(np.abs(found - distance_m))])


def _post_image(distance_m: float, blur_px: int) -> tuple[np.ndarray, int]:
    """A yellow post on the carpet before the hall, blurred along the rows by ``blur_px`` (a box):
    (image, the post's width in pixels)."""
    base = _base_row_at(distance_m)
    width = round(FIELD.goal_post_diameter / distance_m * NAO_CAMERA.focal_px)
    height = round(FIELD.goal_height / distance_m * NAO_CAMERA.focal_px)
    image = np.empty((120, 160, 3), np.float64)
    image[:] = CARPET_RGB
    image[: base - 3] = HALL_RGB  # the hall meets the carpet a little behind the post's base
    left = COLUMN - width // 2
    image[max(0, base - height + 1) : base + 1, left : left + width] = YELLOW_RGB
    if blur_px > 1:
        kernel = np.ones(blur_px) / blur_px
        for channel in range(3):
            image[:, :, channel] = np.apply_along_axis(np.convolve, 1, image[:, :, channel], kernel, mode="same")
    return np.rint(image).astype(np.uint8), width


def _posts(pipeline: VisionPipeline, image: np.ndarray, rims: bool):
    frame = CameraFrame(image, 0.0, SCAN_PITCH_RAD)
    labels = pipeline.table.segment(image)
    return detect_goals(labels, frame, pipeline.model, pipeline.rims if rims else None)


@pytest.mark.parametrize("distance_m", [3.0, 3.5, 4.0])
def test_a_post_blurred_by_a_turning_head_is_found_at_its_distance(pipeline: VisionPipeline, distance_m: float):
    """A blur of 5 px (a head turning at about 1.3 rad/s over a 20 ms exposure) leaves a post of 5-6 px
    too few columns of pure goal colour; with its edge pixels the post keeps its width and is found."""
    image, width = _post_image(distance_m, blur_px=5)
    percepts, trace = _posts(pipeline, image, rims=False)
    assert not any(p.kind is LandmarkKind.GOAL_POST for p in percepts)  # the thresholds alone lose it
    percepts, trace = _posts(pipeline, image, rims=True)
    (post,) = [p for p in percepts if p.kind is LandmarkKind.GOAL_POST]
    assert abs(post.distance_m - distance_m) < 0.1 * distance_m
    (blob,) = [b for b in trace.posts if not b.rejected]
    # the columns of at least a third to a half goal colour (the widened range's edge against the hall and
    # the carpet): the true width and up to two pixels of the blur
    assert width <= blob.core_width_px <= width + 2


def test_a_sharp_post_is_found_alike_with_and_without_rims(pipeline: VisionPipeline):
    image, _ = _post_image(3.0, blur_px=1)
    sharp, _ = _posts(pipeline, image, rims=False)
    with_rims, _ = _posts(pipeline, image, rims=True)
    assert [p.kind for p in sharp] == [LandmarkKind.GOAL_POST] and with_rims == sharp


def test_edge_coloured_pixels_without_goal_pixels_make_no_post(pipeline: VisionPipeline):
    """A column of mixtures (half yellow, half hall) with fewer than RIM_MIN_SEED_PIXELS of yellow itself is
    no post: the widened range alone finds nothing."""
    image = np.empty((120, 160, 3), np.uint8)
    image[:] = CARPET_RGB
    image[:60] = HALL_RGB
    mixture = (np.array(YELLOW_RGB) + np.array(HALL_RGB)) // 2
    image[20:60, 78:84] = mixture
    labels = pipeline.table.segment(image)
    assert not np.any(labels == int(ColorClass.YELLOW))
    image[30 : 30 + RIM_MIN_SEED_PIXELS - 1, 80] = YELLOW_RGB  # too few seeds (and isolated: cleaned away)
    labels = pipeline.table.segment(image)
    rims = pipeline.rims.goal_pixels(labels, image, GoalColor.YELLOW)
    assert find_posts(labels, GoalColor.YELLOW, rims) == []


def test_rims_widen_only_the_goal_colours_and_only_pixels_labelled_white(pipeline: VisionPipeline):
    thresholds = pipeline.table.thresholds
    rims = GoalRims.from_thresholds(thresholds, margin=10)
    low, high = rims.ranges[GoalColor.YELLOW]
    box = thresholds.box(ColorClass.YELLOW)
    assert low.tolist() == [v - 10 for v in box.low] and high.tolist() == [v + 10 for v in box.high]
    image = np.empty((120, 160, 3), np.uint8)
    image[:] = YELLOW_RGB
    labels = np.full((120, 160), int(ColorClass.GREEN), np.uint8)
    labels[50:60, 70:80] = int(ColorClass.YELLOW)
    mask = rims.goal_pixels(labels, image, GoalColor.YELLOW)
    assert np.array_equal(mask, labels == int(ColorClass.YELLOW))  # green-labelled pixels stay out
    labels[50:60, 80:82] = int(ColorClass.WHITE)
    labels[50:60, 100:102] = int(ColorClass.WHITE)  # beyond the reach beside the goal pixels
    mask = rims.goal_pixels(labels, image, GoalColor.YELLOW)
    assert mask[50:60, 80:82].all() and not mask[50:60, 100:102].any()
