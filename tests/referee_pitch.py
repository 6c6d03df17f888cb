"""A pitch for referee tests: ball and robots are placed by hand, time advances by hand."""

from __future__ import annotations

from dataclasses import replace

from match.protocol.ids import AgentId, roster
from match.referee import Referee, RefereeConfig
from world.ball import BallState
from world.field import FIELD, Pose2D
from world.world import RobotTruth

STEP_S = 0.04


class FakePitch:
    """Implements :class:`match.referee.Pitch` without physics: nothing moves unless told."""

    def __init__(self, agents: tuple[AgentId, ...]):
        self.time_s = 0.0
        self.poses = {str(a): Pose2D(0.0, 0.0, 0.0) for a in agents}
        self.fallen = {str(a): False for a in agents}
        self.colors: dict = {}
        self.ball_state = BallState(0.0, 0.0, FIELD.ball_radius, 0.0, 0.0, 0.0, None, None)

    def ball(self) -> BallState:
        return self.ball_state

    def robot_truth(self, robot_id: str) -> RobotTruth:
        return RobotTruth(self.poses[robot_id], 0.34, 0.0, self.fallen[robot_id], self.colors.get(robot_id))

    def place_robot(self, robot_id: str, pose: Pose2D) -> None:
        self.poses[robot_id] = pose
        self.fallen[robot_id] = False

    def place_ball(self, x: float, y: float, vx: float = 0.0, vy: float = 0.0) -> None:
        self.ball_state = replace(self.ball_state, x=x, y=y, z=FIELD.ball_radius, vx=vx, vy=vy, vz=0.0)

    def set_team_color(self, robot_id: str, team) -> None:
        self.colors[robot_id] = team

    def put_ball(self, x: float, y: float, toucher: str | None = None, *, z: float = FIELD.ball_radius, speed: float = 0.0):
        """Put the ball somewhere, as if ``toucher`` had just touched it (None: keep the last toucher)."""
        last, when = self.ball_state.last_toucher, self.ball_state.last_touch_time_s
        if toucher is not None:
            last, when = toucher, self.time_s
        self.ball_state = BallState(x, y, z, speed, 0.0, 0.0, last, when)


def make_referee(home: int = 2, away: int = 2, **config) -> tuple[Referee, FakePitch]:
    agents = roster(home, away)
    pitch = FakePitch(agents)
    referee = Referee(pitch, agents, RefereeConfig(**config))
    referee.start()
    return referee, pitch


def advance(referee: Referee, pitch: FakePitch, seconds: float) -> list:
    """Step time in control steps for ``seconds``; return the events of those steps."""
    events = []
    for _ in range(int(round(seconds / STEP_S))):
        pitch.time_s += STEP_S
        events.extend(referee.update().events)
    return events


def to_playing(referee: Referee, pitch: FakePitch) -> None:
    cfg = referee.config
    advance(referee, pitch, cfg.initial_seconds + cfg.ready_seconds + cfg.set_seconds + STEP_S)
