"""The ERI of one clone (Fig. 5's ERI stage): the two neutral photos measured once, the ratio made in FI's geometry.

The ratio is 1 off the face, so it is computed in the face's box only, on a grid shrunk by
:func:`exprclone.details.eri.filter_step`: the source's neutral photo and the target's are
shrunk over their faces and measured once (:class:`RatioFaces`); each expression photo is
shrunk the same way (:class:`ExpressionPhoto`); and for each geometry of FI the three are
warped onto its grid (:func:`ratio_image`).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..imaging import piecewise, raster
from ..imaging.warpers import ImageWarper
from ..landmarks import align
from ..landmarks.layout import Layout
from . import coarse, eri, gate
from .coarse import Shrunk

#: the face box the ERI is computed in: the moving control points' box grown by this many inter-ocular distances.
ERI_MARGIN = 0.5
#: each photo is shrunk for the ERI over its moving control points' box grown by this many inter-ocular distances:
#: the ratio counts inside their hull only (:func:`exprclone.details.eri.ratio_mask`), and its filters reach 3 sigma
#: (:data:`exprclone.details.eri.FILTER_SIGMA`) beyond; what lies further out is the box's edge repeated.
PHOTO_MARGIN = 0.2
#: where the expression moves the skin is drawn this many times smaller than the face box (:func:`exprclone.details.gate.moved`).
MOTION_SHRINK = 8


@dataclass(frozen=True)
class RatioFaces:
    """What the ERI takes of the two neutral faces, the same for every expression: measured once (:meth:`prepare`).

    Attributes
    ----------
    neutral : Shrunk
        The source's neutral photo on its shrunk grid over its face (:class:`exprclone.details.coarse.Shrunk`), its pixels
        what the ERI takes of it (:func:`exprclone.details.eri.neutral_channels`).
    target : Shrunk
        The target photo likewise, its pixels its skin trust (:func:`exprclone.details.gate.trust`).
    hue : gate.Fit
        The source's neutral chromaticity (:func:`exprclone.details.eri.neutral_channels`).
    iod : float
        The source's inter-ocular distance in its photos: the scale its expression photos are shrunk at.
    """

    neutral: Shrunk
    target: Shrunk
    hue: gate.Fit
    iod: float

    @classmethod
    def of(cls, mesh: piecewise.Mesh, source: np.ndarray, source_ctrl: np.ndarray, target: np.ndarray, layout: Layout) -> RatioFaces:
        """Both neutral photos shrunk (the source's with the control points ``source_ctrl`` of ``mesh`` on it) and measured
        over their faces."""
        measured = []
        for image, ctrl, detail in ((source, source_ctrl, True), (target, mesh.points, False)):
            iod = align.interocular(ctrl[: mesh.n_landmarks], layout)
            photo = Shrunk.of(image, ctrl[: mesh.n_moving], iod, eri.filter_step(iod), PHOTO_MARGIN * iod, detail)
            at = coarse.grid_points(ctrl - photo.origin, photo.step)
            grid = photo.pixels.shape[:2]
            face = eri.ratio_mask(grid, at[: mesh.n_landmarks], at[mesh.forehead], layout, max(1, eri.MASK_SHRINK // photo.step))
            sigma = eri.FILTER_SIGMA * iod / photo.step
            if detail:  # where the texture test trusts it, as the ERI's colour tests do
                face *= eri.texture(photo.pixels[..., coarse.ENERGY], photo.pixels[..., coarse.LUMA], sigma)
            measured.append((photo, face, sigma))
        (neutral, neutral_face, sigma), (target_photo, target_face, target_sigma) = measured
        channels, hue = eri.neutral_channels(neutral.pixels, neutral_face, sigma)
        trust = gate.trust(gate.colour(target_photo.pixels, target_sigma), target_face)
        iod = align.interocular(source_ctrl[: mesh.n_landmarks], layout)
        return cls(dataclasses.replace(neutral, pixels=channels), dataclasses.replace(target_photo, pixels=trust), hue, iod)

    def expression(self, image: np.ndarray, ctrl: np.ndarray, motion: np.ndarray, mesh: piecewise.Mesh) -> ExpressionPhoto:
        """A source expression photo, the control points ``ctrl`` of ``mesh`` on it, shrunk as its neutral photo is;
        ``motion`` is how far each control point moves (:attr:`ExpressionPhoto.motion`)."""
        return ExpressionPhoto(Shrunk.of(image, ctrl[: mesh.n_moving], self.iod, self.neutral.step, PHOTO_MARGIN * self.iod), ctrl, motion)


@dataclass(frozen=True)
class ExpressionPhoto:
    """One source expression as the ERI takes it, the same for every geometry of FI (:meth:`RatioFaces.expression`).

    Attributes
    ----------
    photo : Shrunk
        Its photo, shrunk over its face as the source's neutral photo is.
    ctrl : ndarray of shape (P, 2)
        The mesh's control points placed on that photo.
    motion : ndarray of shape (P,)
        How far each control point moves from the source's neutral face (inter-ocular distances, head motion
        removed), for :func:`exprclone.details.gate.moved`.
    """

    photo: Shrunk
    ctrl: np.ndarray
    motion: np.ndarray

    @staticmethod
    def motion_of(
        still: np.ndarray, neutral: np.ndarray, target: np.ndarray, neutral_ctrl: np.ndarray, mesh: piecewise.Mesh, layout: Layout
    ) -> np.ndarray:
        """How far the source's skin moves at each control point from its ``neutral`` landmarks to ``still`` (its
        expression's, the head's motion removed: :func:`exprclone.geometry.global_warp.remove_head_motion`), in the
        source's inter-ocular distances; ``neutral_ctrl`` are the control points on its neutral photo, placed by the
        similarity from the ``target``'s neutral landmarks."""
        shift = mesh.control_points(still, align.fit_rigid(target, neutral, layout)) - neutral_ctrl
        return np.linalg.norm(shift, axis=1) / align.interocular(neutral, layout)


@dataclass(frozen=True)
class Frame:
    """Where the ERI of one geometry is computed (:meth:`of`): the face's box in the target photo, and its shrunk grid.

    Attributes
    ----------
    box : tuple of slice
        The face's box: the rows and columns of the target photo the ratio is computed over (1 outside).
    step : int
        The grid's blocks' side, in the photo's pixels (:func:`exprclone.details.eri.filter_step`).
    at : ndarray of shape (P, 2)
        The geometry's control points on the grid.
    iod : float
        The face's inter-ocular distance in pixels of the grid.
    """

    box: tuple[slice, slice]
    step: int
    at: np.ndarray
    iod: float

    @classmethod
    def of(cls, mesh: piecewise.Mesh, dst: np.ndarray, shape: tuple[int, ...], layout: Layout) -> Frame:
        """The frame of the control points ``dst`` of ``mesh`` in a photo of ``shape``: their box grown by
        :data:`ERI_MARGIN`."""
        iod = align.interocular(dst[: mesh.n_landmarks], layout)
        rows, cols = box = align.box(dst[: mesh.n_moving], shape, ERI_MARGIN * iod, closed=False)
        step = min(eri.filter_step(iod), rows.stop - rows.start, cols.stop - cols.start)
        return cls(box, step, coarse.grid_points(dst - (cols.start, rows.start), step), iod / step)

    @property
    def size(self) -> tuple[int, int]:
        """The box's ``(height, width)`` in the photo's pixels."""
        rows, cols = self.box
        return rows.stop - rows.start, cols.stop - cols.start

    @property
    def grid(self) -> tuple[int, int]:
        """The grid's ``(height, width)``."""
        return self.size[0] // self.step, self.size[1] // self.step

    def ratio(self, made: np.ndarray, shape: tuple[int, ...]) -> Ratio:
        """The ERI on the grid (:func:`exprclone.details.eri.ratio_on_grid`'s channels) enlarged into the photo of
        ``shape``: its ratio over the face's box, its tint over the part of it where it may change a pixel (:func:`changed`)."""
        size, step, box = self.size, self.step, self.box
        out = np.ones(shape[:2], np.float32)
        raster.enlarge(np.ascontiguousarray(made[..., eri.RATIO]), size, step, out[box])
        rows, cols = changed(made, step, size)
        tint = enlarged_part(made, step, size, rows, cols)[..., eri.TINT]
        box = (slice(box[0].start + rows.start, box[0].start + rows.stop), slice(box[1].start + cols.start, box[1].start + cols.stop))
        return Ratio(out, tint.view(np.complex64).copy().view(np.float32), box)  # copied as pairs: a tenth of the time


def ratio_image(
    mesh: piecewise.Mesh,
    dst: np.ndarray,
    shape: tuple[int, ...],
    faces: RatioFaces,
    neutral_ctrl: np.ndarray,
    expression: ExpressionPhoto,
    layout: Layout,
    image_warp: ImageWarper,
) -> Ratio:
    """The ERI of the source's two photos in the target's final geometry, warped by ``image_warp``
    (:data:`exprclone.imaging.warpers.IMAGE_WARPERS`).

    The ratio is 1 off the face, so it is computed in the face's box only (:class:`Frame`), on its grid shrunk by
    :func:`exprclone.details.eri.filter_step` (:func:`ratio_grid`), and enlarged.

    Parameters
    ----------
    mesh : piecewise.Mesh
    dst : ndarray of shape (P, 2)
        FI's control points: the target's final geometry.
    shape : tuple of int
        The target photo's shape.
    faces : RatioFaces
        The source's neutral photo and the target's, prepared.
    neutral_ctrl : ndarray of shape (P, 2)
        The control points on the source's neutral photo.
    expression : ExpressionPhoto
        The source's expression photo, shrunk, its control points and their motion (:meth:`RatioFaces.expression`).
    layout : Layout
    image_warp : ImageWarper

    Returns
    -------
    Ratio
        The ERI and its tint in the target photo's frame, and the box where they count.
    """
    frame = Frame.of(mesh, dst, shape, layout)
    return frame.ratio(ratio_grid(frame, mesh, faces, neutral_ctrl, expression, layout, image_warp), shape)


def ratio_grid(
    frame: Frame,
    mesh: piecewise.Mesh,
    faces: RatioFaces,
    neutral_ctrl: np.ndarray,
    expression: ExpressionPhoto,
    layout: Layout,
    image_warp: ImageWarper,
) -> np.ndarray:
    """The ERI on the grid of ``frame``, the geometry its control points give (arguments as :func:`ratio_image`'s).

    The three photos, shrunk over their faces (:class:`exprclone.details.coarse.Shrunk`), are warped there
    (:func:`exprclone.details.eri.ratio_on_grid`); the two neutral ones as ``faces`` measured them once. It counts only
    where the expression moves the skin and all three photos show the same skin there (the face's mask times
    :func:`exprclone.details.gate.moved`, the lips exempt from the colour test).

    Returns
    -------
    ndarray of shape (h, w, 3), float32
        :func:`exprclone.details.eri.ratio_on_grid`'s channels.
    """
    grid, at, step = frame.grid, frame.at, frame.step
    labelling = piecewise.Labelling.of(at, mesh.triangles, grid)  # one for the three warps and the motion's mask
    photos = zip((faces.neutral, expression.photo, faces.target), (neutral_ctrl, expression.ctrl, mesh.points))
    neutral, moved_photo, target_trust = (photo.warped(image_warp, ctrl, labelling, mesh) for photo, ctrl in photos)
    face = eri.ratio_mask(grid, at[: mesh.n_landmarks], at[mesh.forehead], layout, max(1, eri.MASK_SHRINK // step))
    moved = gate.moved(labelling, expression.motion, frame.iod, max(1, MOTION_SHRINK // step))
    lip_region = gate.lips(grid, at[: mesh.n_landmarks], layout)
    return eri.ratio_on_grid(
        neutral, moved_photo, target_trust, face * moved, frame.iod, lip_region, faces.hue, step > 1, face * (1 - moved)
    )


def changed(made: np.ndarray, step: int, size: tuple[int, int]) -> tuple[slice, slice]:
    """The rows and columns of the face box (``size``) where the ERI made on its grid (``made``, enlarged by ``step``) may
    change a pixel: the box of its blocks whose ratio is not 1 or whose tint is not 0, grown by one block (the enlargement
    blends each pixel's block with its neighbours; a blend of neutral blocks is neutral), empty where none is."""
    live = (made[..., eri.RATIO] != 1) | (made[..., eri.TINT] != 0).any(-1)
    spans = []
    for axis, blocks in ((1, live.any(1)), (0, live.any(0))):
        found = np.flatnonzero(blocks)
        if not len(found):
            return slice(0, 0), slice(0, 0)
        end = size[1 - axis] if found[-1] + 2 >= len(blocks) else (found[-1] + 2) * step
        spans.append(slice(max(found[0] - 1, 0) * step, end))
    return spans[0], spans[1]


def enlarged_part(made: np.ndarray, step: int, size: tuple[int, int], rows: slice, cols: slice) -> np.ndarray:
    """``raster.enlarge(made, size, step)[rows, cols]``, enlarging only the blocks those pixels blend: theirs and one more
    around (OpenCV's bilinear enlargement gives the same values wherever a block's neighbours are all there)."""
    if min(made.shape[:2]) < 2:  # a single row or column of blocks OpenCV enlarges its own way: the whole of it
        return raster.enlarge(made, size, step)[rows, cols]
    spans = []
    for span, blocks, whole in ((rows, made.shape[0], size[0]), (cols, made.shape[1], size[1])):
        first, last = max(span.start // step - 1, 0), min(-(-span.stop // step) + 1, blocks)
        spans.append((first, last, (last - first) * step if last < blocks else whole - first * step))
    (r0, r1, height), (c0, c1, width) = spans
    part = raster.enlarge(np.ascontiguousarray(made[r0:r1, c0:c1]), (height, width), step)
    return part[rows.start - r0 * step : rows.stop - r0 * step, cols.start - c0 * step : cols.stop - c0 * step]


@dataclass(frozen=True)
class Ratio:
    """The ERI of one clone in the target photo's frame (:func:`ratio_image`).

    Attributes
    ----------
    eri : ndarray of shape (H, W), float32
        The luma ratio, 1 outside ``box``.
    tint : ndarray of shape (h, w, 2), float32
        Its tint in ``box`` (:func:`exprclone.details.eri.ratio_on_grid`): the shift of ``log R/G`` and ``log B/G``.
    box : tuple of slice
        Where they may differ from 1 and 0.
    """

    eri: np.ndarray
    tint: np.ndarray
    box: tuple[slice, slice]
