"""Goal and goal-post recognition (thesis section 4.4).

The goal-coloured pixels of each goal colour are grouped by column into posts: a column
belongs to a post when its longest vertical run of goal pixels is long (crossbars and the
goal's ground frame are horizontal, so their runs are short), and neighbouring post columns
make one post unless a gap separates them (thesis step 1). A post's base pixel is at the
mean column of its lowest rows and at its lowest row (step 2); two posts give the goal
centre (step 3); a lone
post is told left or right by the crossbar leaving its top to one side, read in the same
frame when the top is in view (step 4; otherwise its side stays unknown and the head scan
tilts the head up to look, see :mod:`agents.vision.head_scan`). Then the thesis' two
sanity checks, and ours (marked so): a post's base must be in the image and on the carpet
(a robot in front hides the real base, and the distance from the lowest visible pixel comes
out metres too long), its width and height must fit its distance, and two posts must stand
1.5 m apart; the width and the pair's gap reject the goal's thin back uprights, which stand
0.5 m behind the posts, the width also its ground frame seen along its side from close by,
and the height a piece of that frame seen between robots' legs.

Ours too: a post's pixels are found with hysteresis. A blurred or noisy camera (the
``robotstadium`` and ``nao`` camera profiles) mixes a post's edge columns with what lies behind
it, and the thresholds label those mixtures white, so the post would come out too thin, or in
broken runs. So a pixel labelled white whose colour lies in its goal colour's range widened by
:data:`RIM_MARGIN_LEVELS` per channel (about half goal colour, half background) counts as a
goal pixel for the post search (:class:`GoalRims`), and a post needs
:data:`RIM_MIN_SEED_PIXELS` pixels of the goal class itself. Under a box blur the columns at
least half goal colour span the post's true width, so the width and base checks hold.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from agents.vision.camera_models import CameraModel
from agents.vision.colors import ColorClass
from agents.vision.frame import CameraFrame
from agents.vision.kernels import goal_mask, post_candidates
from agents.vision.percepts import LandmarkPercept, PostSide
from agents.vision.segmentation import ColorThresholds
from world.camera_model import NAO_CAMERA
from world.field import FIELD, GoalColor, LandmarkId, LandmarkKind

POST_GAP_PX_THESIS = 20  # thesis 4.4 step 1: a gap of 20 px in width splits two posts
POST_GAP_PX = 2  # ours: posts render crisp, so any gap of 2 px or more separates them; at 20 px
# two posts seen obliquely (gap 2-19 px) would merge into one post halfway between them
POST_HEIGHT_DIFFERENCE_PX = 40  # thesis 4.4 check 1: the shorter of two posts is rejected
MAX_POST_DISTANCE_M = math.hypot(FIELD.length, FIELD.width)  # thesis 4.4 check 2: "longer than the field"
MIN_POST_RUN_PX = 5  # ours: a post column has a vertical run of at least this many goal pixels ...
POST_RUN_FRACTION = 0.3  # ... and at least this fraction of the longest run of that goal colour
MIN_POST_WIDTH_FRACTION = 0.8  # ours: a post's core is at least this fraction of a 0.1 m post's
# width at its distance. The goal's back uprights (0.04 m square bars, 0.5 m behind the posts)
# are 0.4-0.57 of it and, a pixel wider on the 160-pixel grid, up to 0.71 within 3.5 m; posts
# are 0.83 or more (docs/results.md, "Goal posts and back uprights")
MAX_POST_WIDTH_FRACTION = 2.5  # ours: ... and at most this multiple of it (plus MAX_POST_WIDTH_SLACK_PX);
MAX_POST_WIDTH_SLACK_PX = 2  # the goal's ground frame seen along its side from close by is a wide band
MIN_POST_HEIGHT_FRACTION = 0.5  # ours: a post whose top is in view is at least this fraction of a
# 0.8 m post's height at its distance (a piece of the ground frame seen between robots' legs is not)
BASE_GROUND_ROWS = 2  # ours: a post's base stands on the carpet: green within this many rows below it
CORE_RUN_FRACTION = 0.5  # ours: a post's core columns have at least half its longest run
CROSSBAR_MIN_PIXELS = 2  # ours: goal pixels beside the post top that show the crossbar's side
BASE_ROWS = 3  # ours: the base column is the mean of the post's lowest rows (posts lean in the image)
GOAL_WIDTH_M = 2 * FIELD.goal_post_y  # 1.5 m between the post centres
GOAL_WIDTH_TOLERANCE_M = 0.4  # ours: two posts farther from 1.5 m apart are not one goal's pair

RIM_MARGIN_LEVELS = 40  # ours: a post's edge pixel may lie this far (per channel, 8-bit) outside its colour's range
RIM_MIN_SEED_PIXELS = 3  # ours: a post holds at least this many pixels of the goal class itself
RIM_REACH_PX = 8  # ours: edge pixels are looked for this far beside the goal-class pixels (a blur's half length)

GOAL_CLASSES = {GoalColor.BLUE: ColorClass.BLUE, GoalColor.YELLOW: ColorClass.YELLOW}
NO_RANGE = (np.zeros(3, np.int16), np.zeros(3, np.int16))  # the widened range of a goal colour without thresholds


@dataclass(frozen=True, eq=False)
class GoalRims:
    """The goal colours' RGB ranges widened by ``margin`` levels per channel (goal -> (low, high), int16):
    the colours of a post's blurred or noisy edge pixels, which the thresholds label white."""

    ranges: dict[GoalColor, tuple[np.ndarray, np.ndarray]]

    @classmethod
    def from_thresholds(cls, thresholds: ColorThresholds, margin: int = RIM_MARGIN_LEVELS) -> GoalRims:
        ranges = {}
        for goal, color in GOAL_CLASSES.items():
            box = thresholds.box(color)
            if box is not None:
                ranges[goal] = (np.array(box.low, np.int16) - margin, np.array(box.high, np.int16) + margin)
        return cls(ranges)

    def goal_pixels(self, labels: np.ndarray, image: np.ndarray, goal: GoalColor) -> np.ndarray:
        """The post search's mask (H, W) of ``goal``: its class's pixels and, within :data:`RIM_REACH_PX`
        columns of their extent, the pixels labelled white whose colour (``image``, RGB uint8) lies in its
        widened range."""
        low, high = self.ranges.get(goal, NO_RANGE)
        return goal_mask(np.ascontiguousarray(labels), np.ascontiguousarray(image), int(GOAL_CLASSES[goal]),
                         int(ColorClass.WHITE), low, high, RIM_REACH_PX, goal in self.ranges)


@dataclass(frozen=True)
class PostBlob:
    """A post candidate: its columns [first, last], rows [top, bottom] and base pixel (u, v).

    ``core_width_px`` counts its columns whose goal run is at least half its longest one;
    ``base_first_column``..``base_last_column`` is the extent of its lowest rows.
    """

    goal: GoalColor
    first_column: int
    last_column: int
    top_row: int
    bottom_row: int
    base_u: float
    core_width_px: int
    base_first_column: int
    base_last_column: int
    rejected: str = ""  # why the post was dropped ("" when kept)

    @property
    def width_px(self) -> int:
        return self.last_column - self.first_column + 1

    @property
    def height_px(self) -> int:
        return self.bottom_row - self.top_row + 1

    @property
    def base_v(self) -> float:
        """The lower edge of the lowest post pixel: where the post meets the ground."""
        return self.bottom_row + 0.5


@dataclass(frozen=True)
class GoalTrace:
    """What goal recognition saw: every post candidate, with the reason of any rejection."""

    posts: tuple[PostBlob, ...] = ()


def find_posts(labels: np.ndarray, goal: GoalColor, goal_pixels: np.ndarray | None = None) -> list[PostBlob]:
    """Post candidates of one goal colour, left to right, before any check: from ``goal_pixels``
    (:meth:`GoalRims.goal_pixels`; default the goal class's pixels), each holding at least
    :data:`RIM_MIN_SEED_PIXELS` pixels of the goal class (:func:`agents.vision.kernels.post_candidates`:
    the columns whose longest vertical run is at least :data:`MIN_POST_RUN_PX` and
    :data:`POST_RUN_FRACTION` of the longest, split at gaps of :data:`POST_GAP_PX`)."""
    labels = np.ascontiguousarray(labels)
    goal_class = int(GOAL_CLASSES[goal])
    mask = labels == goal_class if goal_pixels is None else np.ascontiguousarray(goal_pixels, bool)
    rows = post_candidates(labels, mask, goal_class, MIN_POST_RUN_PX, POST_RUN_FRACTION, POST_GAP_PX,
                           RIM_MIN_SEED_PIXELS, BASE_ROWS, CORE_RUN_FRACTION)
    # The base column: the mean column of the post's pixels in its lowest rows.
    return [PostBlob(goal, first, last, top, bottom, base_sum / base_count, core, base_first, base_last)
            for first, last, top, bottom, base_sum, base_count, core, base_first, base_last in rows.tolist()]


def stands_on_field(labels: np.ndarray, post: PostBlob) -> bool:
    """Whether carpet shows right below the post's base (within :data:`BASE_GROUND_ROWS` rows, in its
    base columns). A post stands on the goal line, which it hides, so from the field the carpet
    meets its base; when a robot stands in front, the post's lowest visible pixel is where the
    robot's body begins, higher in the image, and its distance would come out far too long."""
    below = labels[post.bottom_row + 1 : post.bottom_row + 1 + BASE_GROUND_ROWS,
                   post.base_first_column : post.base_last_column + 1]
    return bool(np.any(below == int(ColorClass.GREEN)))


def crossbar_says_left(labels: np.ndarray, post: PostBlob) -> bool | None:
    """Whether a lone post is its goal's left post, from the crossbar leaving its top.

    Seen from the field, the crossbar runs from the left post to the right one: leaving the
    post's top toward the right of the image, it makes this the left post. None when the
    post's top is cut by the image or no crossbar pixels lie beside it.
    """
    if post.top_row <= 0:
        return None
    goal_class = int(GOAL_CLASSES[post.goal])
    band = slice(post.top_row, min(labels.shape[0], post.top_row + max(2, post.width_px)))
    reach = max(3, 2 * post.width_px)
    left = int(np.count_nonzero(labels[band, max(0, post.first_column - reach) : post.first_column] == goal_class))
    right = int(np.count_nonzero(labels[band, post.last_column + 1 : post.last_column + 1 + reach] == goal_class))
    if max(left, right) < CROSSBAR_MIN_PIXELS or left == right:
        return None
    return right > left


def crossbar_sides(labels: np.ndarray, goal: GoalColor) -> tuple[tuple[float, bool], ...]:
    """(column, is left post) of the posts of ``goal`` whose crossbar shows their side.

    For a frame taken with the head tilted up to find the crossbar (thesis 4.4 step 4): the
    posts' bases need not be in view.
    """
    found = []
    for post in find_posts(labels, goal):
        is_left = crossbar_says_left(labels, post)
        if is_left is not None:
            found.append((post.base_u, is_left))
    return tuple(found)


def _ground_gap_m(a: tuple[PostBlob, float, float], b: tuple[PostBlob, float, float]) -> float:
    """Ground distance between two posts given as (blob, bearing rad, distance m)."""
    (_, ba, da), (_, bb, db) = a, b
    return math.hypot(da * math.cos(ba) - db * math.cos(bb), da * math.sin(ba) - db * math.sin(bb))


def post_id(goal: GoalColor, is_left: bool) -> LandmarkId:
    """The id of a goal's left or right post (as seen from the field)."""
    return LandmarkId[f"{goal.name}_GOAL_{'LEFT' if is_left else 'RIGHT'}_POST"]


def _reject(post: PostBlob, reason: str) -> PostBlob:
    return dataclasses.replace(post, rejected=reason)


def detect_goals(
    labels: np.ndarray, frame: CameraFrame, model: CameraModel, rims: GoalRims | None = None
) -> tuple[tuple[LandmarkPercept, ...], GoalTrace]:
    """Goal posts and goal centres in a segmented frame; with ``rims``, posts' edge pixels read from
    ``frame.image`` (:class:`GoalRims`)."""
    percepts: list[LandmarkPercept] = []
    trace: list[PostBlob] = []
    width = labels.shape[1]
    focal = NAO_CAMERA.focal_px
    radius = FIELD.goal_post_radius
    posts = [post for goal in GoalColor
             for post in find_posts(labels, goal, None if rims is None else rims.goal_pixels(labels, frame.image, goal))]
    if not posts:
        return (), GoalTrace()
    ground = model.locate(frame, np.array([p.base_u for p in posts]), np.array([p.base_v for p in posts]))
    located = list(zip(posts, ground.bearing_rad.tolist(), ground.distance_m.tolist()))  # all bases at once
    for goal in GoalColor:
        kept: list[tuple[PostBlob, float, float]] = []
        for post, bearing, base_distance in located:
            if post.goal is not goal:
                continue
            reason = ""
            distance = base_distance + radius  # the base pixel is the post's front
            pixels_per_m = focal / distance  # a post's width and height in pixels per metre at its distance
            if post.base_first_column == 0 or post.base_last_column == width - 1:
                reason = "base cut by the image side"  # ours: its mean column would be off
            elif post.bottom_row >= labels.shape[0] - 1:
                reason = "base below the image"  # ours: the base is not in view
            elif not math.isfinite(distance) or distance > MAX_POST_DISTANCE_M:
                reason = "farther than the field"  # thesis check 2
            elif post.core_width_px < MIN_POST_WIDTH_FRACTION * FIELD.goal_post_diameter * pixels_per_m:
                reason = "too thin for a post at its distance"  # ours: the goal's back frame
            elif post.core_width_px > MAX_POST_WIDTH_FRACTION * FIELD.goal_post_diameter * pixels_per_m + MAX_POST_WIDTH_SLACK_PX:
                reason = "too wide for a post at its distance"  # ours: the goal's ground frame
            elif post.top_row > 0 and post.height_px < MIN_POST_HEIGHT_FRACTION * FIELD.goal_height * pixels_per_m:
                reason = "too short for a post at its distance"  # ours: a piece of the ground frame
            elif not stands_on_field(labels, post):
                reason = "base hidden: no carpet below it"  # ours: a robot in front of the post
            if reason:
                trace.append(_reject(post, reason))
            else:
                kept.append((post, bearing, distance))
        if len(kept) > 2:
            kept.sort(key=lambda k: -k[0].height_px)
            for post, _, _ in kept[2:]:
                trace.append(_reject(post, "more than two posts: shorter ones dropped"))
            kept = sorted(kept[:2], key=lambda k: k[0].base_u)
        if len(kept) == 2 and abs(kept[0][0].height_px - kept[1][0].height_px) > POST_HEIGHT_DIFFERENCE_PX:
            shorter = 0 if kept[0][0].height_px < kept[1][0].height_px else 1
            trace.append(_reject(kept[shorter][0], "much shorter than the other post"))  # thesis check 1
            kept.pop(shorter)
        if len(kept) == 2 and abs(_ground_gap_m(kept[0], kept[1]) - GOAL_WIDTH_M) > GOAL_WIDTH_TOLERANCE_M:
            farther = 0 if kept[0][2] > kept[1][2] else 1  # the goal's back frame stands behind a post
            trace.append(_reject(kept[farther][0], "not 1.5 m from the other post"))  # ours
            kept.pop(farther)
        for post, _, _ in kept:
            trace.append(post)
        percepts += _goal_percepts(labels, goal, kept, model.name)
    return tuple(percepts), GoalTrace(tuple(trace))


def _goal_percepts(
    labels: np.ndarray, goal: GoalColor, kept: list[tuple[PostBlob, float, float]], model_name: str
) -> list[LandmarkPercept]:
    def post_percept(post: PostBlob, bearing: float, distance: float, side: PostSide, is_left: bool | None):
        return LandmarkPercept(
            LandmarkKind.GOAL_POST,
            (post.base_u, post.base_v),
            bearing,
            distance,
            model_name,
            landmark_id=None if is_left is None else post_id(goal, is_left),
            goal=goal,
            post_side=side,
        )

    if len(kept) == 1:
        post, bearing, distance = kept[0]
        is_left = crossbar_says_left(labels, post)
        side = PostSide.UNKNOWN if is_left is None else PostSide.CROSSBAR
        return [post_percept(post, bearing, distance, side, is_left)]
    if len(kept) != 2:
        return []
    (left, lb, ld), (right, rb, rd) = kept
    found = [post_percept(left, lb, ld, PostSide.PAIR, True), post_percept(right, rb, rd, PostSide.PAIR, False)]
    # Thesis step 3 averages the two base pixels; we average the two ground points, which is
    # where the goal centre is (a pixel average is pulled toward the nearer post by perspective).
    cx = (ld * math.cos(lb) + rd * math.cos(rb)) / 2.0
    cy = (ld * math.sin(lb) + rd * math.sin(rb)) / 2.0
    found.append(
        LandmarkPercept(
            LandmarkKind.GOAL_CENTER,
            ((left.base_u + right.base_u) / 2.0, (left.base_v + right.base_v) / 2.0),
            math.atan2(cy, cx),
            math.hypot(cx, cy),
            model_name,
            landmark_id=LandmarkId[f"{goal.name}_GOAL_CENTER"],
            goal=goal,
        )
    )
    return found
