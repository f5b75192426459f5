"""The image warps by name (``image_warp``): how a photo follows its landmarks, as one kind of function.

Both take a photo from a mesh's control points ``src`` to ``dst``: ``mesh``, the piecewise-affine
warp over the mesh's triangles (:mod:`exprclone.imaging.piecewise`, the paper's), or ``tps``, a
thin-plate spline through the same points (:mod:`exprclone.imaging.tps`). FI and the ERI's photos
are warped by the one the clone's options name.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from . import piecewise, tps


class ImageWarper(Protocol):
    """An image warp of :data:`IMAGE_WARPERS`: ``image`` moved from control points ``src`` to ``dst`` of ``mesh``.

    ``labelling``, when given, is the output's pixels labelled by the mesh's triangles at ``dst``
    (:class:`exprclone.imaging.piecewise.Labelling`), made once for several warps to the same points.
    """

    def __call__(
        self,
        image: np.ndarray,
        src: np.ndarray,
        dst: np.ndarray,
        mesh: piecewise.Mesh,
        out_shape: tuple[int, int] | None = None,
        labelling: piecewise.Labelling | None = None,
    ) -> np.ndarray: ...


def mesh_warp(
    image: np.ndarray,
    src: np.ndarray,
    dst: np.ndarray,
    mesh: piecewise.Mesh,
    out_shape: tuple[int, int] | None = None,
    labelling: piecewise.Labelling | None = None,
) -> np.ndarray:
    """The piecewise-affine warp over the mesh's triangles (:func:`exprclone.imaging.piecewise.warp`), the paper's."""
    if labelling is not None:
        return piecewise.sample(image, labelling.affine(src))
    return piecewise.warp(image, src, dst, mesh.triangles, out_shape)


def tps_warp(
    image: np.ndarray,
    src: np.ndarray,
    dst: np.ndarray,
    mesh: piecewise.Mesh,
    out_shape: tuple[int, int] | None = None,
    labelling: piecewise.Labelling | None = None,
) -> np.ndarray:
    """The thin-plate spline through the mesh's control points (:func:`exprclone.imaging.tps.warp`), its grid refined by :func:`tps_refine`
    (it has no triangles: ``labelling`` is not used)."""
    return tps.warp(image, src, dst, out_shape, tps_refine(mesh))


def tps_refine(mesh: piecewise.Mesh) -> tuple[tuple[np.ndarray, int], ...]:
    """Where the TPS warp evaluates its spline on finer grids: the face (the moving control points), then the mouth."""
    return (np.arange(mesh.n_moving), tps.FACE_STEP), (mesh.mouth, tps.MOUTH_STEP)


#: the image warps by name (:attr:`exprclone.options.Options.image_warp`).
IMAGE_WARPERS: dict[str, ImageWarper] = {"mesh": mesh_warp, "tps": tps_warp}
