"""The statistics of a tournament: standings with 95% intervals, head to head, ratings, verdicts.

- **Win rate**: a draw counts as half a win; the 95% interval is Wilson's score interval
  (z = 1.96) on (wins + draws / 2) out of the matches played.
- **Goal difference**: goals scored minus conceded per match (the penalty shoot-out's goals
  are not goals), its mean with a Student t 95% interval.
- **Verdict** of a pair: "A beats B" when A's win-rate interval lies wholly above 0.5 or
  A's goal-difference interval wholly above 0, and neither lies wholly on B's side (below
  0.5, below 0); the same the other way round; otherwise no significant difference.
- **Rating** (three or more policies): a Bradley-Terry fit by Hunter's MM algorithm, a draw
  half a win, with half a win added each way to every pair (a virtual draw, so that a
  policy that never won keeps a finite rating), on the Elo scale (400 log10 of the
  strength, mean 0: 400 points apart means 10:1 odds). Its 95% interval: the 2.5 and
  97.5 percentiles over bootstrap resamples of the matches, resampled within each pair
  so that every pair keeps its count, from a generator seeded by the tournament's seed.

Failed matches (see the batch engine) count for nothing here.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from scenarios.common.statistics import Interval, ci95_half_width, mean, wilson_interval

PRIOR_WINS = 0.5  # virtual half-wins each way per pair in the rating fit
BOOTSTRAP_RESAMPLES = 1000
BOOTSTRAP_STREAM = 7  # the bootstrap's generator: SeedSequence([seed, BOOTSTRAP_STREAM])
ELO_SCALE = 400.0


def mean_interval(values: Sequence[float]) -> tuple[float, Interval]:
    """The mean of ``values`` and its Student t 95% interval (NaN where undefined, n < 2)."""
    centre, half = mean(values), ci95_half_width(values)
    return centre, (centre - half, centre + half)


# ---- standings -------------------------------------------------------------------------------


@dataclass(frozen=True)
class Game:
    """One match as one team saw it: goals for and against, and its result (1 win, 0.5 draw, 0 loss)."""

    goals_for: int
    goals_against: int
    result: float


@dataclass(frozen=True)
class Standing:
    """A team's record over some matches, with 95% intervals."""

    name: str
    matches: int
    wins: int
    draws: int
    losses: int
    win_rate: float
    win_rate_ci95: Interval
    goals_for_per_match: float
    goals_against_per_match: float
    goal_difference: float
    goal_difference_ci95: Interval

    @classmethod
    def of(cls, name: str, games: Sequence[Game]) -> Standing:
        n = len(games)
        wins = sum(1 for g in games if g.result == 1.0)
        draws = sum(1 for g in games if g.result == 0.5)
        score = wins + draws / 2.0
        difference, interval = mean_interval([g.goals_for - g.goals_against for g in games])
        return cls(
            name, n, wins, draws, n - wins - draws, score / n if n else math.nan, wilson_interval(score, n),
            mean([g.goals_for for g in games]), mean([g.goals_against for g in games]), difference, interval,
        )

    def to_json(self) -> dict:
        return {
            "matches": self.matches,
            "wins": self.wins,
            "draws": self.draws,
            "losses": self.losses,
            "win_rate": _rounded(self.win_rate),
            "win_rate_ci95": [_rounded(v) for v in self.win_rate_ci95],
            "goals_for_per_match": _rounded(self.goals_for_per_match),
            "goals_against_per_match": _rounded(self.goals_against_per_match),
            "goal_difference_mean": _rounded(self.goal_difference),
            "goal_difference_ci95": [_rounded(v) for v in self.goal_difference_ci95],
        }


def games_of(records: Sequence[Mapping], entrant: str, opponent: str | None = None) -> list[Game]:
    """The played matches of ``entrant`` (against ``opponent`` only, if given), as it saw them."""
    games = []
    for record in records:
        if record["status"] != "ok":
            continue
        for side, other in (("home", "away"), ("away", "home")):
            if record[f"{side}_entrant"] != entrant or (opponent is not None and record[f"{other}_entrant"] != opponent):
                continue
            winner = record["winner_side"]
            result = 0.5 if winner is None else (1.0 if winner == side else 0.0)
            games.append(Game(record[f"{side}_goals"], record[f"{other}_goals"], result))
    return games


def verdict(first: str, second: str, standing: Standing) -> str:
    """The head to head of ``first`` against ``second`` (``standing``: ``first``'s) in one line."""
    low, high = standing.win_rate_ci95
    gd_low, gd_high = standing.goal_difference_ci95
    first_ahead = low > 0.5 or gd_low > 0.0
    second_ahead = high < 0.5 or gd_high < 0.0
    if first_ahead and not second_ahead:
        return f"{first} beats {second}: {_figures(standing)}"
    if second_ahead and not first_ahead:
        return f"{second} beats {first}: {_figures(_reversed(standing, second))}"
    return f"{first} vs {second}: no significant difference: {_figures(standing)}"


def _reversed(standing: Standing, name: str) -> Standing:
    """The same matches as the other team saw them."""
    low, high = standing.win_rate_ci95
    gd_low, gd_high = standing.goal_difference_ci95
    return Standing(
        name, standing.matches, standing.losses, standing.draws, standing.wins, 1.0 - standing.win_rate,
        (1.0 - high, 1.0 - low), standing.goals_against_per_match, standing.goals_for_per_match,
        -standing.goal_difference, (-gd_high, -gd_low),
    )


def _figures(standing: Standing) -> str:
    low, high = standing.win_rate_ci95
    gd_low, gd_high = standing.goal_difference_ci95
    return (f"win rate {fmt(standing.win_rate, '.2f')} [{fmt(low, '.2f')}, {fmt(high, '.2f')}], goal difference "
            f"{fmt(standing.goal_difference, '+.1f')} [{fmt(gd_low, '+.1f')}, {fmt(gd_high, '+.1f')}] "
            f"over {standing.matches} matches")


def fmt(value: float | None, spec: str) -> str:
    """``value`` formatted by ``spec``; "n/a" for None or NaN."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "n/a"
    return format(value, spec)


def _rounded(value: float, digits: int = 4) -> float | None:
    return None if value is None or not math.isfinite(value) else round(float(value), digits)


# ---- ratings ---------------------------------------------------------------------------------


def bradley_terry(wins: np.ndarray, prior: float = PRIOR_WINS, tolerance: float = 1e-9,
                  max_iterations: int = 100_000) -> np.ndarray:
    """Bradley-Terry strengths (geometric mean 1) from ``wins[..., i, j]``, what i scored against j.

    Hunter's MM algorithm: p_i <- W_i / sum_j n_ij / (p_i + p_j). ``prior`` half-wins are
    added each way to every pair that played; with ``prior`` 0 every team needs a win.
    Leading dimensions are separate tables, fitted at once (the bootstrap's resamples).
    """
    wins = np.asarray(wins, dtype=float)
    played = (wins + np.swapaxes(wins, -1, -2)) > 0
    w = wins + prior * played
    games = w + np.swapaxes(w, -1, -2)
    total = w.sum(axis=-1)
    if np.any(total <= 0):
        raise ValueError(f"Bradley-Terry: a team without a win (scores {total.tolist()}); use a prior > 0")
    strength = np.ones_like(total)
    for _ in range(max_iterations):
        updated = total / (games / (strength[..., :, None] + strength[..., None, :])).sum(axis=-1)
        updated /= np.exp(np.mean(np.log(updated), axis=-1, keepdims=True))
        change = float(np.max(np.abs(updated - strength) / strength))
        strength = updated
        if change < tolerance:
            break
    return strength


def elo(strength: np.ndarray) -> np.ndarray:
    """Bradley-Terry strengths on the Elo scale (400 log10), mean 0 (over the last axis)."""
    rating = ELO_SCALE * np.log10(strength)
    return rating - rating.mean(axis=-1, keepdims=True)


@dataclass(frozen=True)
class Rating:
    name: str
    rating: float
    ci95: Interval

    def to_json(self) -> dict:
        return {"rating": _rounded(self.rating, 1), "ci95": [_rounded(v, 1) for v in self.ci95]}


def ratings(records: Sequence[Mapping], entrants: Sequence[str], seed: int,
            resamples: int = BOOTSTRAP_RESAMPLES) -> list[Rating]:
    """Every entrant's Bradley-Terry rating with its bootstrap 95% interval, best first."""
    index = {name: i for i, name in enumerate(entrants)}
    by_pair: dict[tuple[int, int], list[float]] = {}
    for record in records:
        if record["status"] != "ok":
            continue
        i, j = index[record["home_entrant"]], index[record["away_entrant"]]
        result = 0.5 if record["winner_side"] is None else float(record["winner_side"] == "home")
        if i > j:
            i, j, result = j, i, 1.0 - result
        by_pair.setdefault((i, j), []).append(result)
    k = len(entrants)
    point = np.zeros((k, k))
    rng = np.random.default_rng(np.random.SeedSequence([seed, BOOTSTRAP_STREAM]))
    resampled = np.zeros((resamples, k, k))
    for (i, j), results in sorted(by_pair.items()):
        scores = np.array(results)
        point[i, j], point[j, i] = scores.sum(), scores.size - scores.sum()
        drawn = scores[rng.integers(0, scores.size, (resamples, scores.size))].sum(axis=1)
        resampled[:, i, j], resampled[:, j, i] = drawn, scores.size - drawn
    rating = elo(bradley_terry(point))
    low, high = np.percentile(elo(bradley_terry(resampled)), [2.5, 97.5], axis=0)
    result = [Rating(name, float(rating[i]), (float(low[i]), float(high[i]))) for i, name in enumerate(entrants)]
    return sorted(result, key=lambda r: -r.rating)
