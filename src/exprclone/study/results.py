"""The paper's Table 1 from a study's ratings: each method's mean score per set and overall, with n and a 95% interval.

Per set and method: ``n``, the number of ratings (one from each participant who rated
the set); ``mean``, their mean; and ``ci95``, the half-width of the 95% confidence
interval of that mean by Student's t on the ratings,

    ci95 = t(0.975, n - 1) * s / sqrt(n),  s their standard deviation (n - 1 in its denominator),

so that the interval is ``mean ± ci95``. It treats the scores 1-5 as numbers, as the
paper does when it averages them, and needs two ratings at least (none is given for
fewer). With 2 ratings t is 12.7, so a study needs tens of participants, as the paper's
30, for intervals narrow enough to tell methods apart.

Overall, per method: the mean of all its ratings over the sets and their count, with the
t-interval over participants: each participant's mean score of the method is one value,
since one person's ratings of several sets are not independent. The interval is centred
on the overall mean, which is the mean of those values when each participant rated
every set.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from pathlib import Path

from scipy import stats

from ..errors import ExprCloneError
from ..io.documents import csv_cell
from .folder import RATINGS, Key, read_key, read_study
from .participants import GENDERS, Record, read_all

#: the CSV's columns.
COLUMNS = ("set", "method", "n", "mean", "ci95")
#: the name of the overall row of the table.
OVERALL = "overall"


@dataclass(frozen=True)
class Score:
    """One rating: who gave it, to which set's result by which method, and the score."""

    participant: str
    set_index: int
    method: str
    score: int


@dataclass(frozen=True)
class Cell:
    """A cell of Table 1: a set (or :data:`OVERALL`) and a method, its number of ratings, their mean and ci95 (NaN when undefined)."""

    set: str
    method: str
    n: int
    mean: float
    ci95: float


@dataclass(frozen=True)
class Results:
    """A study's Table 1: the cells per set and method, in the key's order, each method's overall cell, and the participants."""

    key: Key
    cells: list[Cell]
    overall: list[Cell]
    records: list[Record]


def t_interval(values: list[float]) -> float:
    """The half-width of the 95% t-interval of the mean of ``values`` (NaN for fewer than two).

    >>> round(t_interval([3, 4, 5]), 4)  # t(0.975, 2) = 4.3027, s = 1
    2.4841
    """
    n = len(values)
    if n < 2:
        return math.nan
    mean = sum(values) / n
    deviation = math.sqrt(sum((v - mean) ** 2 for v in values) / (n - 1))
    return float(stats.t.ppf(0.975, n - 1)) * deviation / math.sqrt(n)


def cell(set_name: str, method: str, values: list[float], spread: list[float] | None = None) -> Cell:
    """The cell of ``values``; its interval from ``spread`` when given (the participants' means), else from the values."""
    mean = sum(values) / len(values) if values else math.nan
    return Cell(set_name, method, len(values), mean, t_interval(values if spread is None else spread))


def scores(key: Key, records: list[Record]) -> list[Score]:
    """Every rating of the study, its result's method read from the key."""
    found = []
    for record in records:
        for set_index, ratings in sorted(record.ratings.items()):
            for item, score in ratings.items():
                if key.items.get(item, (None,))[0] != set_index:
                    raise ExprCloneError(
                        RATINGS, f"participant {record.participant} rated {item}, which the key has not in set {set_index}"
                    )
                found.append(Score(record.participant, set_index, key.items[item][1], score))
    return found


def table(key: Key, ratings: list[Score]) -> tuple[list[Cell], list[Cell]]:
    """The cells per set and method, and each method's overall cell (see the module's notes)."""
    cells = [
        cell(name, method, [s.score for s in ratings if s.set_index == k and s.method == method])
        for k, name in enumerate(key.names)
        for method in key.methods
    ]
    overall = []
    for method in key.methods:
        mine = [s for s in ratings if s.method == method]
        by_participant: dict[str, list[int]] = {}
        for s in mine:
            by_participant.setdefault(s.participant, []).append(s.score)
        means = [sum(v) / len(v) for v in by_participant.values()]
        overall.append(cell(OVERALL, method, [s.score for s in mine], means))
    return cells, overall


def results(folder: str | Path) -> Results:
    """The Table 1 of the study in ``folder``; ExprCloneError if it is not a study or has no ratings yet."""
    study = read_study(folder)
    key = read_key(folder)
    records = read_all(study)
    ratings = scores(key, records)
    if not ratings:
        raise ExprCloneError(str(folder), "no ratings yet: serve the study (exprclone study serve) and let participants rate it")
    cells, overall = table(key, ratings)
    return Results(key, cells, overall, records)


def csv_text(cells: list[Cell]) -> str:
    """The CSV of the cells: :data:`COLUMNS`, the mean and ci95 to 4 decimals (empty when undefined)."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(COLUMNS)
    for c in cells:
        writer.writerow([csv_cell(c.set), c.method, c.n, *("" if math.isnan(v) else f"{v:.4f}" for v in (c.mean, c.ci95))])
    return out.getvalue()


def formatted(found: Results) -> str:
    """Table 1 as text: a row per set and an overall row, a column per method; each cell ``mean ± ci95 (n)``."""

    def text(c: Cell) -> str:
        if c.n == 0:
            return "-"
        return f"{c.mean:.2f}" + ("" if math.isnan(c.ci95) else f" ± {c.ci95:.2f}") + f" ({c.n})"

    rows = [[name] + [text(c) for c in found.cells if c.set == name] for name in found.key.names]
    rows.append([OVERALL] + [text(c) for c in found.overall])
    header = ["set", *found.key.methods]
    widths = [max(len(r[k]) for r in [header, *rows]) for k in range(len(header))]
    lines = ["  ".join(v.ljust(w) for v, w in zip(r, widths)).rstrip() for r in [header, *rows]]
    return "\n".join(lines) + f"\nmean ± half-width of the 95% t-interval (number of ratings); {who_rated(found.records)}"


def who_rated(records: list[Record]) -> str:
    """Who rated, as the paper describes its participants: how many, their genders and ages (as far as told)."""
    raters = [r for r in records if r.ratings]
    told = [r.about or {} for r in raters]
    genders = ", ".join(f"{sum(a.get('gender') == g for a in told)} {g}" for g in GENDERS)
    ages = [a["age"] for a in told if a.get("age") is not None]
    age_text = f"aged {min(ages)}-{max(ages)}" if ages else "no ages given"
    return f"{len(raters)} participants ({genders}, {sum(a.get('gender') is None for a in told)} not given; {age_text})"
