"""The representations the team agent's behaviour reads, and the :class:`WorldModel` that bundles them.

Frames (docs/design/index.md section 3): *field* (m, rad; x toward the yellow goal), *torso* (the robot's,
x ahead, y left). Times are the agent's own clock (s since its reset), ``*_s`` fields; durations
``*_for_s``.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

from agents.modelling.ball_model import BallEstimate
from agents.modelling.obstacle_model import Obstacle, ObstacleKind
from agents.modelling.team_model import Teammate
from match.protocol import DropIn, GameState, GoalColor, KickOff, Motion, Pose2D


@dataclass(frozen=True)
class RobotPose:
    """The self-locator's estimate: the pose (field frame) and one standard deviation of it."""

    pose_field: Pose2D
    sigma_m: float
    sigma_rad: float


@dataclass(frozen=True)
class Posture:
    """The body, from the motion status and the inertial sensors (:mod:`~agents.team.modelling.odometry`).

    ``motion``: the motion playing now (None: idle); ``fallen``: lying; ``standing_up``: a stand-up
    plays; ``stand_up_tried``: a stand-up finished since the robot last went down (it left it down);
    ``last_stand_up``: that stand-up; ``gyro_radps``: its turn rates (torso x, y, z);
    ``accelerometer_x_mps2``: its forward axis' reading (which side it lies on)."""

    motion: Motion | None
    fallen: bool
    standing_up: bool
    stand_up_tried: bool
    last_stand_up: Motion | None
    gyro_radps: tuple[float, float, float]
    accelerometer_x_mps2: float
    sonar_m: tuple[float, ...]

    @property
    def busy(self) -> bool:
        """Lying or standing up: it plays nothing else."""
        return self.fallen or self.standing_up

    @property
    def kicking(self) -> bool:
        return self.motion is not None and self.motion.is_kick


@dataclass(frozen=True)
class Odometry:
    """How the body moved over the last step (torso frame): the walk's commanded turn and the gyro's
    measured one (rad/s), while it was ``upright`` (not falling)."""

    upright: bool
    commanded_turn_radps: float
    measured_turn_radps: float


@dataclass(frozen=True)
class BallModel:
    """The own ball: ``torso`` as the ball model holds it (however old; None: none believed), ``recent``
    the same if younger than the ball's lost time (``ball.lost_s``), ``field`` the recent one in the
    field frame (the pose's uncertainty included)."""

    torso: BallEstimate | None
    recent: BallEstimate | None
    field: BallEstimate | None


@dataclass(frozen=True)
class TeamBall:
    """The ball the team believes in (field frame): a teammate's, the own, or a throw-in's spot; None:
    no one knows."""

    field: BallEstimate | None


@dataclass(frozen=True)
class Obstacles:
    """The robots and echoes believed around (torso frame, nearest first), seen from ``pose_field``;
    ``robots_field``: those it saw (not the sonars' echoes) in the field frame (m), computed when read."""

    torso: tuple[Obstacle, ...]
    pose_field: Pose2D

    @functools.cached_property
    def robots_field(self) -> tuple[tuple[float, float], ...]:
        pose = self.pose_field
        c, s = math.cos(pose.theta), math.sin(pose.theta)
        return tuple((pose.x + c * o.x_m - s * o.y_m, pose.y + s * o.x_m + c * o.y_m)
                     for o in self.torso if o.kind is not ObstacleKind.UNKNOWN)


@dataclass(frozen=True)
class GameSituation:
    """The game as the game-control data and the robot's memory tell it.

    ``state_since_s``: when the state last changed; ``attack``: +1 when the robot attacks toward +x
    (defends blue), else -1; ``drop_in_at_s``: when the last throw-in put the ball back;
    ``drop_in_spot_field``: where the rule put it, from the last belief (None: not known);
    ``own_goal_ahead_s``: when a frame last showed the own goal near straight ahead."""

    state: GameState
    state_since_s: float
    kickoff: KickOff
    shootout: bool
    defended: GoalColor
    drop_in_team: DropIn
    drop_in_at_s: float
    drop_in_spot_field: tuple[float, float] | None
    own_goal_ahead_s: float

    @property
    def attack(self) -> float:
        return 1.0 if self.defended is GoalColor.BLUE else -1.0

    @property
    def own_kickoff(self) -> bool:
        return self.kickoff is KickOff.OWN_TEAM


@dataclass(frozen=True)
class PlayStatus:
    """What open play says beyond the game-control data (:mod:`~agents.team.modelling.restart`):
    ``restart_field``: where the referee will put back a ball going out or just out (None: in play);
    ``kickoff_played_s``: when the ball of the last kick-off was first believed played (inf: not yet)."""

    restart_field: tuple[float, float] | None
    kickoff_played_s: float


@dataclass(frozen=True)
class TeamState:
    """The teammates heard lately (by player number), and how long none was heard."""

    teammates: tuple[Teammate, ...]
    silent_for_s: float


@dataclass(frozen=True)
class WorldModel:
    """One step's snapshot of everything the behaviour may read. ``ball``, ``team_ball`` and ``play``
    are None while the robot is busy (lying or standing up: it plays nothing); ``play`` also outside
    PLAYING and while a kick plays."""

    player: int
    step: int
    now_s: float
    robot: RobotPose
    posture: Posture
    odometry: Odometry
    game: GameSituation
    team: TeamState
    obstacles: Obstacles
    ball: BallModel | None
    team_ball: TeamBall | None
    play: PlayStatus | None
