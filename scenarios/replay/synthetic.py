"""A synthetic match directory, written without the simulator: for tests and for timing the page.

:func:`synthetic_match` writes ``match_log.npz`` (the arrays of :class:`match.log.MatchLog`),
``events.jsonl`` and ``summary.json`` for a refereed-looking match of two halves: the game
states of each half (INITIAL, READY, SET, PLAYING), goals at chosen playing times (each
followed by READY and SET again), falls, a ball out, a referee placement and a policy fault.
Robots run smooth seeded paths on the field; robots with estimates report their pose with a
seeded error, updated every ``estimate_every_s`` and unknown (NaN) before the first update.
With ``extras`` the log also has every per-robot extra the page knows
(:data:`scenarios.replay.record.EXTRAS`). It is not a simulation: nothing collides, and the
ball does not follow the game.

``python -m scenarios.replay.synthetic DIR [--half-seconds 600] [--players 4]`` writes one
(a full-length match of 4 v 4 is about 32 000 steps).
"""

from __future__ import annotations

import argparse
import json
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from match.protocol.game_control import GameState
from world.field import FIELD

DT = 0.04
PHASES = ((GameState.INITIAL, 2.0), (GameState.READY, 15.0), (GameState.SET, 3.0))
AFTER_GOAL = ((GameState.READY, 15.0), (GameState.SET, 3.0))
ROLE_NAMES = ("keeper", "striker", "supporter", "defender")


@dataclass(frozen=True)
class Goal:
    """A goal by ``team`` (home or away) after ``play_s`` seconds of playing time in ``half``."""

    half: int
    play_s: float
    team: str


@dataclass(frozen=True)
class Fall:
    """``robot`` falls after ``play_s`` seconds of playing time in ``half`` and lies ``seconds``."""

    robot: str
    half: int
    play_s: float
    seconds: float = 5.0


def synthetic_match(
    directory: Path,
    *,
    home: int = 2,
    away: int = 2,
    half_seconds: float = 30.0,
    goals: Sequence[Goal] = (Goal(1, 10.0, "home"),),
    falls: Sequence[Fall] = (Fall("away_1", 1, 4.0),),
    estimators: Sequence[str] = ("home_0", "home_1"),
    estimate_every_s: float = 2.0,
    extras: bool = False,
    seed: int = 0,
) -> Path:
    """Write a synthetic match into ``directory``; return it."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    agents = [f"home_{p}" for p in range(home)] + [f"away_{p}" for p in range(away)]
    states, halves, events, goal_steps = _schedule(half_seconds, goals, home, away)
    steps = len(states)
    time_s = np.arange(steps) * DT
    robots = np.empty((steps, len(agents), 3))
    for i, _ in enumerate(agents):
        robots[:, i, :] = _path(time_s, rng, i)
    fallen = np.zeros((steps, len(agents)), dtype=bool)
    playing = _play_clock(states, halves)
    for fall in falls:
        i = agents.index(fall.robot)
        start = int(np.argmax((halves == fall.half) & (playing >= fall.play_s)))
        end = min(steps, start + round(fall.seconds / DT))
        fallen[start:end, i] = True
        robots[start:end, i, :] = robots[start, i, :]  # it lies where it fell
        events.append(_event(time_s[start], "fall", robot=fall.robot, x=robots[start, i, 0], y=robots[start, i, 1]))
    ball = np.zeros((steps, 3))
    ball[:, 0] = 2.5 * np.sin(time_s / 7.0)
    ball[:, 1] = 1.6 * np.sin(time_s / 4.3)
    ball[:, 2] = FIELD.ball_radius
    for step, team in goal_steps:  # the ball in the net, then at the centre for the kick-off
        ball[max(0, step - 1), :2] = ((FIELD.half_length + 0.1) * (1 if (team == "home") == (halves[step] == 1) else -1), 0.0)
        ball[step:step + round(18.0 / DT), :2] = 0.0
    estimates = np.full((steps, len(agents), 3), np.nan)
    every = max(1, round(estimate_every_s / DT))
    for name in estimators:
        i = agents.index(name)
        noise = rng.normal(0.0, [0.08, 0.08, 0.05], size=(steps, 3))
        for first in range(every, steps, every):
            estimates[first:first + every, i, :] = robots[first, i, :] + noise[first]
    arrays = {
        "agents": np.array(agents), "time_s": time_s, "state": states.astype(np.int8), "half": halves.astype(np.int8),
        "ball": ball.astype(np.float32), "robots": robots.astype(np.float32), "fallen": fallen,
        "estimates": estimates.astype(np.float32),
    }
    if extras:
        arrays.update(_extras(robots, ball, estimates, rng))
    step = int(np.argmax(playing >= min(3.0, half_seconds / 2)))  # a ball out, a placement and a fault in the first half
    events.append(_event(time_s[step], "ball_out", line="side_line", x=float(ball[step, 0]), y=2.0, last_toucher=agents[-1]))
    events.append(_event(time_s[step + 50], "throw_in", x=float(ball[step, 0]), y=1.6, line="side_line"))
    events.append(_event(time_s[step + 10], "fault", agent=agents[0], error="RuntimeError: synthetic",
                         where="synthetic.py:1"))
    set_step = int(np.argmax(states == GameState.SET))
    events.append(_event(time_s[set_step], "robot_placed", robot=agents[-1], x=0.1, y=0.2, fallen=False))
    events.sort(key=lambda e: e["time_s"])
    np.savez_compressed(directory / "match_log.npz", **arrays)
    with open(directory / "events.jsonl", "w", encoding="utf-8") as handle:
        for event in events:
            handle.write(json.dumps(event) + "\n")
    score = {"home": sum(g.team == "home" for g in goals), "away": sum(g.team == "away" for g in goals)}
    winner = None if score["home"] == score["away"] else ("home" if score["home"] > score["away"] else "away")
    summary = {
        "score": score, "shootout": None, "winner": winner, "seed": seed, "sim_seconds": round(float(time_s[-1]), 3),
        "steps": steps - 1, "events_count": len(events), "synthetic": True,
        "config": {"home_players": home, "away_players": away, "half_seconds": half_seconds, "shootout": False},
    }
    (directory / "summary.json").write_text(json.dumps(summary, indent=2) + "\n", encoding="utf-8")
    return directory


def _event(time_s: float, kind: str, **details) -> dict:
    details = {k: round(float(v), 3) if isinstance(v, (float, np.floating)) else v for k, v in details.items()}
    return {"time_s": round(float(time_s), 3), "kind": kind, **details}


def _schedule(half_seconds: float, goals: Sequence[Goal], home: int, away: int):
    """Per-step state and half, the referee's events, and the (step, team) of each goal."""
    states: list[int] = []
    halves: list[int] = []
    events: list[dict] = []
    goal_steps: list[tuple[int, str]] = []
    score = {"home": 0, "away": 0}

    def enter(state: GameState, half: int) -> None:
        events.append(_event(len(states) * DT, "state", state=state.name, half=half, secondary="NORMAL"))

    def hold(state: GameState, half: int, seconds: float) -> None:
        enter(state, half)
        for _ in range(round(seconds / DT)):
            states.append(int(state))
            halves.append(half)

    for half in (1, 2):
        kickoff = "home" if half == 1 else "away"  # the blue team kicks off each half
        for state, seconds in PHASES:
            hold(state, half, seconds)
        played = 0.0
        pending = sorted((g for g in goals if g.half == half), key=lambda g: g.play_s)
        while played < half_seconds - 1e-9:
            enter(GameState.PLAYING, half)
            events.append(_event(len(states) * DT, "kickoff", team=kickoff, half=half))
            until = pending[0].play_s if pending else half_seconds
            while played < min(until, half_seconds) - 1e-9:
                states.append(int(GameState.PLAYING))
                halves.append(half)
                played += DT
            if pending and played < half_seconds - 1e-9:
                goal = pending.pop(0)
                score[goal.team] += 1
                events.append(_event(len(states) * DT, "goal", team=goal.team, goal="yellow", last_toucher=f"{goal.team}_1",
                                     score=dict(score)))
                goal_steps.append((len(states), goal.team))
                kickoff = "away" if goal.team == "home" else "home"
                for state, seconds in AFTER_GOAL:
                    hold(state, half, seconds)
        if half == 1:
            events.append(_event(len(states) * DT, "half_time", score=dict(score)))
    events.append(_event(len(states) * DT, "end", winner=None if score["home"] == score["away"] else
                         max(score, key=score.get), score=dict(score), shootout=None))
    enter(GameState.FINISHED, 2)
    states.append(int(GameState.FINISHED))
    halves.append(2)
    return np.array(states), np.array(halves), events, goal_steps


def _play_clock(states: np.ndarray, halves: np.ndarray) -> np.ndarray:
    """Seconds of playing time before each step, in its half."""
    playing = (states == GameState.PLAYING).astype(float) * DT
    clock = np.zeros(len(states))
    for half in (1, 2):
        mask = halves == half
        clock[mask] = np.cumsum(playing[mask]) - playing[mask]
    return clock


def _path(time_s: np.ndarray, rng: np.random.Generator, index: int) -> np.ndarray:
    """A smooth seeded path on the field: (x, y, theta) per step, heading along the motion."""
    a, b = rng.uniform(0.5, 2.5), rng.uniform(0.4, 1.6)
    wx, wy = rng.uniform(0.02, 0.08), rng.uniform(0.02, 0.08)
    px, py = rng.uniform(0, 2 * math.pi, size=2)
    x = a * np.sin(wx * time_s + px) + (-1.0 if index % 2 else 1.0) * 0.3
    y = b * np.sin(wy * time_s + py)
    theta = np.arctan2(b * wy * np.cos(wy * time_s + py), a * wx * np.cos(wx * time_s + px))
    return np.stack([x, y, theta], axis=1)


def _extras(robots: np.ndarray, ball: np.ndarray, estimates: np.ndarray, rng: np.random.Generator) -> dict:
    steps, n, _ = robots.shape
    known = np.isfinite(estimates[:, :, :1])
    ball_estimates = np.where(known, ball[:, None, :2] + rng.normal(0, 0.1, size=(steps, n, 2)), np.nan)
    team_ball = np.where(known, ball[:, None, :2] + rng.normal(0, 0.05, size=(1, n, 2)), np.nan)
    roles = np.tile(np.arange(n) % len(ROLE_NAMES), (steps, 1)).astype(np.int8)
    landmarks = np.zeros((steps, n, len(FIELD.landmarks)), dtype=bool)
    landmarks[:, :, 0] = landmarks[:, :, 6] = known[:, :, 0]
    return {"ball_estimates": ball_estimates.astype(np.float32), "team_ball": team_ball.astype(np.float32),
            "roles": roles, "role_names": np.array(ROLE_NAMES), "landmarks_seen": landmarks}


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description="Write a synthetic match directory (no simulator).")
    parser.add_argument("out", type=Path)
    parser.add_argument("--half-seconds", type=float, default=600.0)
    parser.add_argument("--players", type=int, default=4, help="per side")
    parser.add_argument("--extras", action="store_true", help="also the per-robot extras the page knows")
    args = parser.parse_args(argv)
    h = args.half_seconds
    agents = [f"home_{p}" for p in range(args.players)] + [f"away_{p}" for p in range(args.players)]
    falls = [Fall(agent, half, h * (0.2 + 0.15 * k)) for k, agent in enumerate(agents) for half in (1, 2)]
    synthetic_match(args.out, home=args.players, away=args.players, half_seconds=h,
                    goals=(Goal(1, h / 3, "home"), Goal(2, h / 2, "away")), falls=falls, estimators=agents,
                    extras=args.extras)
    print(args.out)


if __name__ == "__main__":
    main()
