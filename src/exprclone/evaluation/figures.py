"""The paper's figures that compare methods, drawn on one triple of photos (``exprclone compare``, ``POST /api/compare``).

:func:`sheet`, Figs. 11-13 (``--figure 11``), drawn by the paper's stages (``retarget=False``), in rows of panels
(:mod:`exprclone.evaluation.panels`):

1. Fig. 11: the target's neutral face, the seven methods (a)-(g), the source's expression (h).
2. Fig. 12: (b)-(g) minus (a), each under its panel; the panels that are equal, and why; the DB curve.
3. Fig. 13: (b)-(a), (c)-(a), (d)-(a), (e)-(d), (f)-(d), (g)-(f), under (b)-(g); what lambda_k does; the DB
   metric's terms at the lambda_k chosen, at 0 and at LI (why it was chosen).
4. With ``retarget`` (on by default): the seven methods as this project makes them by default, each under the paper's,
   then its E+MD minus the paper's.

Why both: the figure is the paper's, so the paper's stages draw it; ``retarget`` is this project's addition (the
target's own smile, learnt from real faces), which makes LI equal GI, so that its (b) and (c) are its (a): the last row
shows what a clone gives by default beside what the paper's stages give. ``retarget`` off draws the paper's rows alone.

A difference image is the absolute luminance difference of two results, normalised so that its largest value is 255
("normalizing the values to the range 0~255", Sec. IV); where two results are equal it is black, and says so.

:func:`fig19` draws the paper's Figs. 19-21 instead: the elastic model on the result of another global warp
(``--figure 19``); :func:`fig16` its Figs. 16-17, E+MD beside Song et al.'s method (``--figure 16``), and the elastic
model and E+MD on Song et al.'s global warp (``--figure 17``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from ..errors import ExprCloneError
from ..methods import BY_NAME, FIG11, FIGURES, SHAPES
from ..options import GIVEN, GLOBAL_WARPS, Options
from ..pipeline.result import CloneResult
from ..roles import SOURCE_EXPRESSION, TARGET_NEUTRAL
from . import panels
from .db_words import lambda_words, terms_words
from .panels import difference, panel, words

#: the methods Figs. 19-21 show: the global warp's result, and the elastic model on it (no MD: the paper's target had no texture).
FIG19 = ("global", "elastic")
#: how each global warp is named in Figs. 19-21's panel (b).
GLOBAL_NAMES = {
    "similarity": "similarity (Liu et al.)",
    "rbf": "RBF (Seol and Lewis)",
    "vtc": "VTC (Song et al.)",
    GIVEN: "given landmarks",
}
#: the methods of Figs. 16 and 17, panels (b) on, between the target's neutral face (a) and the source's expression;
#: Fig. 17's made on Song et al.'s global warp, VTC (:data:`SONG_WARP`).
FIG16 = {"16": ("global+eri", "song", "elastic+eri", "e+md"), "17": ("song", "elastic+eri", "e+md")}
#: how Figs. 16-17 name each method, as the paper's captions do.
CAPTIONS = {"global+eri": "global warping + ERI", "song": "Song et al.", "elastic+eri": "elastic + ERI", "e+md": "E+MD"}
#: the global warp Fig. 17 shows the elastic model and E+MD on: Song et al.'s.
SONG_WARP = "vtc"
#: Fig. 12's pairs, each panel (b)-(g) minus (a); Fig. 13's, as the paper lists them.
FIG12 = tuple((m, FIG11[0]) for m in FIG11[1:])
FIG13 = (
    ("local", "global"),
    ("elastic", "global"),
    ("global+eri", "global"),
    ("local+eri", "global+eri"),
    ("elastic+eri", "global+eri"),
    ("e+md", "elastic+eri"),
)
#: what rows 2-4 of the sheet are, in their first panel.
ROW_WORDS = {
    "Fig. 12": ["Each of (b)-(g) minus (a), the global result: their luminance's absolute difference, its largest white."],
    "Fig. 13": ["(b), (c), (d) minus (a); (e), (f) minus (d); (g) minus (f): what each stage adds to the one before it."],
    "This project's default": [
        "retarget on (not in the paper): the source's expression made as the target's own face makes it, learnt from"
        " real faces; local re-shaping aims at it, so LI is GI and lambda_k is 0.",
        "Each panel under the paper's; last, its E+MD minus the paper's (g).",
    ],
}


@dataclass(frozen=True)
class Run:
    """One set of clones a figure draws: its methods, with these options."""

    methods: tuple[str, ...]
    options: Options


def face_box(landmarks: np.ndarray, shape: tuple[int, ...]) -> tuple[slice, slice]:
    """A square box around the face with a margin, inside the image."""
    centre = (landmarks.min(0) + landmarks.max(0)) / 2
    half = 0.7 * (landmarks.max(0) - landmarks.min(0)).max()
    x0, y0 = np.maximum(0, np.floor(centre - half)).astype(int)
    x1, y1 = np.minimum((shape[1], shape[0]), np.ceil(centre + half)).astype(int)
    return slice(y0, y1), slice(x0, x1)


def letter(method: str) -> str:
    """A method's panel in Fig. 11, ``(a)``."""
    return f"({BY_NAME[method].panel})"


def same_as(results: dict[str, CloneResult]) -> dict[str, str]:
    """Each method of Fig. 11 whose image is bit for bit an earlier one's, that method."""
    found: dict[str, str] = {}
    for k, method in enumerate(FIG11):
        earlier = [e for e in FIG11[:k] if e not in found and np.array_equal(results[method].image, results[e].image)]
        if earlier:
            found[method] = earlier[0]
    return found


def why_same(method: str, earlier: str, result: CloneResult) -> str:
    """Why ``method``'s image is ``earlier``'s (:func:`same_as`), in a few words."""
    gi, li, elastic = SHAPES
    shapes = (BY_NAME[method].shape, BY_NAME[earlier].shape)
    retargeted = result.options is not None and result.options.retarget
    if shapes[0] != shapes[1] and shapes[1] == gi and retargeted:
        return "retarget makes LI GI" + (": nothing to balance" if shapes[0] == elastic else "")
    if shapes == (elastic, gi):
        return f"lambda_k = 0 ({'the DB metric' if result.db_curve is not None else 'given'}) keeps GI"
    if shapes == (elastic, li):
        return "lambda_k = inf gives LI"
    if shapes == (li, gi):
        return "local re-shaping moved no point"
    return "its details changed no pixel"


def method_panel(method: str, result: CloneResult, image: np.ndarray, same: dict[str, str]) -> np.ndarray:
    """A method's panel: its letter and title (lambda_k for the elastic model's), and the panel it equals, and why."""
    lam = "" if result.lambda_k is None else f", lambda_k {result.lambda_k:g}"
    note = f"= {letter(same[method])}: {why_same(method, same[method], result)}" if method in same else ""
    return panel(image, f"{letter(method)} {BY_NAME[method].title}{lam}", note)


def difference_panel(a: np.ndarray, b: np.ndarray, caption: str) -> np.ndarray:
    """``a`` minus ``b`` (:func:`~exprclone.evaluation.panels.difference`), saying so where they are equal."""
    equal = np.array_equal(a, b)
    return panel(difference(a, b), caption, "zero everywhere" if equal else "", "no difference: the two are equal" if equal else "")


def equal_words(results: dict[str, CloneResult], same: dict[str, str]) -> np.ndarray:
    """The panel that lists which of Fig. 11's panels are equal, and why."""
    said = [f"{letter(m)} = {letter(e)}: {why_same(m, e, results[m])}." for m, e in same.items()]
    return words("Equal panels", said or ["None: every method changed the image."])


def sheet(paper: dict[str, CloneResult], images: Sequence[np.ndarray], default: dict[str, CloneResult] | None = None) -> np.ndarray:
    """The rows of the module docstring as one RGB image.

    Parameters
    ----------
    paper : dict of str to CloneResult
        All seven methods by the paper's stages (:func:`figure_request`'s first :class:`Run`).
    images : sequence of ndarray of shape (H, W, 3)
        The three photos, in the order of :data:`exprclone.roles.ROLES`.
    default : dict of str to CloneResult, optional
        The seven by this project's default (``retarget``), for the last row.
    """
    landmarks = paper[FIG11[0]].landmarks
    box, src_box = face_box(landmarks[TARGET_NEUTRAL], images[2].shape), face_box(landmarks[SOURCE_EXPRESSION], images[1].shape)
    crop = {m: r.image[box] for m, r in paper.items()}
    same = same_as(paper)
    elastic = paper["e+md"]
    rows = [
        [panel(images[2][box], "target, neutral")]
        + [method_panel(m, paper[m], crop[m], same) for m in FIG11]
        + [panel(images[1][src_box], "(h) source expression")],
        [words("Fig. 12", ROW_WORDS["Fig. 12"]), equal_words(paper, same)]
        + [difference_panel(crop[a], crop[b], f"{letter(a)} - {letter(b)}") for a, b in FIG12]
        + [panels.db_plot(elastic.db_curve)],
        [words("Fig. 13", ROW_WORDS["Fig. 13"]), words("lambda_k", lambda_words(elastic))]
        + [difference_panel(crop[a], crop[b], f"{letter(a)} - {letter(b)}") for a, b in FIG13]
        + [words("Why this lambda_k", terms_words(elastic))],
    ]
    if default is not None:
        own = {m: r.image[box] for m, r in default.items()}
        rows.append(
            [words("This project's default", ROW_WORDS["This project's default"])]
            + [method_panel(m, default[m], own[m], same_as(default)) for m in FIG11]
            + [difference_panel(own["e+md"], crop["e+md"], "(g) default - (g) paper")]
        )
    said = "; last row: this project's default (retarget on)" if default is not None else ""
    return panels.grid(rows, f"Zhang, Lin et al.'s Figs. 11-13 on these photos, by the paper's stages (retarget off){said}")


def fig19(results: dict[str, CloneResult], target_neutral: np.ndarray, source_expression: np.ndarray) -> np.ndarray:
    """The paper's Figs. 19-20 (and 21) as one row: (a) the target's neutral face, (b) the result of the global warp
    (RBF, or landmarks given by another method), (c) the elastic model on (b), (d) the source's expression; then
    (c) - (b) and the DB curve of (c).

    Parameters
    ----------
    results : dict of str to CloneResult
        The methods of :data:`FIG19`, made with the global warp to show.
    target_neutral, source_expression : ndarray of shape (H, W, 3)
    """
    gl, el = (results[m] for m in FIG19)
    box = face_box(gl.landmarks[TARGET_NEUTRAL], target_neutral.shape)
    src_box = face_box(gl.landmarks[SOURCE_EXPRESSION], source_expression.shape)
    name = GLOBAL_NAMES[gl.options.global_stage]
    lam = "chosen" if el.lambda_k is None else f"{el.lambda_k:g}"
    row = [
        panel(target_neutral[box], "(a) target, neutral"),
        panel(gl.image[box], f"(b) global warp: {name}"),
        panel(el.image[box], f"(c) elastic model on (b), lambda_k {lam}"),
        panel(source_expression[src_box], "(d) source expression"),
        difference_panel(el.image[box], gl.image[box], "(c) - (b)"),
        panels.db_plot(el.db_curve),
    ]
    return panels.grid([row])


def fig16(results: dict[str, CloneResult], target_neutral: np.ndarray, source_expression: np.ndarray) -> np.ndarray:
    """The paper's Fig. 16 or 17 as one row: (a) the target's neutral face, the methods of :data:`FIG16` from (b) on,
    then the source's expression; then the last method's (E+MD's) difference to Song et al.'s result, and its DB curve.
    A method on a global warp other than the paper's says so (Fig. 17's ``on VTC``).

    Parameters
    ----------
    results : dict of str to CloneResult
        The methods of one of :data:`FIG16`'s figures, in its order.
    target_neutral, source_expression : ndarray of shape (H, W, 3)
    """
    methods = list(results)
    first = results[methods[0]]
    box = face_box(first.landmarks[TARGET_NEUTRAL], target_neutral.shape)
    src_box = face_box(first.landmarks[SOURCE_EXPRESSION], source_expression.shape)
    letters = "abcdefgh"
    row = [panel(target_neutral[box], "(a) target, neutral")]
    for k, (method, r) in enumerate(results.items(), 1):
        warp = r.options.global_stage
        on = "" if warp == GLOBAL_WARPS[0] or BY_NAME[method].warp is not None else f" on {warp.upper()}"
        row.append(panel(r.image[box], f"({letters[k]}) {CAPTIONS[method]}{on}"))
    row.append(panel(source_expression[src_box], f"({letters[len(methods) + 1]}) source expression"))
    own = next(k for k, m in enumerate(methods) if BY_NAME[m].warp is not None)  # Song et al.'s, on its own warp
    last, song = results[methods[-1]], results[methods[own]]
    row.append(difference_panel(last.image[box], song.image[box], f"({letters[len(methods)]}) - ({letters[own + 1]})"))
    row.append(panels.db_plot(last.db_curve))
    return panels.grid([row])


def figure_request(figure: str, options: Options, global_warp_asked: bool) -> tuple[Run, ...]:
    """The clones ``figure`` (one of :data:`FIGURES`) needs, with the options given: Fig. 11 by the paper's stages
    (``retarget`` off), then, with ``retarget`` on, by this project's default too (:func:`sheet`); Fig. 19 shows the RBF
    transfer unless a global warp was asked for (``global_warp_asked``) or its landmarks are given; Fig. 17 shows
    Song et al.'s global warp (:data:`SONG_WARP`), and no other (ExprCloneError). A figure shows one face: of a photo
    of several, the largest unless ``faces`` chose others (the first of them is shown)."""
    if options.faces == "all":
        options = replace(options, faces="largest")
    if figure == FIGURES[0]:
        paper = Run(FIG11, replace(options, retarget=False))
        return (paper, Run(FIG11, options)) if options.retarget else (paper,)
    if figure in FIG16:
        if figure == "17" and (options.global_landmarks is not None or options.global_warp not in (GLOBAL_WARPS[0], SONG_WARP)):
            subject = "global_landmarks" if options.global_landmarks is not None else "global_warp"
            raise ExprCloneError(subject, f"Fig. 17 shows the methods on Song et al.'s global warp, {SONG_WARP}: drop {subject}")
        return (Run(FIG16[figure], replace(options, global_warp=SONG_WARP) if figure == "17" else options),)
    if not global_warp_asked and options.global_landmarks is None:
        options = replace(options, global_warp="rbf")
    return (Run(FIG19, options),)


def one_face(results: dict[str, CloneResult], images: Sequence[np.ndarray]) -> tuple[dict[str, CloneResult], Sequence[np.ndarray]]:
    """The results and the three photos of the face a figure shows: of a photo of several faces, the first one cloned
    (its own results, and its region as the target's photo); else as they are. ExprCloneError when none was cloned."""
    faces = next(iter(results.values())).face_results
    if not faces:
        return results, images
    cloned = [k for k, face in enumerate(faces) if face.result is not None]
    if not cloned:
        raise ExprCloneError("faces", "no face of the photo could be cloned, and a figure shows one")
    x0, y0, x1, y1 = faces[cloned[0]].region
    own = {method: result.face_results[cloned[0]].result for method, result in results.items()}
    return {m: r for m, r in own.items() if r is not None}, (images[0], images[1], images[2][y0:y1, x0:x1])


def draw(figure: str, runs: Sequence[dict[str, CloneResult]], images: Sequence[np.ndarray]) -> np.ndarray:
    """``figure`` (one of :data:`FIGURES`) of the results of each of :func:`figure_request`'s runs on the three photos
    (of the one face it shows, :func:`one_face`)."""
    shown = [one_face(results, images) for results in runs]
    first, photos = shown[0]
    if figure == FIGURES[0]:
        return sheet(first, photos, shown[1][0] if len(shown) > 1 else None)
    return (fig16 if figure in FIG16 else fig19)(first, photos[2], photos[1])


def summary(figure: str, runs: Sequence[dict[str, CloneResult]]) -> str:
    """What ``figure``'s sheet shows, in a line (``exprclone compare`` prints it): its methods, or the global warp the
    elastic model refines, and the lambda_k the DB metric chose."""
    results = runs[0]
    chosen = next((r.lambda_k for r in reversed(results.values()) if r.lambda_k is not None), None)
    lam = "" if chosen is None else f", lambda_k={chosen:g}"
    if figure == FIGURES[-1]:
        return f"Fig. {figure}, the elastic model on global warp {results[FIG19[0]].options.global_stage}{lam}"
    if figure == FIGURES[0]:
        also = ", and this project's default (retarget) below" if len(runs) > 1 else ""
        return f"Fig. {figure}, {len(results)} methods by the paper's stages{lam}{also}"
    return f"Fig. {figure}, {len(results)} methods{lam}"
