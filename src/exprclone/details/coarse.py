"""The ERI's photos on its shrunk grid (ours, for speed): shrunk once over the face, warped at that size.

The ERI (:mod:`exprclone.details.eri`) is smooth at :data:`exprclone.details.eri.FILTER_SIGMA`, so all of
it but one measure is computed on a grid shrunk by :func:`exprclone.details.eri.filter_step`.
Warping whole photos at full resolution to shrink them after would be wasted work, so
each photo is shrunk first (:meth:`Shrunk.of`), over its face's box only, and warped to
the target's geometry at the shrunk grid's size (:meth:`Shrunk.warped`). What the ERI
needs of a photo survives the shrink as block means: its colour (Liu's ratio of lumas,
and the gate's colour tests, :mod:`exprclone.details.gate`) and the energy of its luma's fine
detail, above ``DETAIL_SIGMA`` inter-ocular distances (the texture test,
:func:`exprclone.details.eri.texture`): that detail is finer than the grid, so it
alone is taken at the photo's resolution, squared, then averaged.

The source's neutral photo and the target are the same for every expression cloned
between two faces (every frame of a video), so a :class:`~exprclone.Cloner`
shrinks them once; only the expression is shrunk per frame.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import cv2
import numpy as np

from ..imaging import raster
from ..landmarks import align

if TYPE_CHECKING:
    from ..imaging.piecewise import Labelling, Mesh
    from ..imaging.warpers import ImageWarper

#: the detail measured for the texture test (:func:`exprclone.details.eri.texture`) is finer than this, in
#: inter-ocular distances.
DETAIL_SIGMA = 0.01
#: a warp samples a photo between its pixels, at offsets spread evenly over a pixel, and bilinear weights ``(1 - u, u)``
#: lose part of the finest detail: averaged over ``u`` their power response is ``(2 + cos w) / 3``, that of this
#: two-tap filter along each axis. The texture test's range (:data:`exprclone.details.eri.TEXTURE_RANGE`) was measured on
#: warped photos, so an unwarped photo's detail is passed through it (:func:`detail_energy`).
RESAMPLING_LOSS = np.array([(1 + 3**-0.5) / 2, (1 - 3**-0.5) / 2], np.float32)
#: the channels of a source photo's :attr:`Shrunk.pixels` after R, G and B: its luma and its detail's energy.
LUMA, ENERGY = 3, 4


def grid_points(points: np.ndarray, step: int) -> np.ndarray:
    """Where ``points`` (pixel x, y of a full-size image) lie on the image shrunk by ``step`` (:func:`exprclone.imaging.raster.shrink`).

    A shrunk pixel is the mean of a block of ``step x step`` pixels, its centre at the middle of the block.

    Examples
    --------
    >>> grid_points(np.array([[1.0, 4.0]]), 3).tolist()
    [[0.0, 1.0]]
    """
    return (np.asarray(points, float) - (step - 1) / 2) / step


def detail_energy(luma: np.ndarray, iod: float) -> np.ndarray:
    """The squared detail of ``luma`` (``(H, W)`` float32) finer than ``DETAIL_SIGMA iod``: what the texture test measures.

    The detail is taken as a warp would leave it (:data:`RESAMPLING_LOSS`). Measured unwarped, without that loss, the
    texture test trusted fewer pixels than on the warped photos its range was set on, and ``exprclone evaluate``'s
    identity distance of e+md moved by -0.003 (150 London pairs).
    """
    detail = luma - cv2.GaussianBlur(luma, (0, 0), max(DETAIL_SIGMA * iod, 0.5))
    detail = cv2.sepFilter2D(detail, -1, RESAMPLING_LOSS, RESAMPLING_LOSS, anchor=(0, 0), borderType=cv2.BORDER_REFLECT)
    return detail * detail


def grid_pixels(image: np.ndarray, iod: float, step: int, detail: bool = True) -> np.ndarray:
    """The block means of ``image`` (uint8 RGB) over blocks of ``step``: :attr:`Shrunk.pixels`, its channels described there.

    ``iod`` is the face's inter-ocular distance in ``image`` (the detail's scale); ``detail`` (a source's photo) measures
    its luma and its detail's energy, of which the target's colour needs neither.
    """
    colour = raster.shrink(image, step)
    pixels = np.empty(colour.shape[:2] + (5 if detail else 3,), np.float32)
    pixels[..., :3] = colour / np.float32(255.0)
    if detail:
        luma = raster.luma(image).astype(np.float32) / 255.0
        pixels[..., LUMA] = raster.shrink(luma, step)
        pixels[..., ENERGY] = raster.shrink(detail_energy(luma, iod), step)
    return pixels


@dataclass(frozen=True)
class Shrunk:
    """A photo's face on the ERI's shrunk grid.

    Attributes
    ----------
    pixels : ndarray of shape (h, w, 3) or (h, w, 5), float32
        Block means of R, G, B (in [0, 1], rounded to 8 bits as the colour tests have
        always taken them) and, for a source's photo, of the luma (:data:`LUMA`, not rounded:
        Liu's ratio divides it) and of :func:`detail_energy` (:data:`ENERGY`).
        A neutral photo's are replaced by what the ERI measures of them, once
        (:class:`exprclone.details.stage.RatioFaces`): five channels of the source's, the target's
        skin trust alone, ``(h, w)``.
    origin : ndarray of shape (2,)
        Where the first block starts in the photo (pixel x, y).
    step : int
        The blocks' side, in the photo's pixels.
    """

    pixels: np.ndarray
    origin: np.ndarray
    step: int

    @classmethod
    def of(cls, image: np.ndarray, points: np.ndarray, iod: float, step: int, margin: float, detail: bool = True) -> Shrunk:
        """The photo ``image`` shrunk by ``step`` over the box of ``points`` grown by ``margin`` pixels.

        Parameters
        ----------
        image : ndarray of shape (H, W, 3), uint8 RGB
        points : ndarray of shape (P, 2)
            The control points in the photo: the box is theirs.
        iod : float
            The face's inter-ocular distance in the photo (the detail's scale).
        step : int
        margin : float
        detail : bool
            Measure the luma and the detail's energy (Liu's ratio and the texture test, for the source's photos).
        """
        rows, cols = align.box(points, image.shape, margin, closed=False)
        crop = image[rows, cols]
        h, w = crop.shape[0] // step * step, crop.shape[1] // step * step
        if h == 0 or w == 0:  # a box thinner than a block: one block of its pixels
            crop, step = crop[:1, :1], 1
        return cls(grid_pixels(crop, iod, step, detail), np.array([cols.start, rows.start], float), step)

    def warped(self, warp: ImageWarper, source: np.ndarray, labelling: Labelling, mesh: Mesh) -> np.ndarray:
        """Its :attr:`pixels` moved from the photo's control points ``source`` to the grid's, ``labelling.dst``.

        Parameters
        ----------
        warp : ImageWarper
            The image warp (:data:`exprclone.imaging.warpers.IMAGE_WARPERS`).
        source : ndarray of shape (P, 2)
            The control points in the photo (full-size pixels).
        labelling : Labelling
            The grid's pixels labelled by the mesh's triangles at their control points (:class:`exprclone.imaging.piecewise.Labelling`).
        mesh : Mesh

        Returns
        -------
        ndarray of shape (h, w) or (h, w, C), float32
            As :attr:`pixels`.
        """
        src = grid_points(source - self.origin, self.step)
        return warp(self.pixels, src, labelling.dst, mesh, labelling.labels.shape, labelling=labelling)
