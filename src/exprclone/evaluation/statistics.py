"""``exprclone evaluate``'s statistics: each method's scores summarised, and methods compared pair by pair.

A subtle real smile is a poor ground truth for a broad cloned one, so every summary can
also be made over the pairs whose target smiles strongly: B's mouth corners move apart
by at least :data:`STRONG_SMILE` (20%) between B's two photos, relative to the
outer-eye-corner distance (head motion removed; :func:`exprclone.evaluation.runner.smile_strength`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from ..pipeline.role_check import SAME_PERSON
from .blendshape_judge import COLUMNS as BLENDSHAPE_COLUMNS
from .judge import SMILING
from .runner import REFERENCES, Row
from .scores import GREY_WARMTH, TEETH_SHOWN

#: resamples of the bootstrap interval of a median or a mean (:func:`median_interval`, :func:`mean_interval`), and its seed.
RESAMPLES, SEED = 2000, 0

#: relative widening of the mouth (corner distance / eye-corner distance) that makes a
#: strong smile: the top 29% of the London Set's 72 people (median 15%, quartiles 11% and 22%).
STRONG_SMILE = 0.20
#: methods compared pair by pair in each variant (:func:`contrasts`): the elastic model with the global warp it starts
#: from (the paper's Figs. 19-21), E+MD with the global warp and ERI (its Table 1), and Song et al.'s method with
#: the global warp and ERI, and E+MD with it (its Figs. 16-17).
REFINED = (("elastic", "global"), ("e+md", "global+eri"), ("song", "global+eri"), ("e+md", "song"))


def identity_line(rows: list[Row]) -> tuple[float, float]:
    """What a real smile as wide costs in identity: the intercept and slope of the line fitted on the targets' own
    real smiles (``real`` rows), identity distance against the mouth's widening (``../shared/notes/identity.md``: real
    smiles drift more the wider they are, so a clone is compared with a real smile as wide as itself, never with the
    average real smile, which would reward smiling less); NaN without two real smiles."""
    real = np.array([(float(r["widening"]), float(r["identity"])) for r in rows if r["method"] == "real" and r.get("widening", "") != ""])
    if len(real) < 2:
        return float("nan"), float("nan")
    slope, intercept = np.polyfit(real[:, 0], real[:, 1], 1)
    return float(intercept), float(slope)


def summarise(rows: list[Row], strong_only: bool = False, baseline: str = "global") -> list[Row]:
    """Mean and median of each score per method; failures counted; share keeping identity.

    ``mouth_vs_baseline`` is the mean of the per-pair difference of mouth error to the
    ``baseline`` method (in the row's own variant) over the pairs where both succeeded,
    with its standard error: differences between methods are small beside the spread
    between pairs, and pairing removes that spread.

    ``excess`` is the identity distance beyond a real smile as wide (:func:`identity_line`), its mean with a 95%
    bootstrap interval (``excess_low``, ``excess_high``).

    Teeth, over the pairs that succeeded: ``teeth_sources`` pairs whose source's real
    smile shows teeth (:data:`TEETH_SHOWN`), of which the share ``teeth_kept`` of
    results show teeth; ``closed_sources`` pairs whose source shows none, of which the
    share ``teeth_invented`` of results show teeth all the same.
    """
    out: list[Row] = []
    methods = list(dict.fromkeys(r["method"] for r in rows))
    intercept, slope = identity_line(rows)
    base = {pair_of(r): r["mouth"] for r in rows if r["method"] == baseline + r.get("variant", "") and not r["failed"]}
    for m in methods:
        mine = [r for r in rows if r["method"] == m and (not strong_only or float(r["target_smile"]) >= STRONG_SMILE)]
        ok = [r for r in mine if not r["failed"]]
        line: Row = {"method": m, "pairs": len(mine), "failed": len(mine) - len(ok)}
        for key in ("overall", "mouth", "eyes_brows", "identity"):
            values = np.array([r[key] for r in ok], np.float64)
            line[f"{key}_mean"] = float(values.mean()) if len(values) else float("nan")
            line[f"{key}_median"] = float(np.median(values)) if len(values) else float("nan")
        ids = np.array([r["identity"] for r in ok], np.float64)
        line["same_person"] = float((ids < SAME_PERSON).mean()) if len(ids) else float("nan")
        wide = [(float(r["widening"]), float(r["identity"])) for r in ok if r.get("widening", "") != ""]
        excess = np.array([i - (intercept + slope * w) for w, i in wide], np.float64)
        line["excess"], line["excess_low"], line["excess_high"] = mean_interval(excess)
        judged = np.array([float(r["smiling"]) for r in ok if r.get("smiling", "") != ""], np.float64)
        line["smiling"] = float((judged >= SMILING).mean()) if len(judged) else float("nan")
        diff = np.array([r["mouth"] - base[pair_of(r)] for r in ok if pair_of(r) in base], np.float64)
        line["mouth_vs_baseline"] = float(diff.mean()) if len(diff) else float("nan")
        line["mouth_vs_baseline_se"] = float(diff.std(ddof=1) / np.sqrt(len(diff))) if len(diff) > 1 else float("nan")
        warm = np.array([float(r["warmth"]) for r in ok if r.get("warmth", "") != ""], np.float64)
        line["warmth"], line["warmth_low"], line["warmth_high"] = median_interval(warm)
        line["warmth_n"] = len(warm)
        line["grey"] = float((warm < GREY_WARMTH).mean()) if len(warm) else float("nan")
        for shown_in_source, count, share in ((True, "teeth_sources", "teeth_kept"), (False, "closed_sources", "teeth_invented")):
            group = [float(r["teeth"]) >= TEETH_SHOWN for r in ok if (float(r["source_teeth"]) >= TEETH_SHOWN) == shown_in_source]
            line[count] = len(group)
            line[share] = float(np.mean(group)) if group else float("nan")
        line.update(blendshape_summary(ok))
        out.append(line)
    return out


def blendshape_summary(rows: list[Row]) -> Row:
    """The blendshape judge's columns (:data:`exprclone.evaluation.blendshape_judge.COLUMNS`) over ``rows``: for each,
    the mean of its distances (the median of the rise kept, a ratio) with a 95% bootstrap interval (``to_source``,
    ``to_source_low``, ``to_source_high``) and how many rows have it (``to_source_n``)."""
    line: Row = {}
    for key in BLENDSHAPE_COLUMNS:
        values = np.array([float(r[key]) for r in rows if r.get(key, "") != ""], np.float64)
        centre = median_interval if key == "rise_kept" else mean_interval
        line[key], line[f"{key}_low"], line[f"{key}_high"] = centre(values)
        line[f"{key}_n"] = len(values)
    return line


def median_interval(values: np.ndarray) -> tuple[float, float, float]:
    """The median of ``values`` and its 95% bootstrap interval (percentiles of :data:`RESAMPLES` resampled medians);
    NaN for no values.

    >>> median, low, high = median_interval(np.arange(101.0))
    >>> median, low < 50 < high
    (50.0, True)
    """
    return _bootstrap(values, np.median)


def mean_interval(values: np.ndarray) -> tuple[float, float, float]:
    """The mean of ``values`` and its 95% bootstrap interval (percentiles of :data:`RESAMPLES` resampled means); NaN
    for no values.

    >>> mean, low, high = mean_interval(np.arange(101.0))
    >>> mean, low < 50 < high
    (50.0, True)
    """
    return _bootstrap(values, np.mean)


def _bootstrap(values: np.ndarray, statistic: Callable[..., Any]) -> tuple[float, float, float]:
    """``statistic`` of ``values`` and the 2.5th and 97.5th percentiles of it over :data:`RESAMPLES` resamples."""
    if not len(values):
        return float("nan"), float("nan"), float("nan")
    drawn = np.random.default_rng(SEED).choice(values, (RESAMPLES, len(values)))
    low, high = np.percentile(statistic(drawn, axis=1), (2.5, 97.5))
    return float(statistic(values)), float(low), float(high)


def pair_of(row: Row) -> tuple[str, str, str]:
    """The pair a row is about, and its variant: ``(source, target, variant label)``."""
    return row["source"], row["target"], row.get("variant", "")


def contrasts(rows: list[Row], strong_only: bool = False) -> list[Row]:
    """Pairs of rows compared pair by pair: in each variant, the elastic model against the global warp it starts
    from, E+MD against the global warp with ERI, and Song et al.'s method against both (:data:`REFINED`); then each
    method in each variant against the same method in the default setting.

    Returns
    -------
    list of dict
        ``compared`` (``"e+md [rbf] - e+md"``), ``pairs`` (where both succeeded), and for
        ``mouth``, ``overall``, ``eyes_brows`` and ``identity`` the mean difference and its
        standard error (``mouth_mean``, ``mouth_se``, ...): below 0, the first is closer
        to the real smile (or, for identity, to the target's own face).
    """
    chosen = [r for r in rows if not r["failed"] and (not strong_only or float(r["target_smile"]) >= STRONG_SMILE)]
    by_pair = {(r["source"], r["target"], r["method"]): r for r in chosen}
    names = set(r["method"] for r in chosen)
    labels = dict.fromkeys(r.get("variant", "") for r in chosen if r["method"] not in REFERENCES)
    compared = [(f"{m}{v}", f"{base}{v}") for v in labels for m, base in REFINED if {f"{m}{v}", f"{base}{v}"} <= names]
    variant_rows = dict.fromkeys((r["method"], r["variant"]) for r in chosen if r.get("variant"))
    compared += [(name, name[: -len(label)]) for name, label in variant_rows if name[: -len(label)] in names]
    return [_paired(by_pair, a, b) for a, b in compared]


def _paired(by_pair: dict[tuple[str, str, str], Row], a: str, b: str) -> Row:
    """Row ``a`` minus row ``b`` over the pairs where both are (:func:`contrasts`)."""
    both = [(r, by_pair[key[0], key[1], b]) for key, r in by_pair.items() if key[2] == a and (key[0], key[1], b) in by_pair]
    line: Row = {"compared": f"{a} - {b}", "pairs": len(both)}
    for score in ("mouth", "overall", "eyes_brows", "identity"):
        diff = np.array([float(r[score]) - float(p[score]) for r, p in both])
        line[f"{score}_mean"] = float(diff.mean()) if len(diff) else float("nan")
        line[f"{score}_se"] = float(diff.std(ddof=1) / np.sqrt(len(diff))) if len(diff) > 1 else float("nan")
    return line
