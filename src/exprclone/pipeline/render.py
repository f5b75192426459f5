"""The second half of Fig. 5, what each image of a prepared clone costs: FI, the ERI in its geometry, the MD model and the
mouth interior, as stages over the data a :class:`~exprclone.pipeline.cloner.Prepared` holds.

:func:`render` runs them for each method asked: FI for each shape (:func:`fi`), the ERI (or Song et al.'s mesh
image) for each shape whose methods have one (:func:`ratio`), then each method's result (:func:`result`) with its
detail stages (:func:`details`). What each method runs is read from its row of :data:`exprclone.methods.TABLE`; how
much of the expression, and where, from the :class:`~exprclone.geometry.weights.Transfer` of the options' strengths
(:func:`transfer`).
"""

from __future__ import annotations

import concurrent.futures
import functools
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..details import eri, muscle
from ..details.mesh_image import RATIOS
from ..details.stage import ExpressionPhoto, Ratio
from ..geometry.weights import Transfer
from ..imaging import piecewise
from ..imaging.warpers import IMAGE_WARPERS
from ..landmarks import lips
from ..methods import BY_NAME, Method
from ..mouth import paste
from ..options import Options
from ..roles import SOURCE_EXPRESSION, SOURCE_NEUTRAL, TARGET_NEUTRAL
from .faces import Faces
from .result import CloneResult
from .stages import Shape, SourceExpression, Synthesis


@dataclass(frozen=True)
class Rendered:
    """The target photo warped to one shape (FI): the image, the control points it was warped to, and how many were unfolded."""

    image: np.ndarray
    control: np.ndarray
    unfolded: int


def transfer(faces: Faces, options: Options) -> Transfer:
    """How much of the expression ``options`` transfer, and where, on the target's face (:class:`~exprclone.geometry.weights.Transfer`)."""
    return Transfer.build(options.region_strengths, options.strength_shading, faces.t_neu, faces.target_image.shape, faces.layout)


def geometry(faces: Faces, points: np.ndarray, transfer: Transfer) -> tuple[np.ndarray, int]:
    """FI's control points for ``points``, their motion scaled by ``transfer`` (:mod:`exprclone.geometry.weights`;
    inner lips made valid, fold-overs relaxed but for the landmarks held by a strength of 0), and how many were unfolded."""
    mesh = faces.mesh
    moved = transfer.landmarks(points)
    valid = lips.uncross(moved, faces.layout)
    held = None if transfer.motion is None else np.flatnonzero(transfer.motion == 0)  # a region at strength 0 stays put
    if held is not None:
        valid[held] = moved[held]  # (uncross judges the lips in the face's axes, which the other regions turn)
    control, unfolded = piecewise.unfold(mesh.points, mesh.control_points(valid), mesh.triangles, mesh.n_moving, held)
    return control, unfolded


def fi(faces: Faces, control: np.ndarray, unfolded: int, image_warp: str) -> Rendered:
    """FI: the target photo warped to its control points (:func:`geometry`) by the image warp named ``image_warp``
    (:data:`~exprclone.imaging.warpers.IMAGE_WARPERS`)."""
    return Rendered(IMAGE_WARPERS[image_warp](faces.target_image, faces.mesh.points, control, faces.mesh), control, unfolded)


def ratio(faces: Faces, control: np.ndarray, photo: ExpressionPhoto, transfer: Transfer, image_warp: str, kind: str = "eri") -> Ratio:
    """The ERI and its tint: both source photos warped to the geometry of FI (its ``control`` points, Liu et al.), or the
    mesh image made of them (Song et al.: ``kind``, :data:`exprclone.details.mesh_image.RATIOS`), scaled by ``transfer``."""
    warp = IMAGE_WARPERS[image_warp]
    shape = faces.target_image.shape
    made = RATIOS[kind](faces.mesh, control, shape, faces.ratio_faces, faces.source_neutral_ctrl, photo, faces.layout, warp)
    return Ratio(transfer.ratio(made.eri, made.box), transfer.tint(made.tint, made.box), made.box)


def details(
    faces: Faces,
    method: Method,
    expression: SourceExpression,
    rendered: Rendered,
    ratio: Ratio,
    mouth: bool,
    transfer: Transfer,
) -> tuple[np.ndarray, dict[str, Any]]:
    """The illumination details on FI: the ERI, weighted by the MD mask (Eqs. 9-11) for ``e+md``; then the mouth interior.

    Returns
    -------
    image : ndarray of shape (H, W, 3), uint8
    details : dict
        The :class:`CloneResult` fields they fill: ``eri``, ``muscle_mask``,
        ``muscle_strengths``, ``mouth_mask``.
    """
    layout, fi_image = faces.layout, rendered.image
    final = rendered.control[: faces.mesh.n_landmarks]
    ratio_map, box = ratio.eri, ratio.box
    found: dict[str, Any] = {"eri": ratio_map}
    importance: np.ndarray | float = 1.0
    if method.md:
        h = muscle.strengths(faces.s_neu, expression.still, layout)
        centres, radii = muscle.areas(final, layout)
        importance = muscle.importance_mask(faces.target_image.shape[:2], centres, radii, h, muscle.mask_step(radii))
        found.update(muscle_mask=importance, muscle_strengths=h)
    image = fi_image.copy()
    image[box] = eri.apply_details(
        fi_image[box], ratio_map[box], importance if isinstance(importance, float) else importance[box], ratio.tint
    )
    if mouth:  # the photos are measured for the paste's match only when there is a paste
        image, found["mouth_mask"] = paste.fill_interior(
            image, final, expression.image, expression.points, lambda: faces.mouth_reference, layout, transfer.paste, in_place=True
        )
    return image, found


def result(
    faces: Faces,
    method: Method,
    expression: SourceExpression,
    shapes: Mapping[str, Shape],
    rendered: Rendered,
    ratio: Ratio | None,
    options: Options,
    transfer: Transfer,
) -> CloneResult:
    """One method's result: FI, then its detail stages (:func:`details`) if it has any (then ``ratio`` is its ERI)."""
    final = rendered.control[: faces.mesh.n_landmarks]
    landmarks = {SOURCE_NEUTRAL: faces.s_neu, SOURCE_EXPRESSION: expression.points, TARGET_NEUTRAL: faces.t_neu}
    landmarks.update({name: shapes[method.key(name)].points for name in ("global", "local", method.shape)}, final=final)
    if ratio is None:
        image, found = rendered.image, dict[str, Any]()
    else:
        image, found = details(faces, method, expression, rendered, ratio, options.mouth, transfer)
    shape = shapes[method.stage]
    return CloneResult(
        image,
        method.name,
        landmarks,
        shape.lambda_k,
        shape.db_curve,
        unfolded_points=rendered.unfolded,
        options=options.ran_by(method),
        **found,
    )


def synthesized(
    faces: Faces, expression: SourceExpression, photo: Callable[[], ExpressionPhoto], image_warp: str, points: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The image E+MD synthesizes at the landmarks ``points``, and the control points it was warped to: FI there, the
    ERI weighted by the MD mask, the mouth's interior, the whole expression whatever the options' strengths (what the
    DB metric's candidates are carried from, :mod:`exprclone.geometry.db_metric`). ``photo`` gives the expression photo
    as the ERI takes it."""
    whole = Transfer(faces.t_neu)
    control, unfolded = geometry(faces, points, whole)
    made = ratio(faces, control, photo(), whole, image_warp)
    image, _ = details(faces, BY_NAME["e+md"], expression, fi(faces, control, unfolded, image_warp), made, True, whole)
    return image, control


def synthesis(faces: Faces, expression: SourceExpression, image_warp: str, photo: Callable[[], ExpressionPhoto] | None = None) -> Synthesis:
    """:func:`synthesized` for one expression, as the elastic stage takes it (:data:`exprclone.pipeline.stages.Synthesis`):
    ``photo`` gives its expression photo as the ERI takes it (one made beside the stages), or it is made when first asked."""
    made = photo or functools.cache(lambda: faces.expression_photo(expression.image, expression.points, expression.still))
    return functools.partial(synthesized, faces, expression, made, image_warp)


def render(
    faces: Faces,
    methods: tuple[Method, ...],
    expression: SourceExpression,
    shapes: Mapping[str, Shape],
    photo: ExpressionPhoto | None,
    options: Options,
    transfer: Transfer,
) -> dict[str, CloneResult]:
    """Each method's image: FI for each shape (by :attr:`exprclone.methods.Method.stage`), the ratio each method's
    details apply in its geometry (:attr:`exprclone.methods.Method.ratio`; ``photo``: the expression photo as the ratios
    take it, None when no method has one; made on another core while FI is warped: it needs FI's geometry alone), then
    each method's :func:`result`."""
    kinds = {m.stage for m in methods}
    shaded = {(m.stage, m.ratio) for m in methods if m.ratio is not None}
    placed = {kind: geometry(faces, shapes[kind].points, transfer) for kind in kinds}
    with concurrent.futures.ThreadPoolExecutor(1) as beside:
        made = (
            {}
            if photo is None
            else {(k, r): beside.submit(ratio, faces, placed[k][0], photo, transfer, options.image_warp, r) for k, r in shaded}
        )
        rendered = {kind: fi(faces, *placed[kind], options.image_warp) for kind in kinds}
        ratios: dict[tuple[str, str | None], Ratio] = {key: future.result() for key, future in made.items()}
    return {
        m.name: result(faces, m, expression, shapes, rendered[m.stage], ratios.get((m.stage, m.ratio)), options, transfer) for m in methods
    }
