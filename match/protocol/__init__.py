"""What agents and the match agree on: ids, spaces, actions, game-control data, packets.

Pure Python (no pybullet): agents may import this package and nothing else of ``match``.
"""

from match.errors import InvalidActionError, RadioPacketError, StepRefusedError, UnknownAgentError
from match.protocol.actions import ACTION_KEYS, STAND, Action, make_action, parse_action, parse_actions
from match.protocol.game_control import DropIn, GameControlData, GameControlView, GameState, KickOff, SecondaryState
from match.protocol.ids import MAX_PLAYERS_PER_TEAM, AgentId, Side, roster
from match.protocol.kickoff import (
    DEFENDING_POSITIONS,
    KICKING_POSITIONS,
    PENALTY_KICKER_BEHIND_BALL_M,
    kickoff_pose,
    legal_kickoff_position,
    penalty_pose,
)
from match.protocol.packets import INBOX_CAPACITY, MAX_PACKET_BYTES, packet_bytes, packet_of, packet_space
from match.protocol.policy import (
    AgentReport,
    AgentReporter,
    Policy,
    PoseReporter,
    PoseTuple,
    Thinker,
    policy_builder,
    policy_factory_problem,
)
from match.protocol.spaces import (
    MAX_SECONDS,
    MOTIONS,
    NO_MOTION,
    WALK_HIGH,
    WALK_LOW,
    CameraChoice,
    action_space,
    observation_space,
)
from match.protocol.throw_in import THROW_IN_INSET_M, THROW_IN_MAX_X_M, throw_in_spot
from world.field import GoalColor, Pose2D
from world.motions import Displacement, Motion
from world.teams import TeamColor

__all__ = [
    "ACTION_KEYS",
    "DEFENDING_POSITIONS",
    "INBOX_CAPACITY",
    "KICKING_POSITIONS",
    "MAX_PACKET_BYTES",
    "MAX_SECONDS",
    "MAX_PLAYERS_PER_TEAM",
    "MOTIONS",
    "NO_MOTION",
    "PENALTY_KICKER_BEHIND_BALL_M",
    "STAND",
    "THROW_IN_INSET_M",
    "THROW_IN_MAX_X_M",
    "WALK_HIGH",
    "WALK_LOW",
    "Action",
    "AgentId",
    "AgentReport",
    "AgentReporter",
    "CameraChoice",
    "Displacement",
    "DropIn",
    "GameControlData",
    "GameControlView",
    "GameState",
    "GoalColor",
    "InvalidActionError",
    "KickOff",
    "Motion",
    "Policy",
    "PoseReporter",
    "PoseTuple",
    "Pose2D",
    "RadioPacketError",
    "SecondaryState",
    "Side",
    "StepRefusedError",
    "TeamColor",
    "Thinker",
    "UnknownAgentError",
    "action_space",
    "kickoff_pose",
    "legal_kickoff_position",
    "penalty_pose",
    "make_action",
    "packet_bytes",
    "packet_of",
    "packet_space",
    "observation_space",
    "parse_action",
    "parse_actions",
    "policy_builder",
    "policy_factory_problem",
    "roster",
    "throw_in_spot",
]
