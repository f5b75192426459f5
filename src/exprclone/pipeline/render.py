"""The second half of Fig. 5, what each image of a prepared clone costs: FI, the ERI in its geometry, the MD model and the
mouth interior, as stages over the data a :class:`~exprclone.pipeline.cloner.Prepared` holds.

:func:`render` runs them for each method asked: FI for each shape (:func:`fi`); in FI's geometry, on another core while
FI is warped, what the methods' details lay on it (:class:`Layers`: the ERI or Song et al.'s mesh image, :func:`ratio`;
the MD mask, :func:`md_mask`; the mouth's patch, :func:`mouth_patch`); then each method's result (:func:`result`) with
its detail stages (:func:`details`). What each method runs is read from its row of :data:`exprclone.methods.TABLE`; how
much of the expression, and where, from the :class:`~exprclone.geometry.weights.Transfer` of the options' strengths
(:func:`transfer`).
"""

from __future__ import annotations

import collections
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
from ..methods import Method
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


def details(faces: Faces, rendered: Rendered, layers: Layers, *, own: bool = False) -> tuple[np.ndarray, dict[str, Any]]:
    """The illumination details on FI: the ERI, weighted by the MD mask (Eqs. 9-11) for ``e+md``; then the mouth
    interior (:class:`Layers`). ``own``: FI's image is this result's alone, and is drawn on, not copied.

    Returns
    -------
    image : ndarray of shape (H, W, 3), uint8
    details : dict
        The :class:`CloneResult` fields they fill: ``eri``, ``muscle_mask``,
        ``muscle_strengths``, ``mouth_mask``.
    """
    ratio, mask, mouth = layers.ratio, layers.mask, layers.mouth
    fi_image, ratio_map, box = rendered.image, ratio.eri, ratio.box
    found: dict[str, Any] = {"eri": ratio_map}
    importance: np.ndarray | float = 1.0
    if mask is not None:
        importance, h = mask
        found.update(muscle_mask=importance, muscle_strengths=h)
    image = fi_image if own else fi_image.copy()
    image[box] = eri.apply_details(
        fi_image[box], ratio_map[box], importance if isinstance(importance, float) else importance[box], ratio.tint
    )
    image, found["mouth_mask"] = paste.blend(image, *mouth, in_place=True) if mouth else (image, None)
    return image, found


def md_mask(faces: Faces, expression: SourceExpression, control: np.ndarray) -> Mask:
    """The MD model's detail-importance mask at FI's ``control`` points (Eqs. 10-11,
    :func:`exprclone.details.muscle.importance_mask`) and its areas' strengths ``h``: it needs FI's geometry alone."""
    final, layout = control[: faces.mesh.n_landmarks], faces.layout
    h = muscle.strengths(faces.s_neu, expression.still, layout)
    centres, radii = muscle.areas(final, layout)
    return muscle.importance_mask(faces.target_image.shape[:2], centres, radii, h, muscle.mask_step(radii)), h


#: the MD model's mask over the target photo, ``(H, W)``, and its areas' strengths, ``(A,)``.
Mask = tuple[np.ndarray, np.ndarray]


def mouth_patch(faces: Faces, expression: SourceExpression, control: np.ndarray, transfer: Transfer) -> paste.Patch | None:
    """The source's mouth interior made ready to paste at FI's ``control`` points (:func:`exprclone.mouth.paste.patch`):
    it needs FI's geometry, not its image. The photos are measured for the paste's match only when there is a paste."""
    final = control[: faces.mesh.n_landmarks]
    reference = lambda: faces.mouth_reference  # noqa: E731
    return paste.patch(faces.target_image.shape, final, expression.image, expression.points, reference, faces.layout, transfer.paste)


def mouth_grain(faces: Faces, expression: SourceExpression, control: np.ndarray) -> Callable[[], tuple[float, np.ndarray]]:
    """The source's grain the mouth's patch at FI's ``control`` points is matched to, when asked, once
    (:func:`exprclone.mouth.paste.source_grain`): it needs neither the patch nor FI's image."""
    final = control[: faces.mesh.n_landmarks]
    return functools.cache(lambda: paste.source_grain(expression.image, expression.points, faces.mouth_reference, final, faces.layout))


#: the mouth interior a result is given: its patch (None: none) and the source's grain it is matched to.
Mouth = tuple[paste.Patch | None, Callable[[], tuple[float, np.ndarray]]]


@dataclass(frozen=True)
class Layers:
    """What a method's details lay on FI, made of FI's geometry alone (on another core while FI is warped).

    Attributes
    ----------
    ratio : Ratio
        The ERI (or Song et al.'s mesh image) and its tint (:func:`ratio`).
    mask : Mask or None
        The MD model's mask and strengths (:func:`md_mask`); None: the ERI is laid whole (Liu et al.).
    mouth : Mouth or None
        The mouth interior (:func:`mouth_patch`, :func:`mouth_grain`); None: none is pasted.
    """

    ratio: Ratio
    mask: Mask | None
    mouth: Mouth | None


def result(
    faces: Faces,
    method: Method,
    expression: SourceExpression,
    shapes: Mapping[str, Shape],
    rendered: Rendered,
    layers: Layers | None,
    options: Options,
    own: bool = False,
) -> CloneResult:
    """One method's result: FI, then its detail stages (:func:`details`, ``own`` as it takes it) if it has any (their
    ``layers``)."""
    final = rendered.control[: faces.mesh.n_landmarks]
    landmarks = {SOURCE_NEUTRAL: faces.s_neu, SOURCE_EXPRESSION: expression.points, TARGET_NEUTRAL: faces.t_neu}
    landmarks.update({name: shapes[method.key(name)].points for name in ("global", "local", method.shape)}, final=final)
    if layers is None:
        image, found = rendered.image, dict[str, Any]()
    else:
        image, found = details(faces, rendered, layers, own=own)
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
    layers = Layers(
        made, md_mask(faces, expression, control), (mouth_patch(faces, expression, control, whole), mouth_grain(faces, expression, control))
    )
    image, _ = details(faces, fi(faces, control, unfolded, image_warp), layers, own=True)
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
    """Each method's image: FI for each shape (by :attr:`exprclone.methods.Method.stage`), then each method's
    :func:`result`, its details' :class:`Layers` made in FI's geometry on another core while FI is warped: the ratio
    (:attr:`exprclone.methods.Method.ratio`; ``photo``: the expression photo as the ratios take it, None when no method
    has one), the mouth's patch, the MD mask; the source's grain the patch needs is measured on this core after FI."""
    kinds = {m.stage for m in methods}
    shaded = {(m.stage, m.ratio) for m in methods if m.ratio is not None}
    placed = {kind: geometry(faces, shapes[kind].points, transfer) for kind in kinds}
    with concurrent.futures.ThreadPoolExecutor(1) as beside:
        warp = options.image_warp
        ratios: dict[tuple[str, str | None], concurrent.futures.Future[Ratio]] = (
            {} if photo is None else {(k, r): beside.submit(ratio, faces, placed[k][0], photo, transfer, warp, r) for k, r in shaded}
        )
        pasting = {k for k, _ in ratios} if options.mouth else set()
        patches = {k: beside.submit(mouth_patch, faces, expression, placed[k][0], transfer) for k in pasting}
        masks = {m.stage: beside.submit(md_mask, faces, expression, placed[m.stage][0]) for m in methods if m.md and photo is not None}
        rendered = {kind: fi(faces, *placed[kind], warp) for kind in kinds}
        grains = {k: mouth_grain(faces, expression, placed[k][0]) for k in pasting}
        for k in pasting:  # measured on this core while the patches are made on the other, if one will be
            if paste.opened(placed[k][0][: faces.mesh.n_landmarks], expression.points, faces.layout, transfer.paste):
                grains[k]()
        layers = {
            m.name: Layers(
                ratios[m.stage, m.ratio].result(),
                masks[m.stage].result() if m.md else None,
                (patches[m.stage].result(), grains[m.stage]) if m.stage in pasting else None,
            )
            for m in methods
            if (m.stage, m.ratio) in ratios
        }
    users = collections.Counter(m.stage for m in methods)
    return {
        m.name: result(faces, m, expression, shapes, rendered[m.stage], layers.get(m.name), options, users[m.stage] == 1) for m in methods
    }
