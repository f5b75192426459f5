"""The stages of Fig. 5 as tables of functions, looked up by name: the global warps, the shape stages, the image warps.

A :class:`~exprclone.cloner.Cloner` runs them: each shape stage
(:data:`SHAPE_STAGES`) computes its landmarks from the ones before it; the global
stage by the global warp the options name (:data:`GLOBAL_WARPERS`, keyed by
:attr:`exprclone.options.Options.global_warp`) unless they give GI; FI and the ERI by the image warp they
name (:data:`IMAGE_WARPERS`, keyed by :attr:`exprclone.options.Options.image_warp`).
The names themselves, and what a user may choose, are :mod:`exprclone.options`'.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

import numpy as np

from . import elastic, eri, geometry, global_warp, local_warp, metric, shading, tps, warp
from .layout import Layout
from .models import default_eigenfaces

if TYPE_CHECKING:
    from .cloner import Cloner

#: the face box the ERI is computed in: the moving control points' box grown by this many inter-ocular distances.
ERI_MARGIN = 0.5


@dataclass(frozen=True)
class Expression:
    """One source expression to clone (:meth:`Cloner.expression <exprclone.cloner.Cloner.expression>` makes it).

    Attributes
    ----------
    image : ndarray of shape (H, W, 3), uint8 RGB
        Its photo.
    points : ndarray of shape (N, 2)
        Its landmarks in the photo, the lips made valid.
    lambda_k : float or str
        The lambda_k asked for.
    moving : ndarray of shape (N, 2)
        The landmarks whose motion from the source's neutral ones the global warps carry:
        ``points`` (the paper), or that motion cleaned (:func:`exprclone.retarget.clean`).
    organs : ndarray of shape (N, 2)
        What local re-shaping gives each organ the height-to-width ratio of (Eqs. 1-2):
        ``points``, the source's own organs (the paper), or the target's organs moved by
        the source (:func:`exprclone.retarget.organ_reference`).
    """

    image: np.ndarray
    points: np.ndarray
    lambda_k: float | str
    moving: np.ndarray
    organs: np.ndarray


@dataclass(frozen=True)
class Shape:
    """What a shape stage gives: landmarks, and for the elastic model the lambda_k used and the DB curve."""

    points: np.ndarray
    lambda_k: float | None = None
    db_curve: metric.DBCurve | None = None


@dataclass(frozen=True)
class Rendered:
    """The target photo warped to one shape (FI): the image, the control points it was warped to, and how many were unfolded."""

    image: np.ndarray
    control: np.ndarray
    unfolded: int


def similarity_warp(cloner: Cloner, expression: Expression) -> np.ndarray:
    """GI of the paper: the source's motion, similarity-aligned, on the target (:func:`global_warp.global_landmarks`)."""
    return global_warp.global_landmarks(cloner.s_neu, expression.moving, cloner.t_neu, cloner.layout)


def rbf_warp(cloner: Cloner, expression: Expression) -> np.ndarray:
    """GI of Seol and Lewis: each landmark's motion by the RBF map's Jacobian (:func:`global_warp.rbf_landmarks`)."""
    return global_warp.rbf_landmarks(cloner.s_neu, expression.moving, cloner.t_neu, cloner.layout, cloner.rbf_jacobians)


#: the global warps by name (:data:`exprclone.options.GLOBAL_WARPS`), each ``(cloner, expression) -> GI landmarks``.
GLOBAL_WARPERS: dict[str, Callable[[Cloner, Expression], np.ndarray]] = {"similarity": similarity_warp, "rbf": rbf_warp}


def global_stage(cloner: Cloner, expression: Expression, shapes: dict[str, Shape]) -> Shape:
    """GI: given from outside, the result of any other method (Fig. 21), else by the global warp of the cloner's
    options (:data:`GLOBAL_WARPERS`)."""
    given = cloner.options.global_landmarks
    return Shape(given if given is not None else GLOBAL_WARPERS[cloner.options.global_warp](cloner, expression))


def local_stage(cloner: Cloner, expression: Expression, shapes: dict[str, Shape]) -> Shape:
    """LI: each organ of GI re-shaped to the expression's organs (:attr:`Expression.organs`), Eqs. (1)-(2)."""
    return Shape(local_warp.local_landmarks(shapes["global"].points, expression.organs, cloner.layout))


def elastic_stage(cloner: Cloner, expression: Expression, shapes: dict[str, Shape]) -> Shape:
    """The elastic model's balance of GI and LI, Eqs. (3)-(6), lambda_k given or chosen by the DB metric, Eqs. (7)-(8)."""
    gl, local = shapes["global"].points, shapes["local"].points
    if expression.lambda_k != "auto":
        chosen = float(expression.lambda_k)
        return Shape(elastic.elastic_landmarks(gl, local, cloner.neighbours, chosen), chosen)
    lambdas = np.array(metric.LAMBDAS)
    candidates = list(elastic.elastic_landmarks(gl, local, cloner.neighbours, lambdas))
    eigenfaces = cloner.eigenfaces or default_eigenfaces()
    curve = metric.choose_lambda(
        cloner.target_image, cloner.mesh, candidates, lambdas, expression.image, expression.points, eigenfaces, cloner.layout
    )
    return Shape(candidates[int(np.flatnonzero(lambdas == curve.best)[0])], curve.best, curve)


#: the shape stages of :data:`exprclone.methods.SHAPES` by name, each computed from the ones before it.
SHAPE_STAGES: dict[str, Callable[[Cloner, Expression, dict[str, Shape]], Shape]] = {
    "global": global_stage,
    "local": local_stage,
    "elastic": elastic_stage,
}


class ImageWarper(Protocol):
    """An image warp of :data:`IMAGE_WARPERS`: ``image`` moved from control points ``src`` to ``dst`` of ``mesh``."""

    def __call__(
        self, image: np.ndarray, src: np.ndarray, dst: np.ndarray, mesh: warp.Mesh, out_shape: tuple[int, int] | None = None
    ) -> np.ndarray: ...


def mesh_warp(image: np.ndarray, src: np.ndarray, dst: np.ndarray, mesh: warp.Mesh, out_shape: tuple[int, int] | None = None) -> np.ndarray:
    """The piecewise-affine warp over the mesh's triangles (:func:`warp.warp`), the paper's."""
    return warp.warp(image, src, dst, mesh.triangles, out_shape)


def tps_warp(image: np.ndarray, src: np.ndarray, dst: np.ndarray, mesh: warp.Mesh, out_shape: tuple[int, int] | None = None) -> np.ndarray:
    """The thin-plate spline through the mesh's control points (:func:`tps.warp`), its grid refined by :func:`tps_refine`."""
    return tps.warp(image, src, dst, out_shape, tps_refine(mesh))


def tps_refine(mesh: warp.Mesh) -> tuple[tuple[np.ndarray, int], ...]:
    """Where the TPS warp evaluates its spline on finer grids: the face (the moving control points), then the mouth."""
    return (np.arange(mesh.n_moving), tps.FACE_STEP), (mesh.mouth, tps.MOUTH_STEP)


#: the image warps by name (:attr:`exprclone.options.Options.image_warp`).
IMAGE_WARPERS: dict[str, ImageWarper] = {"mesh": mesh_warp, "tps": tps_warp}


def ratio_image(
    mesh: warp.Mesh,
    target: Rendered,
    sources: tuple[np.ndarray, np.ndarray],
    source_ctrl: list[np.ndarray],
    motion: np.ndarray,
    layout: Layout,
    image_warp: ImageWarper = mesh_warp,
) -> tuple[np.ndarray, tuple[slice, slice]]:
    """The ERI of the source's two photos in the target's final geometry, warped by ``image_warp`` (:data:`IMAGE_WARPERS`).

    The ratio is 1 off the face, so it is computed in the face's box only. It counts
    only where the expression moves the skin and all three photos show the same skin
    there (:func:`exprclone.eri.expression_ratio`, its ``mask`` times
    :func:`exprclone.shading.moved`, the lips exempt from the colour test).

    Parameters
    ----------
    mesh : warp.Mesh
    target : Rendered
        FI: the target photo warped to its final geometry, and that geometry's control points.
    sources : tuple of two ndarray of shape (h, w, 3), uint8 RGB
        The source's neutral and expression photos.
    source_ctrl : list of two ndarray of shape (P, 2)
        The control points in each of them.
    motion : ndarray of shape (P,)
        How far each control point moves in the source's expression (inter-ocular
        distances, head motion removed), for :func:`exprclone.shading.moved`.
    layout : Layout
    image_warp : ImageWarper

    Returns
    -------
    eri : ndarray of shape (H, W)
        In the target photo's frame.
    box : tuple of slice
        Where it may differ from 1.
    """
    dst, shape = target.control, target.image.shape
    iod = geometry.interocular(dst[: mesh.n_landmarks], layout)
    rows, cols = box = geometry.box(dst[: mesh.n_moving], shape, ERI_MARGIN * iod, closed=False)
    size = (rows.stop - rows.start, cols.stop - cols.start)
    local = dst - (cols.start, rows.start)
    # RGB, not the luma alone: the colour tells a change of material from shading
    neutral, expression = (image_warp(img, c, local, mesh, size) for img, c in zip(sources, source_ctrl))
    mask = eri.ratio_mask(size, local[: mesh.n_landmarks], local[mesh.forehead], layout)
    mask *= shading.moved(size, local, motion, mesh.triangles, iod)
    lip_region = shading.lips(size, local[: mesh.n_landmarks], layout)
    out = np.ones(shape[:2], np.float32)
    out[box] = eri.expression_ratio(neutral, expression, mask, iod, target.image[box], lip_region)
    return out, box
