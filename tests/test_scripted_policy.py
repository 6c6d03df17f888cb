"""The scripted policy and its ball finder, on synthetic observations (no simulator)."""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest

from agents.vision.ball import find_ball
from agents.behavior.policies.scripted import LONE_SILENCE_STEPS, ScriptedPlayer, decode_reports
from agents.observation import RadioPacket
from agents.radio import Intention, Role, TeamMessage, decode
from match.protocol import (
    MOTIONS,
    NO_MOTION,
    CameraChoice,
    GameState,
    Motion,
    action_space,
    observation_space,
    packet_of,
    parse_action,
)
from world.camera_model import NAO_CAMERA, NAO_HEAD, CameraPosition, world_to_camera
from world.field import FIELD

CARPET_RGB = (38, 128, 45)
BALL_RGB = (230, 126, 0)  # orange, shaded
SUBPIXEL_SHIFT = 4


def green_image() -> np.ndarray:
    return np.broadcast_to(np.asarray(CARPET_RGB, np.uint8), (120, 160, 3)).copy()


def ball_image(forward_m: float, left_m: float, yaw: float, pitch: float, camera: CameraPosition) -> tuple[np.ndarray, np.ndarray]:
    """A green image with the ball (torso frame position) drawn as a disc; also its projected pixel."""
    rotation, position = NAO_HEAD.camera_in_torso(yaw, pitch, camera)
    centre = world_to_camera(np.array([[forward_m, left_m, FIELD.ball_radius]]), rotation, position)[0]
    pixel = NAO_CAMERA.project(centre[None])[0]
    radius_px = NAO_CAMERA.focal_px * FIELD.ball_radius / centre[2]
    image = green_image()
    scale = 1 << SUBPIXEL_SHIFT
    cv2.circle(image, tuple(int(round(c * scale)) for c in pixel), int(round(radius_px * scale)), BALL_RGB, -1, cv2.LINE_8, SUBPIXEL_SHIFT)
    return image, pixel


def make_obs(
    *,
    state: GameState = GameState.PLAYING,
    player: int = 1,
    defended_goal: int = 0,
    camera: CameraChoice = CameraChoice.OFF,
    image: np.ndarray | None = None,
    head: tuple[float, float] = (0.0, 0.3),
    seed: int = 0,
) -> dict:
    space = observation_space()
    space.seed(seed)
    obs = space.sample()
    obs.update(
        image=green_image() if image is None else image,
        head=np.asarray(head, np.float32),
        camera=int(camera),
        accelerometer=np.asarray((0.0, 0.0, 9.81), np.float32),
        gyro=np.zeros(3, np.float32),
        fallen=0,
        motion=NO_MOTION,
    )
    obs["game"].update(state=int(state), player=player, defended_goal=defended_goal)
    obs["radio"].update(count=0)
    return obs


def scripted(agent: str) -> ScriptedPlayer:
    """A scripted player reset to play ``agent``."""
    player = ScriptedPlayer()
    player.reset(agent, 0)
    return player


def motion_of(action: dict) -> Motion:
    return MOTIONS[int(action["motion"])]


# ---- ball finder ------------------------------------------------------------------------


@pytest.mark.parametrize("forward_m, left_m", [(1.5, 0.3), (1.0, -0.2), (2.5, 0.0)])
def test_finder_locates_a_disc(forward_m: float, left_m: float) -> None:
    pitch = 0.35
    image, pixel = ball_image(forward_m, left_m, 0.0, pitch, CameraPosition.TOP)
    ball = find_ball(image, 0.0, pitch, CameraPosition.TOP)
    assert ball is not None
    assert ball.pixel_u == pytest.approx(pixel[0], abs=0.75)
    assert ball.pixel_v == pytest.approx(pixel[1], abs=0.75)
    assert ball.distance_m == pytest.approx(math.hypot(forward_m, left_m), rel=0.1)
    assert ball.bearing_rad == pytest.approx(math.atan2(left_m, forward_m), abs=0.03)


def test_finder_bearing_sign_left_of_centre_is_positive() -> None:
    pitch = 0.4
    image = green_image()
    cv2.circle(image, (40, 70), 4, BALL_RGB, -1)
    left = find_ball(image, 0.0, pitch, CameraPosition.TOP)
    assert left is not None and (left.pixel_u, left.pixel_v) == pytest.approx((40.0, 70.0), abs=0.5)
    assert left.bearing_rad > 0.0
    assert 0.5 < left.distance_m < 2.5
    image = green_image()
    cv2.circle(image, (120, 70), 4, BALL_RGB, -1)
    right = find_ball(image, 0.0, pitch, CameraPosition.TOP)
    assert right is not None and right.bearing_rad < 0.0


def test_finder_ignores_plain_field_and_goal_colours() -> None:
    assert find_ball(green_image(), 0.0, 0.3, CameraPosition.TOP) is None
    image = green_image()
    image[20:60, 30:36] = (242, 217, 25)  # yellow post
    image[20:60, 90:96] = (25, 64, 242)  # blue post
    image[70:75, 60:80] = (217, 25, 25)  # red waistband
    image[90:95, :] = (245, 245, 245)  # white line
    assert find_ball(image, 0.0, 0.3, CameraPosition.TOP) is None


def test_finder_uses_the_bottom_camera_geometry() -> None:
    pitch = 0.45
    image, _ = ball_image(0.15, -0.04, 0.0, pitch, CameraPosition.BOTTOM)
    ball = find_ball(image, 0.0, pitch, CameraPosition.BOTTOM)
    assert ball is not None
    assert ball.distance_m == pytest.approx(math.hypot(0.15, 0.04), abs=0.02)
    assert ball.bearing_rad < 0.0


# ---- scripted player --------------------------------------------------------------------


def test_every_action_is_valid() -> None:
    space = action_space()
    observations = observation_space()
    observations.seed(1)
    player = scripted("home_1")
    for step in range(40):
        obs = observations.sample()
        if step % 3 == 0:
            obs["game"]["state"] = int(GameState.PLAYING)
            obs["fallen"] = 0
        action = player.act(obs)
        assert isinstance(action["radio"], bytes)  # make_action keeps a packet as bytes, which the env accepts
        assert space.contains({**action, "radio": packet_of(action["radio"])}), action
        parse_action("home_1", action)


def test_fallen_on_back_stands_up_from_back_until_it_ends() -> None:
    player = scripted("home_2")
    obs = make_obs()
    obs.update(fallen=1, accelerometer=np.asarray((9.81, 0.0, 0.3), np.float32))
    assert motion_of(player.act(obs)) is Motion.STAND_UP_FROM_BACK
    obs.update(fallen=0, accelerometer=np.asarray((0.0, 0.0, 9.81), np.float32))
    obs["motion"] = MOTIONS.index(Motion.STAND_UP_FROM_BACK)
    assert motion_of(player.act(obs)) is Motion.STAND_UP_FROM_BACK


def test_fallen_on_front_stands_up_from_front() -> None:
    obs = make_obs()
    obs.update(fallen=1, accelerometer=np.asarray((-9.81, 0.0, 0.3), np.float32))
    assert motion_of(scripted("home_2").act(obs)) is Motion.STAND_UP_FROM_FRONT


@pytest.mark.parametrize("state", [GameState.INITIAL, GameState.READY, GameState.SET, GameState.FINISHED])
def test_stands_when_not_playing(state: GameState) -> None:
    assert motion_of(scripted("away_3").act(make_obs(state=state))) is Motion.STAND


def test_camera_is_off_on_alternate_steps() -> None:
    player = scripted("home_1")
    cameras = [CameraChoice(player.act(make_obs())["camera"]) for _ in range(6)]
    assert cameras[1::2] == [CameraChoice.OFF] * 3
    assert all(c is not CameraChoice.OFF for c in cameras[0::2])


def _ball_obs(forward_m: float, left_m: float, *, defended_goal: int = 0, player: int = 1, pitch: float = 0.45,
              camera: CameraChoice = CameraChoice.BOTTOM, yaw: float = 0.0) -> dict:
    position = CameraPosition.BOTTOM if camera is CameraChoice.BOTTOM else CameraPosition.TOP
    image, _ = ball_image(forward_m, left_m, yaw, pitch, position)
    return make_obs(camera=camera, image=image, head=(yaw, pitch), defended_goal=defended_goal, player=player)


def _after_set(player: ScriptedPlayer, defended_goal: int) -> None:
    """One SET step: the heading estimate is the kick-off heading (facing the attacked goal)."""
    player.act(make_obs(state=GameState.SET, defended_goal=defended_goal))


@pytest.mark.parametrize("defended_goal", [0, 1])
@pytest.mark.parametrize("left_m, kick", [(-0.04, Motion.KICK_RIGHT), (0.04, Motion.KICK_LEFT)])
def test_kicks_a_close_ball_toward_the_attacked_goal(defended_goal: int, left_m: float, kick: Motion) -> None:
    player = scripted("home_1")
    _after_set(player, defended_goal)
    assert motion_of(player.act(_ball_obs(0.14, left_m, defended_goal=defended_goal))) is kick
    obs = make_obs(defended_goal=defended_goal)
    obs["motion"] = MOTIONS.index(kick)
    assert motion_of(player.act(obs)) is kick  # a playing kick is continued


def test_does_not_kick_toward_its_own_goal() -> None:
    player = scripted("home_1")
    _after_set(player, 0)
    obs = _ball_obs(0.14, -0.02)
    obs["gyro"] = np.asarray((0.0, 0.0, math.pi / 0.04), np.float32)  # turned around in one step
    action = player.act(obs)
    assert motion_of(action) is Motion.WALK
    vx, vy, omega = action["walk"]
    assert vy * omega < 0.0  # sideways around the ball


def test_walks_to_a_far_ball_and_turns_to_a_side_ball() -> None:
    player = scripted("home_1")
    action = player.act(_ball_obs(1.5, 0.1, pitch=0.3, camera=CameraChoice.TOP))
    assert motion_of(action) is Motion.WALK and action["walk"][0] > 0.0 and action["walk"][2] > 0.0
    action = scripted("home_1").act(_ball_obs(1.0, -0.6, pitch=0.3, camera=CameraChoice.TOP, yaw=-0.5))
    assert motion_of(action) is Motion.WALK and action["walk"][0] == 0.0 and action["walk"][2] < 0.0


def test_holds_position_when_a_teammate_is_nearer() -> None:
    obs = _ball_obs(1.5, 0.0, pitch=0.3, camera=CameraChoice.TOP)
    packet = TeamMessage(2, ball_relative=(0.4, 0.1)).encode()
    radio = obs["radio"]
    radio["count"] = 1
    radio["sender"][0] = 2
    radio["length"][0] = len(packet)
    radio["data"][0, : len(packet)] = np.frombuffer(packet, np.uint8)
    assert motion_of(scripted("home_1").act(obs)) is Motion.STAND


def test_sends_its_ball_estimate_every_fifth_step() -> None:
    player = scripted("home_3")
    obs = _ball_obs(1.5, 0.0, player=3, pitch=0.3, camera=CameraChoice.TOP)
    packets = [player.act(obs)["radio"] for _ in range(6)]
    assert [bool(p) for p in packets] == [True, False, False, False, False, True]
    report = decode(packets[0])
    distance, bearing = report.ball_relative
    assert report.player == 3 and distance == pytest.approx(1.5, rel=0.1) and abs(bearing) < 0.05
    assert report.pose is None and report.ball_xy is None  # no pose: its ball from itself only


def test_goalkeeper_side_steps_without_walking_forward() -> None:
    keeper = scripted("home_0")
    action = keeper.act(_ball_obs(1.5, 0.5, player=0, pitch=0.3, camera=CameraChoice.TOP))
    assert motion_of(action) is Motion.WALK
    vx, vy, _ = action["walk"]
    assert vx == 0.0 and vy > 0.0
    assert motion_of(scripted("home_0").act(_ball_obs(0.14, 0.03, player=0))) is Motion.KICK_LEFT


@pytest.mark.parametrize("teammate_talks, chases", [(False, True), (True, False)])
def test_a_goalkeeper_that_hears_no_teammate_chases_the_ball(teammate_talks: bool, chases: bool) -> None:
    """A team of one: after 4 s without a teammate's report the keeper walks to a far ball ahead, which
    a keeper on its line never does; one that hears a teammate keeps its line."""
    keeper = scripted("home_0")
    packet = TeamMessage(1, ball_relative=(2.0, 0.0)).encode()
    actions = []
    for step in range(LONE_SILENCE_STEPS + 5):
        obs = _ball_obs(1.5, 0.0, player=0, pitch=0.3, camera=CameraChoice.TOP)
        if teammate_talks and step % 5 == 0:
            radio = obs["radio"]
            radio["count"], radio["sender"][0], radio["length"][0] = 1, 1, len(packet)
            radio["data"][0, : len(packet)] = np.frombuffer(packet, np.uint8)
        actions.append(keeper.act(obs))
    assert all(float(a["walk"][0]) == 0.0 for a in actions[: LONE_SILENCE_STEPS - 5])  # on its line, not yet alone
    last = actions[-1]
    assert (motion_of(last) is Motion.WALK and float(last["walk"][0]) > 0.0) is chases


def test_scans_and_then_turns_when_the_ball_is_unknown() -> None:
    player = scripted("home_2")
    obs = make_obs()
    actions = [player.act(obs) for _ in range(150)]
    yaws = [float(a["head"][0]) for a in actions]
    assert max(yaws) > math.radians(90) and min(yaws) < -math.radians(90)
    sweeping = [a for a in actions if motion_of(a) is Motion.STAND]
    # far sweeps with the top camera at pitch 0.3 alternate with near sweeps with the bottom one
    views = {(CameraChoice(a["camera"]), round(float(a["head"][1]), 2)) for a in sweeping}
    assert {(CameraChoice.TOP, 0.3), (CameraChoice.BOTTOM, 0.45)} <= views
    assert views <= {(CameraChoice.TOP, 0.3), (CameraChoice.BOTTOM, 0.45), (CameraChoice.OFF, 0.3), (CameraChoice.OFF, 0.45)}
    first_turn = next(i for i, a in enumerate(actions) if motion_of(a) is Motion.WALK)
    assert first_turn > 50  # only after a full sweep
    assert actions[first_turn]["walk"][2] != 0.0 and actions[first_turn]["walk"][0] == 0.0


def test_one_radio_format_for_the_scripted_and_the_team_players() -> None:
    """A team agent's report, which has no ball seen from the sender, is a teammate heard without a ball;
    a scripted report reads as a team message without pose or play."""
    team = TeamMessage(1, 4, (0.0, 1.0, 0.0), role=Role.STRIKER, intention=Intention.KICK, time_to_ball_s=1.0)
    scripted_report = TeamMessage(2, ball_relative=(0.8, -0.2)).encode()
    reports = decode_reports((RadioPacket(1, team.encode()), RadioPacket(2, scripted_report), RadioPacket(3, b"xyz")), 0)
    assert [(r.player, r.ball_distance_m) for r in reports] == [(1, -1.0), (2, pytest.approx(0.8))]
    heard = decode(scripted_report)
    assert heard.pose is None and heard.role == Role.NONE and heard.time_to_ball_s == math.inf

