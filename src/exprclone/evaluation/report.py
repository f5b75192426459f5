"""``exprclone evaluate``'s report: the Markdown tables, ``pairs.csv``, ``summary.md`` and the gallery of pairs.

The rows come from :mod:`exprclone.evaluation.runner`, the summaries and the pair-by-pair
comparisons from :mod:`exprclone.evaluation.statistics`.
"""

from __future__ import annotations

import csv
from pathlib import Path

import cv2
import numpy as np

from ..io.images import save_image
from ..landmarks.blendshapes import NAMES
from ..landmarks.layout import DLIB68
from ..methods import BY_NAME
from ..mouth.measure import mouth_width
from .blendshape_judge import RISE_TOP
from .digest import digest
from .figures import face_box
from .judge import MIN_PEOPLE
from .london import Dataset
from .runner import FIELDS, NO_RETARGET, PAPER, REFERENCES, Row, Variant, clone_pair, marks, photo
from .scores import GREY_WARMTH, TEETH_SHOWN, shadows
from .statistics import STRONG_SMILE, contrasts, summarise


def table(summary: list[Row]) -> str:
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
        "identity beyond a real smile as wide [95% CI]",
        "shows teeth: source does",
        "shows teeth: source does not",
        "judged smiling",
        "shadow warmth, median [95% CI]",
        f"grey shadows (< {GREY_WARMTH})",
    ]
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    lines += ["| " + " | ".join([s["method"], *cells(s)]) + " |" for s in summary]
    return "\n".join(lines)


def cells(s: Row) -> list[str]:
    """A line of :func:`summarise`'s output as the tables show it, after the method's name ("-" where nothing was
    measured, or where global, the paired mouth error's baseline, was not run)."""
    paired = "-" if np.isnan(s["mouth_vs_baseline"]) else f"{s['mouth_vs_baseline']:+.4f} ± {s['mouth_vs_baseline_se']:.4f}"
    return [
        str(s["pairs"]),
        str(s["failed"]),
        *(_cell(s, score) for score in ("overall", "mouth")),
        paired,
        *(_cell(s, score) for score in ("eyes_brows", "identity")),
        f"{100 * s['same_person']:.0f}%",
        "-" if np.isnan(s["excess"]) else f"{s['excess']:+.3f} [{s['excess_low']:+.3f}, {s['excess_high']:+.3f}]",
        _share(s["teeth_kept"], s["teeth_sources"]),
        _share(s["teeth_invented"], s["closed_sources"]),
        "-" if np.isnan(s["smiling"]) else f"{100 * s['smiling']:.0f}%",
        "-" if np.isnan(s["warmth"]) else f"{s['warmth']:.3f} [{s['warmth_low']:.3f}, {s['warmth_high']:.3f}]",
        _share(s["grey"], s["warmth_n"]),
    ]


#: the blendshape judge's table's columns after the method's name (:func:`blendshape_cells`).
BLENDSHAPE_HEADER = (
    "results judged",
    "to the source's expression: mouth",
    "eyes",
    "brows",
    "total",
    "its change against the source's: mouth",
    "total",
    "to the target's real expression: total",
    "source's rise kept (median)",
)


def blendshape_table(summary: list[Row]) -> str:
    """A Markdown table of the blendshape judge's columns of :func:`summarise`'s output, each with its 95% interval."""
    lines = ["| method | " + " | ".join(BLENDSHAPE_HEADER) + " |", "|" + "---|" * (1 + len(BLENDSHAPE_HEADER))]
    lines += ["| " + " | ".join([s["method"], *blendshape_cells(s)]) + " |" for s in summary]
    return "\n".join(lines)


def blendshape_cells(s: Row) -> list[str]:
    """A line of :func:`summarise`'s output as the blendshape judge's table shows it (:data:`BLENDSHAPE_HEADER`):
    the distances' means and the rise kept's median, each ``0.123 [0.110, 0.135]`` ("-" where none was measured)."""
    keys = ("to_source_mouth", "to_source_eyes", "to_source_brows", "to_source", "change_mouth", "change", "to_real", "rise_kept")
    return [str(s["to_source_n"]), *(_interval(s, key) for key in keys)]


def _interval(line: Row, key: str) -> str:
    return "-" if np.isnan(line[key]) else f"{line[key]:.3f} [{line[key + '_low']:.3f}, {line[key + '_high']:.3f}]"


def _cell(line: Row, score: str) -> str:
    """A score's mean and median in a summary's line ("-" where none was measured)."""
    mean, median = line[score + "_mean"], line[score + "_median"]
    return "-" if np.isnan(mean) else f"{mean:.4f} / {median:.4f}"


#: the scores that tell two methods' results apart, pair by pair.
TOLD_BY = ("overall", "mouth", "eyes_brows", "identity", "teeth")


def alike(rows: list[Row]) -> list[str]:
    """A sentence for each method whose results score exactly as an earlier method's (in the same variant) on every pair
    they share, with the reason where the stages give it: the elastic model at lambda_k = 0 is its GI (Eq. 6), and with
    ``retarget`` LI is GI (the rows without the ``[no retarget]`` mark).

    >>> rows = [{"source": "a", "target": "b", "method": m, "lambda_k": lam, "failed": "", "variant": " [no retarget]",
    ...          **dict.fromkeys(TOLD_BY, 0.1)} for m, lam in (("global", ""), ("elastic", 0.0))]
    >>> print(*alike(rows))  # doctest: +NORMALIZE_WHITESPACE
    elastic [no retarget] scores exactly as global [no retarget] on all 1 pairs: the DB metric chose lambda_k = 0 for
    every one of them, and at 0 the elastic model (Eq. 6) keeps the global warp's landmarks.
    """
    scores: dict[str, dict[tuple[str, str], tuple[object, ...]]] = {}
    for r in rows:
        if not r["failed"] and r["method"] not in REFERENCES:
            scores.setdefault(r["method"] + r.get("variant", ""), {})[r["source"], r["target"]] = tuple(r[k] for k in TOLD_BY)
    said, methods = [], list(scores)
    for k, method in enumerate(methods):
        for earlier in methods[:k]:
            shared = scores[method].keys() & scores[earlier].keys()
            if shared and all(scores[method][pair] == scores[earlier][pair] for pair in shared):
                said.append(f"{method} scores exactly as {earlier} on all {len(shared)} pairs{_why_alike(rows, method)}.")
                break
    return said


def _why_alike(rows: list[Row], named: str) -> str:
    """Why the method ``named`` (its name and variant's mark) scores as its global warp, where the stages say why
    (:func:`alike`)."""
    method, _, label = named.partition(" ")
    if method not in ("local", "local+eri", "elastic", "elastic+eri"):
        return ""
    if NO_RETARGET not in marks(label):
        return ": with retarget, local re-shaping aims at the target's own face so moved, so LI is GI and lambda_k is 0 without a search"
    mine = [r for r in rows if r["method"] == method and r.get("variant", "").strip() == label]
    if method.startswith("elastic") and {float(r["lambda_k"]) for r in mine if r["lambda_k"] != ""} == {0.0}:
        return (
            ": the DB metric chose lambda_k = 0 for every one of them, and at 0 the elastic model (Eq. 6) keeps the global warp's landmarks"
        )
    return ""


def contrast_table(lines: list[Row]) -> str:
    """A Markdown table of :func:`contrasts`' output."""
    columns = ["compared, paired", "pairs", "mouth", "landmarks overall", "eyes+brows", "identity"]
    out = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    for c in lines:
        cells = [f"{c[k + '_mean']:+.4f} ± {c[k + '_se']:.4f}" for k in ("mouth", "overall", "eyes_brows", "identity")]
        out.append("| " + " | ".join([c["compared"], str(c["pairs"]), *cells]) + " |")
    return "\n".join(out)


def _share(share: float, of: int) -> str:
    return f"{100 * share:.0f}% of {of}" if of else "-"


#: what each sign of the tables means (:func:`tables`).
LEGEND = (
    "Reading the tables: `a / b` is a mean / a median over the pairs; `[a, b]` a 95% bootstrap interval over the pairs;"
    " `x% of n` a share of n pairs (the teeth columns: of the pairs whose source's real expression shows teeth, or shows"
    " none); `+d ± s` a mean difference, pair by pair, and its standard error (below 0 the first method is closer to the"
    " real expression, or, for identity, to the target's own face); a name with `[...]` a variant, its options beside the"
    " default. `-` where there is nothing to measure: no result with shadows (shadow warmth: the methods without ERI or"
    " mesh image shade nothing), no pair of that kind (teeth), the method paired with not run (mouth minus global), too"
    " few people to train the expression judge without the pair's two (judged smiling: it needs"
    f" {MIN_PEOPLE} people), fewer than two real expressions to draw the identity line from, no face the blendshape judge could"
    " read, or every result of the method failed."
)


def tables(rows: list[Row], pair_rows: list[Row]) -> list[str]:
    """The report's tables as Markdown lines: what their signs mean (:data:`LEGEND`), every method over all pairs, a
    sentence for each method that scores as another (:func:`alike`), the pairs whose target smiles strongly (a sentence
    when there are none), and the pair-by-pair comparisons of the variants if any; ``pair_rows`` are the rows of the
    pairs (not of built-in expressions)."""
    n_strong = len({(r["source"], r["target"]) for r in pair_rows if float(r["target_smile"]) >= STRONG_SMILE})
    every = summarise(rows)
    text = [LEGEND, "", "## All pairs", "", table(every), "", "The blendshape judge:", "", blendshape_table(every), ""]
    text += [line for sentence in alike(pair_rows) for line in (sentence, "")]
    strong = f"## Pairs whose target smiles strongly ({n_strong}: mouth widens by at least {STRONG_SMILE:.0%})"
    if n_strong:
        broad = summarise(rows, strong_only=True)
        text += [strong, "", table(broad), "", "The blendshape judge:", "", blendshape_table(broad), ""]
    else:
        text += [strong, "", f"No target's real expression widens the mouth by {STRONG_SMILE:.0%}: no table.", ""]
    compared = contrasts(pair_rows)
    if compared:
        text += [
            "## Pair by pair: the elastic model on its GI, E+MD and Song et al.'s method against global+eri and each other,"
            " in each variant; each variant against the default",
            "",
        ]
        text += ["All pairs, then the strong smiles." if n_strong else "All pairs.", "", contrast_table(compared), ""]
        text += [contrast_table(contrasts(pair_rows, strong_only=True)), ""] if n_strong else []
    return text


def _introduction(command: str, data: Dataset, n_pairs: int, held_out: int = 0) -> list[str]:
    """The summary's opening: the command, the data, and what each column measures."""
    within = f" (within {held_out} folds of the people, each fold's clones made with what was learnt without its people)"
    return [
        "# exprclone evaluation",
        "",
        f"`{command}`",
        "",
        f"{n_pairs} ordered pairs of different people from `{data.root}`{within if held_out else ''};",
        "each method's result is scored against the target's real smile. Landmark errors are in",
        "outer-eye-corner distances after similarity alignment; identity is dlib's face-descriptor",
        "distance to the target's neutral photo (same person below 0.6), and its excess over a real smile as wide (the",
        "line of identity against the mouth's widening over the targets' own real smiles). Teeth show when tooth-coloured",
        f"pixels (paler and brighter than the lips) cover at least {TEETH_SHOWN} squared mouth widths",
        "inside the inner lips (`exprclone.evaluation.teeth`); the two teeth columns give, of the pairs whose source's",
        "real smile shows teeth and of those whose does not, the share of results that do; the last, the share that the",
        "expression judge (a classifier on the landmarks, trained without the pair's two people) calls smiling.",
        "Shadow warmth: over the skin that darkens by more than 6 L* from the target's neutral photo (warped onto the",
        "result), the median of (C*/C*_neutral) / (L*/L*_neutral): 1 for a shading that dims R, G and B alike; real",
        f"skin's shadows are warmer. Grey shadows: the share of results under {GREY_WARMTH} (`exprclone.evaluation.scores.warmth`).",
        "The blendshape judge (`exprclone.evaluation.blendshape_judge`) reads MediaPipe's 52 expression scores (0 to 1) on",
        "each result: their Euclidean distance to the source's expression photo's, per region (mouth, eyes, brows) and in",
        "total, and to the target's real expression's; the distance between its change from the target's neutral photo",
        "and the source's change from its own (the motion alone: people's faces differ at rest; means, with 95% bootstrap",
        "intervals over the pairs); and the share",
        f"of the source's rise it keeps: over the {RISE_TOP} scores the source raises most from its neutral photo, the result's",
        "rise from the target's neutral photo over the source's (median). Each result's 52 scores: `blendshapes.csv`.",
        "",
    ]


def write_report(
    out: Path,
    data: Dataset,
    rows: list[Row],
    landmarks: dict[str, np.ndarray],
    methods: tuple[str, ...],
    command: str,
    variants: tuple[Variant, ...] = (PAPER,),
    sections: tuple[str, ...] = (),
    held_out: int = 0,
) -> str:
    """``pairs.csv``, ``summary.md`` (what each score measures, which method is best on what
    (:func:`exprclone.evaluation.digest.digest`), the full tables (:func:`tables`: with the variants against the default
    setting, :func:`contrasts`, if there are any), then the paragraphs of ``sections``) and the gallery (:func:`_gallery`)
    of e+md pairs in the first variant; returns the full tables, for the terminal (``--full``). ``held_out``: the folds
    of the people the pairs were drawn within, each cloned with what was learnt without its people (0: none)."""
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "pairs.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, FIELDS, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)
    _write_blendshapes(out / "blendshapes.csv", rows)
    pair_rows = [r for r in rows if r["source"] in data.photos]  # not a built-in expression's (sections)
    n_pairs = len({(r["source"], r["target"]) for r in pair_rows})
    shown = tables(rows, pair_rows)
    best = ["## Which method is best on what", "", digest(pair_rows, data.root, None, alike(pair_rows), held_out), ""]
    text = _introduction(command, data, n_pairs, held_out) + best + shown
    text += [line for section in sections for line in (section, "")]
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
    sheet = _warmth_sheet(out, data, rows, landmarks, methods, variants[0])
    if sheet:
        text += [
            "## The greyest shadows",
            "",
            "The results of the methods with ERI (or mesh image) whose shadows are the least warm: target neutral, result, and the result",
            f"with the darkened skin the measure counts outlined: {sheet}",
            "",
            f"![greyest shadows]({sheet})",
            "",
        ]
    (out / "summary.md").write_text("\n".join(text))
    return "\n".join(shown)


def _write_blendshapes(path: Path, rows: list[Row]) -> None:
    """Each scored row's 52 blendshape scores (:data:`exprclone.landmarks.blendshapes.NAMES`), after its source, target
    and method."""
    with open(path, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["source", "target", "method", *NAMES])
        for r in rows:
            if r.get("blendshapes") is not None:
                writer.writerow([r["source"], r["target"], r["method"], *(f"{v:.4f}" for v in r["blendshapes"])])


def _warmth_sheet(
    out: Path, data: Dataset, rows: list[Row], landmarks: dict[str, np.ndarray], methods: tuple[str, ...], variant: Variant, count: int = 12
) -> str | None:
    """The ``count`` results of the methods with ERI (or mesh image) in ``variant`` whose shadows are the least warm
    (:func:`exprclone.evaluation.scores.warmth`), three to a row: [target neutral | result | result, the darkened skin
    the measure counts outlined], each captioned with its pair, method and warmth."""

    label, options = variant
    eri = [m for m in methods if BY_NAME[m].ratio is not None]
    scored = sorted(
        (r for r in rows if r["method"] in {m + label for m in eri} and not r["failed"] and r.get("warmth", "") != ""),
        key=lambda r: float(r["warmth"]),
    )[:count]
    if not scored:
        return None
    cells = []
    for r in scored:
        method, (a, b) = r["method"][: len(r["method"]) - len(label)], (r["source"], r["target"])
        result = clone_pair(data, (a, b), (method,), landmarks, options)[method]
        neutral, found = photo(data.path(b, False)), landmarks[data.path(b, False)]
        darker = shadows(result.image, result.landmarks["final"], neutral, found, DLIB68).darker
        outlined = result.image.copy()
        contours, _ = cv2.findContours(darker.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
        cv2.drawContours(outlined, contours, -1, (0, 255, 255), 3)
        box = face_box(found, neutral.shape)
        strip = np.hstack([cv2.resize(image[box], (240, 240), interpolation=cv2.INTER_AREA) for image in (neutral, result.image, outlined)])
        _caption(strip, f"{a}->{b} {method}: warmth {float(r['warmth']):.2f}")
        cells.append(strip)
    while len(cells) % 3:
        cells.append(np.zeros_like(cells[0]))
    save_image(out / "warmth.jpg", np.vstack([np.hstack(cells[k : k + 3]) for k in range(0, len(cells), 3)]))
    return "warmth.jpg"


def _gallery(
    out: Path, data: Dataset, rows: list[Row], landmarks: dict[str, np.ndarray], method: str, variant: Variant = PAPER
) -> str | None:
    """Best, median and worst pairs by mouth error, and the median one whose source shows teeth (if another), of
    ``method`` in ``variant``.

    Each: [source smile | target neutral | result | target real smile], and under it the
    four mouths close up, each with its teeth measure (``shows`` from :data:`TEETH_SHOWN`).
    """
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
        result = clone_pair(data, (a, b), (method,), landmarks, options)[method]
        cells = [
            (photo(data.path(a, True)), landmarks[data.path(a, True)], r["source_teeth"]),
            (photo(data.path(b, False)), landmarks[data.path(b, False)], row_of[a, b, "no change"]["teeth"]),
            (result.image, result.landmarks["final"], r["teeth"]),
            (photo(data.path(b, True)), landmarks[data.path(b, True)], row_of[a, b, "real"]["teeth"]),
        ]
        tiles = [cv2.resize(image, (360, 360), interpolation=cv2.INTER_AREA) for image, _, _ in cells]
        for tile, label in zip(tiles, (f"{a}'s expression", f"{b} neutral", f"result: {method}", f"{b}'s real expression")):
            _caption(tile, label, bottom=True)
        faces = np.hstack(tiles)
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
    width = mouth_width(landmarks, DLIB68)
    centre = landmarks[list(DLIB68.mouth_outer)].mean(0)
    crop = cv2.getRectSubPix(image, (int(1.4 * width), int(0.7 * width)), (float(centre[0]), float(centre[1])))
    return cv2.resize(crop, (360, 180), interpolation=cv2.INTER_AREA)


def _caption(image: np.ndarray, text: str, bottom: bool = False) -> None:
    """White text, outlined in black, at the image's top left (or bottom left)."""
    at = (8, image.shape[0] - 12 if bottom else 24)
    for colour, thickness in (((0, 0, 0), 4), ((255, 255, 255), 2)):
        cv2.putText(image, text, at, cv2.FONT_HERSHEY_SIMPLEX, 0.7, colour, thickness, cv2.LINE_AA)
