"""The paper's Figs. 11-13 and the DB curve as one labelled sheet (``exprclone compare``).

Row 1 (Fig. 11): the seven methods (a)-(g) and the source expression (h).
Row 2 (Fig. 12): the differences of (b)-(g) to the global result (a).
Row 3 (Fig. 13): (b)-(a), (c)-(a), (d)-(a), (e)-(d), (f)-(d), (g)-(f), then the DB metric
over lambda_k with the chosen value marked.

A difference image is the absolute luminance difference of two results, normalised so
that its largest value is 255 ("normalizing the values to the range 0~255", Sec. IV).

:func:`fig19` draws the paper's Figs. 19-21 instead: the elastic model on the result of
another global warp (``exprclone compare --figure 19``); :func:`fig16` its Figs. 16-17, E+MD beside Song et
al.'s method (``--figure 16``), and the elastic model and E+MD on Song et al.'s global warp (``--figure 17``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import cv2
import numpy as np

from ..errors import ExprCloneError
from ..geometry.db_metric import DBCurve
from ..imaging import raster
from ..methods import BY_NAME, FIG11, FIGURES, TABLE
from ..options import GIVEN, GLOBAL_WARPS, Options
from ..pipeline.result import CloneResult
from ..roles import SOURCE_EXPRESSION, TARGET_NEUTRAL

CELL = 320
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
FIG13 = (
    ("local", "global"),
    ("elastic", "global"),
    ("global+eri", "global"),
    ("local+eri", "global+eri"),
    ("elastic+eri", "global+eri"),
    ("e+md", "elastic+eri"),
)


def face_box(landmarks: np.ndarray, shape: tuple[int, ...]) -> tuple[slice, slice]:
    """A square box around the face with a margin, inside the image."""
    centre = (landmarks.min(0) + landmarks.max(0)) / 2
    half = 0.7 * (landmarks.max(0) - landmarks.min(0)).max()
    x0, y0 = np.maximum(0, np.floor(centre - half)).astype(int)
    x1, y1 = np.minimum((shape[1], shape[0]), np.ceil(centre + half)).astype(int)
    return slice(y0, y1), slice(x0, x1)


def difference(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Absolute luminance difference of two RGB images, normalised to 0-255, as RGB."""
    d = np.abs(raster.luma(a).astype(np.float32) - raster.luma(b))
    d = (255 * d / max(float(d.max()), 1e-6)).astype(np.uint8)
    return cv2.cvtColor(d, cv2.COLOR_GRAY2RGB)


def cell(image: np.ndarray, text: str) -> np.ndarray:
    """An image scaled to the cell size with a caption bar."""
    out = cv2.resize(image, (CELL, CELL), interpolation=cv2.INTER_AREA)
    cv2.rectangle(out, (0, 0), (CELL, 24), (255, 255, 255), -1)
    cv2.putText(out, text, (5, 17), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (0, 0, 0), 1, cv2.LINE_AA)
    return out


def db_plot(curve: DBCurve) -> np.ndarray:
    """The DB metric over the candidate lambda_k (evenly spaced), the chosen one in red."""
    img = np.full((CELL, CELL, 3), 255, np.uint8)
    left, right, top, bottom = 40, CELL - 12, 40, CELL - 40
    db = curve.db
    lo, hi = float(db.min()), float(db.max())
    span = max(hi - lo, 1e-9)
    xs = np.linspace(left, right, len(db))
    ys = bottom - (db - lo) / span * (bottom - top)
    cv2.line(img, (left, bottom), (right, bottom), (0, 0, 0), 1)
    cv2.line(img, (left, top), (left, bottom), (0, 0, 0), 1)
    cv2.polylines(img, [np.stack([xs, ys], 1).round().astype(np.int32)], False, (40, 40, 200), 2, cv2.LINE_AA)
    for x, lam in zip(xs, curve.lambdas):
        label = "inf" if np.isinf(lam) else f"{lam:g}"
        cv2.putText(img, label, (int(x) - 8, bottom + 14 + 12 * (int(x) % 2)), cv2.FONT_HERSHEY_SIMPLEX, 0.3, (0, 0, 0), 1, cv2.LINE_AA)
    k = int(np.flatnonzero(curve.lambdas == curve.best)[0])
    cv2.circle(img, (int(xs[k]), int(ys[k])), 6, (220, 0, 0), -1)
    cv2.putText(img, f"DB (Eq. 7); lambda_k = {curve.best:g}", (8, 18), cv2.FONT_HERSHEY_SIMPLEX, 0.45, (0, 0, 0), 1, cv2.LINE_AA)
    cv2.putText(img, f"{hi:.3f}", (2, top + 4), cv2.FONT_HERSHEY_SIMPLEX, 0.3, (0, 0, 0), 1, cv2.LINE_AA)
    cv2.putText(img, f"{lo:.3f}", (2, bottom), cv2.FONT_HERSHEY_SIMPLEX, 0.3, (0, 0, 0), 1, cv2.LINE_AA)
    return img


def sheet(results: dict[str, CloneResult], source_expression: np.ndarray) -> np.ndarray:
    """The three rows of the module docstring as one RGB image.

    Parameters
    ----------
    results : dict of str to CloneResult
        All seven methods (:func:`exprclone.clone_methods`).
    source_expression : ndarray of shape (H, W, 3)
    """
    letters = {m.name: m.panel for m in TABLE}
    lm = results["global"].landmarks
    box = face_box(lm[TARGET_NEUTRAL], results["global"].image.shape)
    src_box = face_box(lm[SOURCE_EXPRESSION], source_expression.shape)
    crop = {m: r.image[box] for m, r in results.items()}
    row1 = [cell(crop[m], f"({letters[m]}) {m}") for m in FIG11] + [cell(source_expression[src_box], "(h) source expression")]
    row2 = [cell(difference(crop[m], crop["global"]), f"Fig. 12: ({letters[m]}) - (a)") for m in FIG11[1:]]
    row3 = [cell(difference(crop[a], crop[b]), f"Fig. 13: ({letters[a]}) - ({letters[b]})") for a, b in FIG13]
    blank = np.full((CELL, CELL, 3), 255, np.uint8)
    row2 += [blank, blank]
    row3 += [db_plot(results["e+md"].db_curve) if results["e+md"].db_curve is not None else blank, blank]
    return np.vstack([np.hstack(row1), np.hstack(row2), np.hstack(row3)])


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
        cell(target_neutral[box], "(a) target, neutral"),
        cell(gl.image[box], f"(b) global warp: {name}"),
        cell(el.image[box], f"(c) elastic model on (b), lambda_k = {lam}"),
        cell(source_expression[src_box], "(d) source expression"),
        cell(difference(el.image[box], gl.image[box]), "(c) - (b)"),
        db_plot(el.db_curve) if el.db_curve is not None else np.full((CELL, CELL, 3), 255, np.uint8),
    ]
    return np.hstack(row)


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
    row = [cell(target_neutral[box], "(a) target, neutral")]
    for k, (method, r) in enumerate(results.items(), 1):
        warp = r.options.global_stage
        on = "" if warp == GLOBAL_WARPS[0] or BY_NAME[method].warp is not None else f" on {warp.upper()}"
        row.append(cell(r.image[box], f"({letters[k]}) {CAPTIONS[method]}{on}"))
    row.append(cell(source_expression[src_box], f"({letters[len(methods) + 1]}) source expression"))
    own = next(k for k, m in enumerate(methods) if BY_NAME[m].warp is not None)  # Song et al.'s, on its own warp
    last, song = results[methods[-1]], results[methods[own]]
    row.append(cell(difference(last.image[box], song.image[box]), f"({letters[len(methods)]}) - ({letters[own + 1]})"))
    curve = last.db_curve
    row.append(db_plot(curve) if curve is not None else np.full((CELL, CELL, 3), 255, np.uint8))
    return np.hstack(row)


def figure_request(figure: str, options: Options, global_warp_asked: bool) -> tuple[tuple[str, ...], Options]:
    """The methods and the clone options that ``figure`` (one of :data:`FIGURES`) needs: Fig. 19 shows the RBF
    transfer unless a global warp was asked for (``global_warp_asked``) or its landmarks are given; Fig. 17 shows
    Song et al.'s global warp (:data:`SONG_WARP`), and no other (ExprCloneError). A figure shows one face: of a photo
    of several, the largest unless ``faces`` chose others (the first of them is shown)."""
    if options.faces == "all":
        options = replace(options, faces="largest")
    if figure == FIGURES[0]:
        return FIG11, options
    if figure in FIG16:
        if figure == "17" and (options.global_landmarks is not None or options.global_warp not in (GLOBAL_WARPS[0], SONG_WARP)):
            subject = "global_landmarks" if options.global_landmarks is not None else "global_warp"
            raise ExprCloneError(subject, f"Fig. 17 shows the methods on Song et al.'s global warp, {SONG_WARP}: drop {subject}")
        return FIG16[figure], replace(options, global_warp=SONG_WARP) if figure == "17" else options
    if not global_warp_asked and options.global_landmarks is None:
        options = replace(options, global_warp="rbf")
    return FIG19, options


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


def draw(figure: str, results: dict[str, CloneResult], images: Sequence[np.ndarray]) -> np.ndarray:
    """``figure`` (one of :data:`FIGURES`) of the results of :func:`figure_request`'s methods on the three photos (of
    the one face it shows, :func:`one_face`)."""
    results, images = one_face(results, images)
    if figure == FIGURES[0]:
        return sheet(results, images[1])
    return (fig16 if figure in FIG16 else fig19)(results, images[2], images[1])


def summary(figure: str, results: dict[str, CloneResult]) -> str:
    """What ``figure``'s sheet shows, in a line (``exprclone compare`` prints it): its methods, or the global warp the
    elastic model refines, and the lambda_k the DB metric chose."""
    chosen = next((r.lambda_k for r in reversed(results.values()) if r.lambda_k is not None), None)
    lam = "" if chosen is None else f", lambda_k={chosen:g}"
    if figure == FIGURES[-1]:
        return f"Fig. {figure}, the elastic model on global warp {results[FIG19[0]].options.global_stage}{lam}"
    return f"Fig. {figure}, {len(results)} methods{lam}"
