"""The stages of Fig. 5 as tables of functions, looked up by name: the global warps, the shape stages, the image warps.

A :class:`~exprclone.cloner.Cloner` runs them: each shape stage
(:data:`SHAPE_STAGES`) computes its landmarks from the ones before it; the global
stage by the global warp the options name (:data:`GLOBAL_WARPERS`, keyed by
:attr:`exprclone.options.Options.global_warp`) unless they give GI; FI and the ERI by the image warp they
name (:data:`IMAGE_WARPERS`, keyed by :attr:`exprclone.options.Options.image_warp`).
The names themselves, and what a user may choose, are :mod:`exprclone.options`'.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

import numpy as np

from . import eigenface, elastic, eri, geometry, global_warp, local_warp, metric, raster, shading, shrunk, tps, warp
from .layout import Layout
from .models import default_eigenfaces
from .shrunk import Shrunk

if TYPE_CHECKING:
    from .cloner import Cloner

#: the face box the ERI is computed in: the moving control points' box grown by this many inter-ocular distances.
ERI_MARGIN = 0.5
#: each photo is shrunk for the ERI over its moving control points' box grown by this many inter-ocular distances:
#: the ratio counts inside their hull only (:func:`exprclone.eri.ratio_mask`), and its filters reach 3 sigma
#: (:data:`exprclone.eri.FILTER_SIGMA`) beyond; what lies further out is the box's edge repeated.
PHOTO_MARGIN = 0.2
#: where the expression moves the skin is drawn this many times smaller than the face box (:func:`exprclone.shading.moved`).
MOTION_SHRINK = 8


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
    crop : ndarray of shape (S, S) or None
        Its eye-aligned grey crop (:func:`exprclone.eigenface.crop`), whose eigenface features
        the DB metric compares (``E_source_exp`` of Eq. 7), if the caller has made it (the
        role check's); None leaves it to the elastic stage, made only when it chooses ``lambda_k``.
    """

    image: np.ndarray
    points: np.ndarray
    lambda_k: float | str
    moving: np.ndarray
    organs: np.ndarray
    crop: np.ndarray | None = None


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
    # the DB metric looks at 64-pixel crops: its candidates need no sub-pixel search (metric.CANDIDATE_PASSES)
    candidates = list(elastic.elastic_landmarks(gl, local, cloner.neighbours, lambdas, metric.CANDIDATE_PASSES))
    eigenfaces = cloner.eigenfaces or default_eigenfaces()
    crop = eigenface.crop(expression.image, expression.points, cloner.layout) if expression.crop is None else expression.crop
    curve = metric.choose_lambda(cloner.db_target, cloner.mesh, candidates, lambdas, crop, eigenfaces, cloner.layout)
    return Shape(elastic.elastic_landmarks(gl, local, cloner.neighbours, curve.best), curve.best, curve)


#: the shape stages of :data:`exprclone.methods.SHAPES` by name, each computed from the ones before it.
SHAPE_STAGES: dict[str, Callable[[Cloner, Expression, dict[str, Shape]], Shape]] = {
    "global": global_stage,
    "local": local_stage,
    "elastic": elastic_stage,
}


class ImageWarper(Protocol):
    """An image warp of :data:`IMAGE_WARPERS`: ``image`` moved from control points ``src`` to ``dst`` of ``mesh``.

    ``labelling``, when given, is the output's pixels labelled by the mesh's triangles at ``dst``
    (:class:`exprclone.warp.Labelling`), made once for several warps to the same points.
    """

    def __call__(
        self,
        image: np.ndarray,
        src: np.ndarray,
        dst: np.ndarray,
        mesh: warp.Mesh,
        out_shape: tuple[int, int] | None = None,
        labelling: warp.Labelling | None = None,
    ) -> np.ndarray: ...


def mesh_warp(
    image: np.ndarray,
    src: np.ndarray,
    dst: np.ndarray,
    mesh: warp.Mesh,
    out_shape: tuple[int, int] | None = None,
    labelling: warp.Labelling | None = None,
) -> np.ndarray:
    """The piecewise-affine warp over the mesh's triangles (:func:`warp.warp`), the paper's."""
    if labelling is not None:
        return warp.sample(image, labelling.affine(src))
    return warp.warp(image, src, dst, mesh.triangles, out_shape)


def tps_warp(
    image: np.ndarray,
    src: np.ndarray,
    dst: np.ndarray,
    mesh: warp.Mesh,
    out_shape: tuple[int, int] | None = None,
    labelling: warp.Labelling | None = None,
) -> np.ndarray:
    """The thin-plate spline through the mesh's control points (:func:`tps.warp`), its grid refined by :func:`tps_refine`
    (it has no triangles: ``labelling`` is not used)."""
    return tps.warp(image, src, dst, out_shape, tps_refine(mesh))


def tps_refine(mesh: warp.Mesh) -> tuple[tuple[np.ndarray, int], ...]:
    """Where the TPS warp evaluates its spline on finer grids: the face (the moving control points), then the mouth."""
    return (np.arange(mesh.n_moving), tps.FACE_STEP), (mesh.mouth, tps.MOUTH_STEP)


#: the image warps by name (:attr:`exprclone.options.Options.image_warp`).
IMAGE_WARPERS: dict[str, ImageWarper] = {"mesh": mesh_warp, "tps": tps_warp}


@dataclass(frozen=True)
class RatioFaces:
    """What the ERI takes of the two neutral faces, the same for every expression: measured once (:meth:`prepare`).

    Attributes
    ----------
    neutral : Shrunk
        The source's neutral photo on its shrunk grid over its face (:class:`exprclone.shrunk.Shrunk`), its pixels
        what the ERI takes of it (:func:`exprclone.eri.neutral_channels`).
    target : Shrunk
        The target photo likewise, its pixels its skin trust (:func:`exprclone.shading.trust`).
    hue : shading.Fit
        The source's neutral chromaticity (:func:`exprclone.eri.neutral_channels`).
    iod : float
        The source's inter-ocular distance in its photos: the scale its expression photos are shrunk at.
    """

    neutral: Shrunk
    target: Shrunk
    hue: shading.Fit
    iod: float

    @classmethod
    def prepare(cls, mesh: warp.Mesh, source: np.ndarray, source_ctrl: np.ndarray, target: np.ndarray, layout: Layout) -> RatioFaces:
        """Both neutral photos shrunk (the source's with the control points ``source_ctrl`` of ``mesh`` on it) and measured
        over their faces."""
        measured = []
        for image, ctrl, detail in ((source, source_ctrl, True), (target, mesh.points, False)):
            iod = geometry.interocular(ctrl[: mesh.n_landmarks], layout)
            photo = Shrunk.of(image, ctrl[: mesh.n_moving], iod, eri.filter_step(iod), PHOTO_MARGIN * iod, detail)
            at = shrunk.grid_points(ctrl - photo.origin, photo.step)
            grid = photo.pixels.shape[:2]
            face = eri.ratio_mask(grid, at[: mesh.n_landmarks], at[mesh.forehead], layout, max(1, eri.MASK_SHRINK // photo.step))
            sigma = eri.FILTER_SIGMA * iod / photo.step
            if detail:  # where the texture test trusts it, as the ERI's colour tests do
                face *= eri.texture(photo.pixels[..., shrunk.ENERGY], photo.pixels[..., shrunk.LUMA], sigma)
            measured.append((photo, face, sigma))
        (neutral, neutral_face, sigma), (target_photo, target_face, target_sigma) = measured
        channels, hue = eri.neutral_channels(neutral.pixels, neutral_face, sigma)
        trust = shading.trust(shading.colour(target_photo.pixels, target_sigma), target_face)
        iod = geometry.interocular(source_ctrl[: mesh.n_landmarks], layout)
        return cls(dataclasses.replace(neutral, pixels=channels), dataclasses.replace(target_photo, pixels=trust), hue, iod)

    def expression(self, image: np.ndarray, ctrl: np.ndarray, mesh: warp.Mesh) -> Shrunk:
        """A source expression photo, the control points ``ctrl`` of ``mesh`` on it, shrunk as its neutral photo is."""
        return Shrunk.of(image, ctrl[: mesh.n_moving], self.iod, self.neutral.step, PHOTO_MARGIN * self.iod)


def ratio_image(
    mesh: warp.Mesh,
    target: Rendered,
    faces: RatioFaces,
    expression: Shrunk,
    source_ctrl: tuple[np.ndarray, np.ndarray],
    motion: np.ndarray,
    layout: Layout,
    image_warp: ImageWarper = mesh_warp,
) -> tuple[np.ndarray, tuple[slice, slice]]:
    """The ERI of the source's two photos in the target's final geometry, warped by ``image_warp`` (:data:`IMAGE_WARPERS`).

    The ratio is 1 off the face, so it is computed in the face's box only, on its grid
    shrunk by :func:`exprclone.eri.filter_step`: the three photos, shrunk over their faces
    (:class:`exprclone.shrunk.Shrunk`), are warped there (:func:`exprclone.eri.ratio_on_grid`); the
    two neutral ones as ``faces`` measured them once. It counts only where the expression
    moves the skin and all three photos show the same skin there (its ``mask`` times
    :func:`exprclone.shading.moved`, the lips exempt from the colour test).

    Parameters
    ----------
    mesh : warp.Mesh
    target : Rendered
        FI: the target photo warped to its final geometry, and that geometry's control points.
    faces : RatioFaces
        The source's neutral photo and the target's, prepared.
    expression : Shrunk
        The source's expression photo, shrunk (:meth:`RatioFaces.expression`).
    source_ctrl : tuple of two ndarray of shape (P, 2)
        The control points in the source's neutral and expression photos.
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
    step = min(eri.filter_step(iod), *size)
    grid = (size[0] // step, size[1] // step)
    local = dst - (cols.start, rows.start)
    at = shrunk.grid_points(local, step)
    labelling = warp.Labelling.of(at, mesh.triangles, grid)  # one for the three warps and the motion's mask
    photos = zip((faces.neutral, expression, faces.target), (*source_ctrl, mesh.points))
    neutral, moved_photo, target_trust = (photo.warped(image_warp, ctrl, labelling, mesh) for photo, ctrl in photos)
    mask = eri.ratio_mask(grid, at[: mesh.n_landmarks], at[mesh.forehead], layout, max(1, eri.MASK_SHRINK // step))
    mask *= shading.moved(labelling, motion, iod / step, max(1, MOTION_SHRINK // step))
    lip_region = shading.lips(grid, at[: mesh.n_landmarks], layout)
    small = eri.ratio_on_grid(neutral, moved_photo, target_trust, mask, iod / step, lip_region, faces.hue, step > 1)
    out = np.ones(shape[:2], np.float32)
    out[box] = raster.enlarge(small, size, step)
    return out, box
