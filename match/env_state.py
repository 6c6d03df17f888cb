"""The env's global state: one float32 vector of the game and the true positions (ground truth).

It is the whole match as a referee sees it, for centralized critics and logs; no agent
observes it. Layout, for the agents ``agents`` (the env's ``possible_agents``, in order)::

    0  game state            GameState index: 0 INITIAL, 1 READY, 2 SET, 3 PLAYING, 4 FINISHED
    1  half                  1 or 2 (the shoot-out keeps 2)
    2  seconds remaining     s of playing time left in the half
    3  score home            goals, shoot-out goals not included
    4  score away
    5  shoot-out home        shoot-out goals (0 before a shoot-out)
    6  shoot-out away
    7  ball x                m, field frame (origin at the centre, +x towards the yellow goal)
    8  ball y                m
    9  ball vx               m/s, field frame
    10 ball vy               m/s
    11 + 4 i .. 14 + 4 i     robot i of ``agents``: x m, y m, theta rad (torso heading, field frame,
                             in [-pi, pi]), fallen (0 or 1)

Every value is clipped to :func:`state_space`'s bounds, which a match does not reach
(positions within +-50 m, ball speeds within +-50 m/s, at most 255 goals).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from gymnasium import spaces

from match.game import Match
from match.protocol.game_control import GameState
from match.protocol.spaces import MAX_SCORE, MAX_SECONDS

POSITION_LIMIT_M = 50.0
BALL_SPEED_LIMIT_MPS = 50.0

GAME_FIELDS: tuple[tuple[str, float, float], ...] = (  # (label, low, high)
    ("game_state", 0.0, len(GameState) - 1),
    ("half", 1.0, 2.0),
    ("seconds_remaining", 0.0, MAX_SECONDS),
    ("score_home", 0.0, MAX_SCORE),
    ("score_away", 0.0, MAX_SCORE),
    ("shootout_home", 0.0, MAX_SCORE),
    ("shootout_away", 0.0, MAX_SCORE),
    ("ball_x", -POSITION_LIMIT_M, POSITION_LIMIT_M),
    ("ball_y", -POSITION_LIMIT_M, POSITION_LIMIT_M),
    ("ball_vx", -BALL_SPEED_LIMIT_MPS, BALL_SPEED_LIMIT_MPS),
    ("ball_vy", -BALL_SPEED_LIMIT_MPS, BALL_SPEED_LIMIT_MPS),
)
ROBOT_FIELDS: tuple[tuple[str, float, float], ...] = (
    ("x", -POSITION_LIMIT_M, POSITION_LIMIT_M),
    ("y", -POSITION_LIMIT_M, POSITION_LIMIT_M),
    ("theta", -math.pi, math.pi),
    ("fallen", 0.0, 1.0),
)


def _fields(agents: Sequence[str]) -> list[tuple[str, float, float]]:
    return [*GAME_FIELDS, *((f"{agent}/{name}", low, high) for agent in agents for name, low, high in ROBOT_FIELDS)]


def state_labels(agents: Sequence[str]) -> tuple[str, ...]:
    """The name of every entry of the state vector, in order (``home_0/x`` for a robot's x)."""
    return tuple(label for label, _, _ in _fields(agents))


def state_space(agents: Sequence[str]) -> spaces.Box:
    """The Box of the state vector: shape ``(11 + 4 * len(agents),)``, float32."""
    fields = _fields(agents)
    low = np.array([low for _, low, _ in fields], np.float32)
    high = np.array([high for _, _, high in fields], np.float32)
    return spaces.Box(low=low, high=high, dtype=np.float32)


def global_state(match: Match, agents: Sequence[str], space: spaces.Box) -> np.ndarray:
    """The state vector of ``match`` now, for ``agents`` in order, clipped to ``space``."""
    gc = match.referee.game_control()
    truth = match.truth()
    ball = truth["ball"]
    values = [
        float(match.state),
        gc.half,
        gc.seconds_remaining,
        *gc.score,
        *gc.shootout_score,
        *ball["position"][:2],
        *ball["velocity"],
    ]
    for agent in agents:
        robot = truth["robots"][agent]
        values.extend((*robot["pose"], float(robot["fallen"])))
    state = np.asarray(values, dtype=np.float32)
    return np.clip(state, space.low, space.high, out=state)
