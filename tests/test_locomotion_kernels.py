"""The locomotion controller's compiled arithmetic (:mod:`world.locomotion_kernels`) against the Python it
replaced, kept here as the reference: the same bits on random inputs, and a pinned run of eight robots
walking, kicking, standing, falling and standing up."""

from __future__ import annotations

import hashlib
import math
import struct
import sys

import numpy as np
import pybullet as pb
import pytest

from world import gaits
from world import locomotion_kernels as kernels
from world.compile import compile_locomotion
from world.config import RobotSpec
from world.field import Pose2D, normalize_angle
from world.locomotion import HEAD_SPEED_RADPS, BalanceConfig, control_gains
from world.motions import Motion
from world.robot_model import ACTUATED_JOINTS, TOTAL_MASS_KG, Joint
from world.teams import TeamColor
from world.world import World

# ---- the reference: the controller's Python before it was compiled ------------------------------------


def _lift(side: str, amount: float) -> dict[Joint, float]:
    hip, knee, ankle = (Joint[f"{side}_HIP"], Joint[f"{side}_KNEE"], Joint[f"{side}_ANKLE"])
    return {hip: -amount, knee: 2 * amount, ankle: -amount}


def walking_targets(t_s: float) -> dict[Joint, float]:
    targets = dict(gaits.STANDING)
    phase = (t_s % gaits.STEP_PERIOD_S) / gaits.STEP_PERIOD_S
    side = "L" if phase < 0.5 else "R"
    amount = gaits.STEP_LIFT_RAD * math.sin(math.pi * ((phase * 2) % 1.0))
    targets.update(_lift(side, amount))
    swing = 0.25 * math.sin(2 * math.pi * phase)
    targets[Joint.L_SHOULDER] = 0.15 + swing
    targets[Joint.R_SHOULDER] = 0.15 - swing
    return targets


def _interpolate(keys, t_s: float) -> tuple[float, ...]:
    if t_s <= keys[0][0]:
        return keys[0][1:]
    for (t0, *a), (t1, *b) in zip(keys, keys[1:]):
        if t_s <= t1:
            w = (t_s - t0) / (t1 - t0)
            return tuple(x + w * (y - x) for x, y in zip(a, b))
    return keys[-1][1:]


def kick_targets(motion: Motion, t_s: float) -> dict[Joint, float]:
    side = "L" if motion is Motion.KICK_LEFT else "R"
    hip, knee, ankle = _interpolate(gaits.KICK_KEYS, t_s)
    targets = dict(gaits.STANDING)
    targets.update({Joint[f"{side}_HIP"]: hip, Joint[f"{side}_KNEE"]: knee, Joint[f"{side}_ANKLE"]: ankle})
    arm = Joint.R_SHOULDER if side == "L" else Joint.L_SHOULDER
    targets[arm] = 0.15 - 0.6 * (hip - 0.0)
    return targets


def stand_up_targets(t_s: float, duration_s: float) -> dict[Joint, float]:
    s = min(max(t_s / duration_s, 0.0), 1.0)
    tuck = math.sin(math.pi * s)
    targets = dict(gaits.STANDING)
    for side in ("L", "R"):
        targets[Joint[f"{side}_SHOULDER"]] = 0.15 - 1.2 * tuck
        targets[Joint[f"{side}_HIP"]] = -0.8 * tuck
        targets[Joint[f"{side}_KNEE"]] = 1.4 * tuck
        targets[Joint[f"{side}_ANKLE"]] = -0.6 * tuck
    return targets


def reference_targets(mode: int, t_s: float, duration_s: float) -> dict[Joint, float]:
    if mode == kernels.WALKING:
        return walking_targets(t_s)
    if mode in (kernels.KICK_LEFT, kernels.KICK_RIGHT):
        return kick_targets(Motion.KICK_LEFT if mode == kernels.KICK_LEFT else Motion.KICK_RIGHT, t_s)
    if mode == kernels.STAND_UP:
        return stand_up_targets(t_s, duration_s)
    return gaits.STANDING


def reference_drive(targets, head_goals, limb_step, head_step, setpoints: dict) -> tuple[bool, bool]:
    changed, reached = False, True
    for joint in ACTUATED_JOINTS:
        head = {Joint.HEAD_YAW: 0, Joint.HEAD_PITCH: 1}.get(joint)
        goal, step = (targets.get(joint, 0.0), limb_step) if head is None else (head_goals[head], head_step)
        before = setpoints.get(joint)
        current = goal if before is None else before
        if current != goal:
            current = goal if abs(goal - current) <= step else current + math.copysign(step, goal - current)
        if before != current:
            setpoints[joint] = current
            changed = True
        reached = reached and current == goal
    return changed, reached


def _split(value: float) -> tuple[float, float]:
    """Dekker's split of ``value`` into a high part of 26 bits and the rest (exact)."""
    t = value * 134217729.0
    hi = t - (t - value)
    return hi, value - hi


def reference_hypot(x: float, y: float) -> float:
    """CPython 3.11's ``math.hypot`` of two finite coordinates, not subnormal-small: ``vector_norm`` in
    Python floats (exact squares, compensated sums, one correction of the square root)."""
    a, b = abs(x), abs(y)
    if max(a, b) == 0.0:
        return 0.0
    scale = math.ldexp(1.0, -math.frexp(max(a, b))[1])
    csum, fractions = 1.0, [0.0, 0.0, 0.0]

    def add(term: float, which: int) -> None:
        nonlocal csum
        old = csum
        csum += term
        fractions[which] += (old - csum) + term

    for value in (a, b):
        hi, lo = _split(value * scale)
        add(hi * hi, 0)
        add(2.0 * hi * lo, 1)
        fractions[2] += lo * lo
    h = math.sqrt(csum - 1.0 + (fractions[0] + fractions[1] + fractions[2]))
    hi, lo = _split(h)
    add(-hi * hi, 0)
    add(-2.0 * hi * lo, 1)
    add(-lo * lo, 2)
    return (h + (csum - 1.0 + (fractions[0] + fractions[1] + fractions[2])) / (2.0 * h)) / scale


def reference_control(cfg: BalanceConfig, px, py, linear, angular, heading, m, velocity, dt_s, ref):
    """``_track`` then ``_balance``: (fx, fy, tx, ty, tz, ref); ``math.hypot`` as CPython 3.11 computes it."""
    hypot = math.hypot if sys.version_info[:2] == (3, 11) else reference_hypot
    vx, vy, omega = velocity
    ref = list(ref)
    c, s = math.cos(ref[2]), math.sin(ref[2])
    vwx, vwy = c * vx - s * vy, s * vx + c * vy
    ref[0] += vwx * dt_s
    ref[1] += vwy * dt_s
    ref[2] = normalize_angle(ref[2] + omega * dt_s)
    ex, ey = ref[0] - px, ref[1] - py
    if hypot(ex, ey) > cfg.reanchor_position_m:
        ref[0], ref[1], ex, ey = px, py, 0.0, 0.0
    eh = normalize_angle(ref[2] - heading)
    if abs(eh) > cfg.reanchor_heading_rad:
        ref[2], eh = heading, 0.0
    gain = TOTAL_MASS_KG / cfg.drive_time_constant_s
    fx = gain * (vwx + cfg.position_gain_per_s * ex - linear[0])
    fy = gain * (vwy + cfg.position_gain_per_s * ey - linear[1])
    norm = hypot(fx, fy)
    if norm > cfg.drive_force_max_n:
        fx, fy = fx * cfg.drive_force_max_n / norm, fy * cfg.drive_force_max_n / norm
    tz = cfg.yaw_inertia_kgm2 / cfg.drive_time_constant_s * (omega + cfg.heading_gain_per_s * eh - angular[2])
    tz = max(-cfg.yaw_torque_max_nm, min(cfg.yaw_torque_max_nm, tz))
    zx, zy, zz = m[2], m[5], m[8]
    sin_tilt = hypot(zx, zy)
    tilt = math.atan2(sin_tilt, zz)
    ax, ay = (zy / sin_tilt, -zx / sin_tilt) if sin_tilt > 1e-9 else (0.0, 0.0)
    tx = cfg.upright_kp * tilt * ax - cfg.upright_kd * angular[0]
    ty = cfg.upright_kp * tilt * ay - cfg.upright_kd * angular[1]
    norm = hypot(tx, ty)
    if norm > cfg.upright_torque_max_nm:
        tx, ty = tx * cfg.upright_torque_max_nm / norm, ty * cfg.upright_torque_max_nm / norm
    return fx, fy, tx, ty, tz, tuple(ref)


# ---- the kernels against it ---------------------------------------------------------------------------


def _bits(values) -> bytes:
    return np.asarray(values, np.float64).tobytes()


def test_py_hypot_is_cpython_311s_hypot_to_the_bit():
    """The kernel's hypot is CPython 3.11's: against a port of it, and against ``math.hypot`` on 3.11 (later
    versions compute it another way)."""
    rng = np.random.default_rng(0)
    pairs = []
    for scale in (1e-300, 1e-9, 1e-3, 1.0, 50.0, 1e200):
        x = rng.normal(0.0, scale, 20_000)
        y = rng.normal(0.0, scale, 20_000) * rng.choice([1.0, 1e-3, 1e-9], 20_000)
        pairs += list(zip(x.tolist(), y.tolist()))
    pairs += [(0.0, 0.0), (-0.0, 0.0), (3.0, 4.0), (5e-324, 5e-324), (2.2250738585072014e-308, 1e-310),
              (1e308, 1e308), (math.inf, math.nan), (math.nan, 1.0), (-math.inf, 2.0)]
    got = [kernels.py_hypot(x, y) for x, y in pairs]
    ported = [(k, reference_hypot(x, y)) for k, (x, y) in enumerate(pairs)
              if math.isfinite(x) and math.isfinite(y) and max(abs(x), abs(y)) > 1e-300]
    assert _bits([got[k] for k, _ in ported]) == _bits([value for _, value in ported])
    if sys.version_info[:2] == (3, 11):
        assert _bits(got) == _bits([math.hypot(x, y) for x, y in pairs])


def test_normalize_angle_is_the_fields_to_the_bit():
    rng = np.random.default_rng(1)
    angles = np.concatenate([rng.uniform(-7.0, 7.0, 50_000), rng.uniform(-300.0, 300.0, 20_000),
                             [0.0, -0.0, math.pi, -math.pi, 2 * math.pi, -2 * math.pi, 1e300]]).tolist()
    assert _bits([kernels.normalize_angle(a) for a in angles]) == _bits([normalize_angle(a) for a in angles])


@pytest.mark.parametrize("mode", [kernels.STANDING, kernels.WALKING, kernels.KICK_LEFT, kernels.KICK_RIGHT,
                                  kernels.STAND_UP])
def test_joint_targets_are_the_gaits_to_the_bit(mode):
    rng = np.random.default_rng(mode)
    times = np.concatenate([rng.uniform(-0.1, 3.0, 2000), [k[0] for k in gaits.KICK_KEYS], [0.25, 0.5, 1.0]])
    out = np.full(kernels.SLOTS, np.nan)
    for t in times.tolist():
        kernels.joint_targets(mode, t, 2.5, out)
        targets = reference_targets(mode, t, 2.5)
        assert _bits(out[2:]) == _bits([targets.get(joint, 0.0) for joint in ACTUATED_JOINTS[2:]])


def test_drive_joints_moves_the_setpoints_as_the_controller_did():
    rng = np.random.default_rng(2)
    for trial in range(3000):
        mode = int(rng.integers(0, 5))
        t, duration = float(rng.uniform(0.0, 3.0)), 2.5
        head_goals = tuple(rng.uniform(-1.0, 1.0, 2).tolist())
        limb_step, head_step = float(rng.choice([0.0, 0.03125, 0.1])), HEAD_SPEED_RADPS * 0.008
        known = trial % 7 != 0
        start = rng.uniform(-1.0, 1.0, kernels.SLOTS)
        if trial % 5 == 1:  # standing legs exactly one step from their goal (0): the last step reaches it
            mode = kernels.STANDING
            start[4:] = rng.choice([-limb_step, limb_step], kernels.SLOTS - 4)
        if trial % 5 == 0:  # some setpoints already at their goals
            goals = np.array([reference_targets(mode, t, duration).get(j, 0.0) for j in ACTUATED_JOINTS])
            goals[:2] = head_goals
            start[::2] = goals[::2]
        reference = dict(zip(ACTUATED_JOINTS, start.tolist())) if known else {}
        expected = reference_drive(reference_targets(mode, t, duration), head_goals, limb_step, head_step, reference)
        setpoints = start.copy()
        got = kernels.drive_joints(mode, t, duration, *head_goals, limb_step, head_step, setpoints, known)
        assert got == expected
        assert _bits(setpoints) == _bits([reference[j] for j in ACTUATED_JOINTS])


def test_control_is_track_and_balance_to_the_bit():
    cfg = BalanceConfig()
    gains = control_gains(cfg)
    rng = np.random.default_rng(3)
    for trial in range(5000):
        px, py = rng.uniform(-4.0, 4.0, 2).tolist()
        spread = [0.001, 0.04, 0.3][trial % 3]  # within and beyond the re-anchoring limits
        ref = (px + rng.normal(0.0, spread), py + rng.normal(0.0, spread), float(rng.uniform(-math.pi, math.pi)))
        heading = normalize_angle(ref[2] + rng.normal(0.0, spread))
        linear, angular = rng.normal(0.0, 0.5, 3).tolist(), rng.normal(0.0, 2.0, 3).tolist()
        tilt_axis = rng.normal(0.0, [0.3, 0.3, 1.0][trial % 3], 2)
        z = np.array([*tilt_axis, 1.0]) / np.linalg.norm([*tilt_axis, 1.0])
        m = [0.0, 0.0, float(z[0]), 0.0, 0.0, float(z[1]), 0.0, 0.0, float(z[2])]
        if trial % 11 == 0:
            m[2], m[5], m[8] = 0.0, 0.0, 1.0  # upright: no balance axis
        velocity = tuple(rng.normal(0.0, 0.2, 3).tolist())
        expected = reference_control(cfg, px, py, linear, angular, heading, m, velocity, 0.008, ref)
        got = kernels.control(px, py, linear[0], linear[1], angular[0], angular[1], angular[2], heading, m[2], m[5],
                              m[8], *velocity, 0.008, *ref, gains)
        assert _bits(got) == _bits([*expected[:5], *expected[5]])


PINNED_RUN_SHA256 = "4643cd8b7e2e757a8c2658d4f20cd87c7741b912f47db6e92c55f47c49470285"
"""The digest of :func:`_pinned_run` with the Python controller the kernels replaced."""
PLAN = (Motion.FORWARD, Motion.TURN_LEFT_40, Motion.KICK_LEFT, Motion.STAND, Motion.SIDE_STEP_RIGHT, Motion.KICK_RIGHT)


def _pinned_run() -> tuple[str, dict[str, int]]:
    """Eight robots for 600 steps: motions of :data:`PLAN`, one robot walking at changing velocities, heads
    turning, two robots shoved over at step 200 and standing up (one first from the wrong side); the digest
    of every body's pose and joint angles after every step, and what happened."""
    specs = [RobotSpec(f"r{i}", TeamColor.BLUE if i < 4 else TeamColor.RED) for i in range(8)]
    digest = hashlib.sha256()
    counts = {"fallen": 0, "wrong_side": 0}
    with World(specs, seed=3) as world:
        client = world.client
        for i, rid in enumerate(world.robot_ids):
            world.place_robot(rid, Pose2D(-2.0 + 0.6 * i, 0.5 * (i % 3) - 0.5, 0.4 * i))
        world.place_ball(-1.2, 0.7)
        for step in range(600):
            for i, rid in enumerate(world.robot_ids):
                status = world.motion_status(rid)
                if i == 6 and step % 50 == 0:
                    world.command_walk(rid, 0.1 * ((step // 50) % 3), 0.05, 0.3 - 0.2 * ((step // 50) % 2))
                elif status.fallen and status.current is None:
                    counts["fallen"] += 1
                    front = status.fall_side.value == "front"
                    if rid == "r5" and counts["wrong_side"] == 0:
                        front = not front
                        counts["wrong_side"] += 1
                    world.command_motion(rid, Motion.STAND_UP_FROM_FRONT if front else Motion.STAND_UP_FROM_BACK)
                elif status.current is None and i != 6:
                    world.command_motion(rid, PLAN[(step // 7 + i) % len(PLAN)])
                world.set_head(rid, 0.5 * np.sin(0.05 * step + i), 0.2 + 0.1 * np.cos(0.03 * step))
            if step == 200:
                for rid in ("r1", "r5"):
                    pb.resetBaseVelocity(world.body_id(rid), (2.5, 0.0, 0.0), (0.0, 6.0, 0.0), physicsClientId=client)
            world.step(1)
            for rid in world.robot_ids:
                body = world.body_id(rid)
                position, orientation = pb.getBasePositionAndOrientation(body, physicsClientId=client)
                joints = [state[0] for state in pb.getJointStates(
                    body, range(pb.getNumJoints(body, physicsClientId=client)), physicsClientId=client)]
                digest.update(struct.pack(f"{7 + len(joints)}d", *position, *orientation, *joints))
    return digest.hexdigest(), counts


def test_a_pinned_run_plays_as_with_the_python_controller():
    digest, counts = _pinned_run()
    assert counts == {"fallen": 3, "wrong_side": 1}  # the run took the fall and stand-up paths
    assert digest == PINNED_RUN_SHA256


def test_compile_locomotion_compiles_what_a_world_calls():
    """``python -m world.compile`` (run by ``make install``) leaves nothing for a world's steps to compile: the
    controller's kernels (their helpers are compiled into them) get no new signature from robots walking,
    kicking and turning their heads."""
    compile_locomotion()
    compiled = {kernel: list(kernel.signatures) for kernel in (kernels.control, kernels.drive_joints)}
    with World([RobotSpec("a", TeamColor.BLUE), RobotSpec("b", TeamColor.RED)]) as world:
        world.command_walk("a", 0.1, 0.0, 0.2)
        world.command_motion("b", Motion.KICK_LEFT)
        world.set_head("a", 1, 0)
        world.step(10)
    assert compiled and {kernel: list(kernel.signatures) for kernel in compiled} == compiled
