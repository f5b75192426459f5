"""``exprclone evaluate``: every method on many cross-person pairs, scored against real smiles.

For an ordered pair (A, B) of different people, A's neutral-to-smile change is cloned
onto B's neutral photo by every method, and each result is scored against B's own real
smile (:mod:`exprclone.evaluation.scores`). Two references share the table: ``no change`` (B's
neutral photo taken as the result: the floor) and ``real`` (B's real smile: the
ceiling, zero landmark error by construction, its identity distance the natural one).

Every row also says how much tooth shows in its image and in A's real smile
(:func:`exprclone.evaluation.scores.teeth`): of the pairs whose source shows teeth, the
summary gives the share of results that show teeth too, and of the others, the share
that shows teeth where the source showed none.

A subtle real smile is a poor ground truth for a broad cloned one, so every table is
also given for the pairs whose target smiles strongly: B's mouth corners move apart by
at least :data:`STRONG_SMILE` (20%) between B's two photos, relative to the outer-eye
-corner distance (head motion removed).

Variants: every method may also run with other options of the clone (another global
warp, the TPS image warp, another strength, the paper's stages without retargeting;
:func:`variants`), its rows named after the method and the variant (``e+md [rbf]``,
``e+md [no retarget]``). Each row's paired mouth difference is to global
warping in the same variant (is the elastic model better than the GI it starts from?),
and :func:`contrasts` pairs each method in a variant with the same method in the
default setting (is the RBF transfer better than the similarity one? does retargeting help?).
"""

from __future__ import annotations

import contextlib
import csv
import functools
import itertools
import multiprocessing
import time
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np

from .. import geometry, global_warp
from ..errors import ExprCloneError, naming
from ..io.images import load_image, save_image
from ..layout import DLIB68
from ..mouth import mouth_width
from ..pipeline import clone_methods, default_detector
from ..progress import Quiet
from .london import Dataset
from .scores import SAME_PERSON, TEETH_SHOWN, FaceDescriptor, identity_distance, landmark_error, teeth

#: relative widening of the mouth (corner distance / eye-corner distance) that makes a
#: strong smile: the top 29% of the London Set's 72 people (median 15%, quartiles 11% and 22%).
STRONG_SMILE = 0.20
REFERENCES = ("no change", "real")
#: photos kept in memory per process (5.5 MB each at 1350 px): pairs come sorted by source,
#: so a source's two photos are read once for all its targets.
PHOTO_CACHE = 8
FIELDS = (
    "source",
    "target",
    "method",
    "target_smile",
    "failed",
    "overall",
    "mouth",
    "eyes_brows",
    "identity",
    "teeth",
    "source_teeth",
    "lambda_k",
    "variant",
)
#: the default setting: the variant of no options (retargeting on), whose rows carry the methods' bare names.
PAPER = ("", {})
#: methods compared with the result they refine, in each variant (:func:`contrasts`): the elastic model with the
#: global warp it starts from (the paper's Figs. 19-21), E+MD with the global warp and ERI (its Table 1).
REFINED = (("elastic", "global"), ("e+md", "global+eri"))


@functools.lru_cache(maxsize=PHOTO_CACHE)
def _photo(path: str) -> np.ndarray:
    """A photo, read once while it is among the last :data:`PHOTO_CACHE` used (pairs come sorted by source)."""
    return load_image(path)


@functools.cache
def _descriptor() -> FaceDescriptor:
    return FaceDescriptor()


def smile_strength(neutral: np.ndarray, smile: np.ndarray) -> float:
    """Relative widening of the mouth from ``neutral`` to ``smile`` landmarks (head motion removed)."""
    aligned = global_warp.remove_head_motion(neutral, smile, DLIB68)
    width = lambda p: mouth_width(p, DLIB68) / geometry.interocular(p, DLIB68)  # noqa: E731
    return float(width(aligned) / width(neutral) - 1.0)


def variant_label(options: dict) -> str:
    """What follows a method's name in a variant's rows: nothing in the default setting, else ``" [rbf, tps, S=1.5]"``.

    Examples
    --------
    >>> variant_label({}), variant_label(dict(global_warp="rbf", strength=1.5)), variant_label(dict(image_warp="mesh"))
    ('', ' [rbf, S=1.5]', '')
    >>> variant_label(dict(global_warp="rbf", retarget=False))
    ' [rbf, no retarget]'
    """
    said = [options.get("global_warp", "similarity"), options.get("image_warp", "mesh")]
    said = [word for word in said if word not in ("similarity", "mesh")]
    if options.get("strength", 1.0) != 1.0:
        said.append(f"S={options['strength']:g}")
    if not options.get("retarget", True):
        said.append("no retarget")
    return f" [{', '.join(said)}]" if said else ""


def variants(global_warps=("similarity",), image_warps=("mesh",), strengths=(1.0,), retargets=(True,)) -> tuple[tuple[str, dict], ...]:
    """Every combination of the options, each ``(label, clone options)`` (:func:`variant_label`), the default setting first if asked."""
    combinations = itertools.product(global_warps, image_warps, strengths, retargets)
    options = [{k: v for k, v in zip(("global_warp", "image_warp", "strength", "retarget"), c)} for c in combinations]
    return tuple(sorted(((variant_label(o), o) for o in options), key=lambda v: v[0] != ""))


def _clone(data: Dataset, pair: tuple[str, str], methods: tuple[str, ...], landmarks: dict, options: dict | None = None) -> dict:
    """A's smile cloned onto B by ``methods`` (with the clone ``options``), with the landmarks already found."""
    sn, se, tn = data.path(pair[0], False), data.path(pair[0], True), data.path(pair[1], False)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with naming({"source_neutral": sn, "source_expression": se, "target_neutral": tn}):
            images, found = (_photo(sn), _photo(se), _photo(tn)), (landmarks[sn], landmarks[se], landmarks[tn])
            return clone_methods(*images, methods, landmarks=found, **(options or {}))


def _candidates(data: Dataset, pair: tuple[str, str], methods: tuple[str, ...], landmarks: dict, variant: tuple[str, dict]) -> dict:
    """Each method's result in one variant, by its row's name: ``(image or None, failure, lambda_k, variant label)``."""
    label, options = variant
    try:
        results = _clone(data, pair, methods, landmarks, options)
        return {f"{m}{label}": (r.image, "", r.lambda_k, label) for m, r in results.items()}
    except Exception as e:  # counted as a failure of every method, never dropped
        return {f"{m}{label}": (None, f"{type(e).__name__}: {e}", None, label) for m in methods}


def score_pair(
    data: Dataset, pair: tuple[str, str], methods: tuple[str, ...], landmarks: dict, variants: tuple[tuple[str, dict], ...] = (PAPER,)
) -> list[dict]:
    """Clone A's smile onto B by each method in each variant (:func:`variants`) and score it; also the two references.

    Returns
    -------
    list of dict
        One row of :data:`FIELDS` per method and variant, and per reference.
    """
    a, b = pair
    tn, ts, source_smile = data.path(b, False), data.path(b, True), data.path(a, True)
    truth = landmarks[ts]
    source_teeth = teeth(_photo(source_smile), landmarks[source_smile], DLIB68)
    target_descriptor = _descriptor()(_photo(tn), landmarks[tn])
    target_smile = smile_strength(landmarks[tn], truth)
    candidates: dict[str, tuple[np.ndarray | None, str, float | None, str]] = {
        "no change": (_photo(tn), "", None, ""),
        "real": (_photo(ts), "", None, ""),
    }
    for variant in variants:
        candidates.update(_candidates(data, pair, methods, landmarks, variant))
    rows = []
    for method, (image, failed, lam, label) in candidates.items():
        row = dict.fromkeys(FIELDS, "")
        row.update(source=a, target=b, method=method, target_smile=round(target_smile, 4), lambda_k="" if lam is None else lam)
        row["variant"] = label
        row["source_teeth"] = round(source_teeth, 5)
        if image is not None:
            try:
                known = {"real": landmarks[ts], "no change": landmarks[tn]}
                found = known[method] if method in known else default_detector().detect(image, f"{method} result")
                row.update(landmark_error(found, truth, DLIB68))
                row["identity"] = identity_distance(_descriptor()(image, found), target_descriptor)
                row["teeth"] = round(teeth(image, found, DLIB68), 5)
            except ExprCloneError as e:
                failed = str(e)
        row["failed"] = failed
        rows.append(row)
    return rows


def _score(args):
    return score_pair(*args)


def run(
    data: Dataset,
    pairs: list[tuple[str, str]],
    methods: tuple[str, ...],
    jobs: int = 1,
    progress: Callable = Quiet,
    variants: tuple[tuple[str, dict], ...] = (PAPER,),
) -> tuple[list[dict], dict]:
    """Score every pair (in ``jobs`` processes), each method in each of ``variants`` (:func:`variants`).

    ``progress(total, what)`` makes a display of how many of ``total``
    things are done, with a method ``update(done, note)`` (as
    :class:`exprclone.progress.Bar`): one for the photos' landmarks, one for the pairs.

    Returns
    -------
    rows : list of dict
        :func:`score_pair`'s rows of every pair.
    landmarks : dict of str to ndarray
        The landmarks detected on each photo, by path (detected once, shared by all pairs).
    """
    people = sorted({p for pair in pairs for p in pair})
    paths = [data.path(p, s) for p in people for s in (False, True)]
    landmarks = {}
    bar = progress(len(paths), "landmarks")
    for k, path in enumerate(paths, 1):
        landmarks[path] = default_detector().detect(_photo(path), path)
        bar.update(k)
    rows = []
    tasks = [(data, pair, methods, landmarks, variants) for pair in pairs]
    bar, start = progress(len(pairs), "pairs"), time.perf_counter()
    with multiprocessing.get_context("fork").Pool(jobs) if jobs > 1 else contextlib.nullcontext() as pool:
        for k, pair_rows in enumerate(pool.imap(_score, tasks) if pool else map(_score, tasks), 1):
            rows += pair_rows
            bar.update(k, f"{(time.perf_counter() - start) / k:.1f} s each")
    return rows, landmarks


def summarise(rows: list[dict], strong_only: bool = False, baseline: str = "global") -> list[dict]:
    """Mean and median of each score per method; failures counted; share keeping identity.

    ``mouth_vs_baseline`` is the mean of the per-pair difference of mouth error to the
    ``baseline`` method (in the row's own variant) over the pairs where both succeeded,
    with its standard error: differences between methods are small beside the spread
    between pairs, and pairing removes that spread.

    Teeth, over the pairs that succeeded: ``teeth_sources`` pairs whose source's real
    smile shows teeth (:data:`TEETH_SHOWN`), of which the share ``teeth_kept`` of
    results show teeth; ``closed_sources`` pairs whose source shows none, of which the
    share ``teeth_invented`` of results show teeth all the same.
    """
    out = []
    methods = list(dict.fromkeys(r["method"] for r in rows))
    pair_of = lambda r: (r["source"], r["target"], r.get("variant", ""))  # noqa: E731
    base = {pair_of(r): r["mouth"] for r in rows if r["method"] == baseline + r.get("variant", "") and not r["failed"]}
    for m in methods:
        mine = [r for r in rows if r["method"] == m and (not strong_only or float(r["target_smile"]) >= STRONG_SMILE)]
        ok = [r for r in mine if not r["failed"]]
        line = {"method": m, "pairs": len(mine), "failed": len(mine) - len(ok)}
        for key in ("overall", "mouth", "eyes_brows", "identity"):
            values = np.array([r[key] for r in ok], float)
            line[f"{key}_mean"] = float(values.mean()) if len(values) else float("nan")
            line[f"{key}_median"] = float(np.median(values)) if len(values) else float("nan")
        ids = np.array([r["identity"] for r in ok], float)
        line["same_person"] = float((ids < SAME_PERSON).mean()) if len(ids) else float("nan")
        diff = np.array([r["mouth"] - base[pair_of(r)] for r in ok if pair_of(r) in base], float)
        line["mouth_vs_baseline"] = float(diff.mean()) if len(diff) else float("nan")
        line["mouth_vs_baseline_se"] = float(diff.std(ddof=1) / np.sqrt(len(diff))) if len(diff) > 1 else float("nan")
        for shown_in_source, count, share in ((True, "teeth_sources", "teeth_kept"), (False, "closed_sources", "teeth_invented")):
            group = [float(r["teeth"]) >= TEETH_SHOWN for r in ok if (float(r["source_teeth"]) >= TEETH_SHOWN) == shown_in_source]
            line[count] = len(group)
            line[share] = float(np.mean(group)) if group else float("nan")
        out.append(line)
    return out


def table(summary: list[dict]) -> str:
    """A Markdown table of :func:`summarise`'s output."""
    columns = [
        "method",
        "pairs",
        "failed",
        "landmark error mean / median",
        "mouth mean / median",
        "mouth minus global, paired (± s.e.)",
        "eyes+brows mean / median",
        "identity mean / median",
        "identity < 0.6",
        "shows teeth: source does",
        "shows teeth: source does not",
    ]
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    for s in summary:
        cell = lambda k: f"{s[k + '_mean']:.4f} / {s[k + '_median']:.4f}"  # noqa: E731
        paired = f"{s['mouth_vs_baseline']:+.4f} ± {s['mouth_vs_baseline_se']:.4f}"
        values = [s["method"], s["pairs"], s["failed"], cell("overall"), cell("mouth"), paired, cell("eyes_brows"), cell("identity")]
        values += [
            f"{100 * s['same_person']:.0f}%",
            _share(s["teeth_kept"], s["teeth_sources"]),
            _share(s["teeth_invented"], s["closed_sources"]),
        ]
        lines.append("| " + " | ".join(map(str, values)) + " |")
    return "\n".join(lines)


def contrasts(rows: list[dict], strong_only: bool = False) -> list[dict]:
    """Pairs of rows compared pair by pair: in each variant, the elastic model against the global warp it starts
    from, and E+MD against the global warp with ERI (:data:`REFINED`); then each method in each variant against the
    same method in the default setting.

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


def _paired(by_pair: dict, a: str, b: str) -> dict:
    """Row ``a`` minus row ``b`` over the pairs where both are (:func:`contrasts`)."""
    both = [(r, by_pair[key[0], key[1], b]) for key, r in by_pair.items() if key[2] == a and (key[0], key[1], b) in by_pair]
    line = {"compared": f"{a} - {b}", "pairs": len(both)}
    for score in ("mouth", "overall", "eyes_brows", "identity"):
        diff = np.array([float(r[score]) - float(p[score]) for r, p in both])
        line[f"{score}_mean"] = float(diff.mean()) if len(diff) else float("nan")
        line[f"{score}_se"] = float(diff.std(ddof=1) / np.sqrt(len(diff))) if len(diff) > 1 else float("nan")
    return line


def contrast_table(lines: list[dict]) -> str:
    """A Markdown table of :func:`contrasts`' output."""
    columns = ["compared, paired", "pairs", "mouth", "landmarks overall", "eyes+brows", "identity"]
    out = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    for c in lines:
        cells = [f"{c[k + '_mean']:+.4f} ± {c[k + '_se']:.4f}" for k in ("mouth", "overall", "eyes_brows", "identity")]
        out.append("| " + " | ".join([c["compared"], str(c["pairs"]), *cells]) + " |")
    return "\n".join(out)


def _share(share: float, of: int) -> str:
    return f"{100 * share:.0f}% of {of}" if of else "-"


def write_report(
    out: Path,
    data: Dataset,
    rows: list[dict],
    landmarks: dict,
    methods: tuple[str, ...],
    command: str,
    variants: tuple[tuple[str, dict], ...] = (PAPER,),
) -> str:
    """``pairs.csv``, ``summary.md`` (with the variants against the default setting, :func:`contrasts`, if there are
    any) and the gallery (:func:`_gallery`) of e+md pairs in the first variant."""
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "pairs.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, FIELDS)
        writer.writeheader()
        writer.writerows(rows)
    n_pairs = len({(r["source"], r["target"]) for r in rows})
    n_strong = len({(r["source"], r["target"]) for r in rows if float(r["target_smile"]) >= STRONG_SMILE})
    text = [
        "# exprclone evaluation",
        "",
        f"`{command}`",
        "",
        f"{n_pairs} ordered pairs of different people from `{data.root}`;",
        "each method's result is scored against the target's real smile. Landmark errors are in",
        "outer-eye-corner distances after similarity alignment; identity is dlib's face-descriptor",
        "distance to the target's neutral photo (same person below 0.6). Teeth show when tooth-coloured",
        f"pixels (paler and brighter than the lips) cover at least {TEETH_SHOWN} squared mouth widths",
        "inside the inner lips (`exprclone.evaluation.teeth`); the last two columns give, of the pairs",
        "whose source's real smile shows teeth and of those whose does not, the share of results that do.",
        "",
        "## All pairs",
        "",
        table(summarise(rows)),
        "",
        f"## Pairs whose target smiles strongly ({n_strong}: mouth widens by at least {STRONG_SMILE:.0%})",
        "",
        table(summarise(rows, strong_only=True)),
        "",
    ]
    if contrasts(rows):
        text += ["## Pair by pair: the elastic model on its GI in each variant, and each variant against the default", ""]
        text += ["All pairs, then the strong smiles.", ""]
        text += [contrast_table(contrasts(rows)), "", contrast_table(contrasts(rows, strong_only=True)), ""]
    gallery = _gallery(out, data, rows, landmarks, "e+md" if "e+md" in methods else methods[-1], variants[0])
    if gallery:
        text += [
            "## Gallery",
            "",
            "Best, median and worst pairs by mouth error, and the median pair whose source shows teeth:",
            "source smile, target neutral, result, target's real smile; under each, the mouths close up",
            f"with their teeth measure: {gallery}",
            "",
            f"![gallery]({gallery})",
            "",
        ]
    (out / "summary.md").write_text("\n".join(text))
    return "\n".join(text)


def _gallery(out: Path, data: Dataset, rows: list[dict], landmarks: dict, method: str, variant: tuple[str, dict] = PAPER) -> str | None:
    """Best, median and worst pairs by mouth error, and the median one whose source shows teeth (if another), of
    ``method`` in ``variant``.

    Each: [source smile | target neutral | result | target real smile], and under it the
    four mouths close up, each with its teeth measure (``shows`` from :data:`TEETH_SHOWN`).
    """
    import cv2

    label, options = variant
    scored = sorted((r for r in rows if r["method"] == method + label and not r["failed"]), key=lambda r: r["mouth"])
    if not scored:
        return None
    picks = {"best": scored[0], "median": scored[len(scored) // 2], "worst": scored[-1]}
    with_teeth = [r for r in scored if float(r["source_teeth"]) >= TEETH_SHOWN]
    if with_teeth and not any(r is with_teeth[len(with_teeth) // 2] for r in picks.values()):
        picks["median of sources showing teeth"] = with_teeth[len(with_teeth) // 2]
    row_of = {(r["source"], r["target"], r["method"]): r for r in rows}
    strips = []
    for name, r in picks.items():
        a, b = r["source"], r["target"]
        result = _clone(data, (a, b), (method,), landmarks, options)[method]
        cells = [
            (_photo(data.path(a, True)), landmarks[data.path(a, True)], r["source_teeth"]),
            (_photo(data.path(b, False)), landmarks[data.path(b, False)], row_of[a, b, "no change"]["teeth"]),
            (result.image, result.landmarks["final"], r["teeth"]),
            (_photo(data.path(b, True)), landmarks[data.path(b, True)], row_of[a, b, "real"]["teeth"]),
        ]
        faces = np.hstack([cv2.resize(image, (360, 360), interpolation=cv2.INTER_AREA) for image, _, _ in cells])
        _caption(faces, f"{name}: {a} -> {b}, mouth error {r['mouth']:.4f}")
        mouths = []
        for image, points, amount in cells:
            close_up = _mouth_close_up(image, points)
            shows = amount != "" and float(amount) >= TEETH_SHOWN
            _caption(close_up, "" if amount == "" else f"teeth {float(amount):.3f}{' shows' if shows else ''}")
            mouths.append(close_up)
        strips += [faces, np.hstack(mouths)]
    save_image(out / "gallery.jpg", np.vstack(strips))
    return "gallery.jpg"


def _mouth_close_up(image: np.ndarray, landmarks: np.ndarray) -> np.ndarray:
    """The mouth, 1.4 mouth widths across and half as high, as a 360 x 180 image."""
    import cv2

    width = mouth_width(landmarks, DLIB68)
    centre = landmarks[list(DLIB68.mouth_outer)].mean(0)
    crop = cv2.getRectSubPix(image, (int(1.4 * width), int(0.7 * width)), (float(centre[0]), float(centre[1])))
    return cv2.resize(crop, (360, 180), interpolation=cv2.INTER_AREA)


def _caption(image: np.ndarray, text: str) -> None:
    """White text, outlined in black, at the image's top left."""
    import cv2

    for colour, thickness in (((0, 0, 0), 4), ((255, 255, 255), 2)):
        cv2.putText(image, text, (8, 24), cv2.FONT_HERSHEY_SIMPLEX, 0.7, colour, thickness, cv2.LINE_AA)
