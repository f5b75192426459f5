"""The mesh image (Song et al. 2007): the expression's illumination change taken in one frame shared by both faces.

Liu et al.'s ERI (:func:`exprclone.details.stage.ratio_image`) warps the source's two photos to the target's final
geometry and filters their ratio there, in a frame that is the target's and changes with the expression. Song et al.
map the details into a *mesh image* instead, "to reduce the facial feature differences" (the paper's Sec. I): both
faces are warped onto one mesh, the ratio is taken and filtered there, and the result is brought back onto the
target's warped face (FI).

The one mesh (:func:`shared_mesh`) is the mean of the two neutral faces, the source's placed on the target's by the
similarity of all their landmarks (GI's), the control points made from it as the target's mesh makes them. On it,
the ratio is the ERI's own (:func:`exprclone.details.stage.ratio_grid`: the source's two photos, the target's skin
trust, the same masks, gate and filter, the filter's width in the shared face's inter-ocular distances); then it is
warped, on its grid, from the shared mesh's control points to FI's (:func:`mesh_image`) and enlarged there.

Where this reading had to choose (Song et al.'s 2-D description could not be read; docs/explanation/song.rst): the
shared mesh (the mean face, between the two people), and that the ratio's filters and tests are the ERI's, so that
the two methods differ in the frame alone.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Final

import numpy as np

from ..imaging import piecewise
from ..imaging.warpers import ImageWarper
from ..landmarks import align
from ..landmarks.layout import Layout
from .stage import ExpressionPhoto, Frame, Ratio, RatioFaces, ratio_grid, ratio_image


def shared_mesh(mesh: piecewise.Mesh, neutral_ctrl: np.ndarray, layout: Layout) -> np.ndarray:
    """The control points of the mesh both faces are warped onto, in the target photo's frame.

    Its landmarks are the mean of the target's neutral ones (``mesh.points``) and the source's (``neutral_ctrl``, on
    its own photo) placed on them by the least-squares similarity; its other control points follow them
    (:meth:`exprclone.imaging.piecewise.Mesh.control_points`), and a triangle that would fold over is relaxed
    (:func:`exprclone.imaging.piecewise.unfold`).

    Parameters
    ----------
    mesh : piecewise.Mesh
        The target's mesh.
    neutral_ctrl : ndarray of shape (P, 2)
        The mesh's control points on the source's neutral photo.
    layout : Layout

    Returns
    -------
    ndarray of shape (P, 2)
    """
    n = mesh.n_landmarks
    placed = align.apply(align.fit_similarity(neutral_ctrl[:n], mesh.points[:n]), neutral_ctrl[:n])
    shared = mesh.control_points((mesh.points[:n] + placed) / 2)
    return piecewise.unfold(mesh.points, shared, mesh.triangles, mesh.n_moving)[0]


def mesh_image(
    mesh: piecewise.Mesh,
    dst: np.ndarray,
    shape: tuple[int, ...],
    faces: RatioFaces,
    neutral_ctrl: np.ndarray,
    expression: ExpressionPhoto,
    layout: Layout,
    image_warp: ImageWarper,
) -> Ratio:
    """The expression's ratio made on the shared mesh (:func:`shared_mesh`), filtered there, and brought onto FI's
    geometry ``dst``: the arguments and the result as :func:`exprclone.details.stage.ratio_image`'s.

    The ratio's channels on the shared mesh's grid are warped by ``image_warp`` to FI's grid, from one geometry's
    control points to the other's; off the face they are 1 and 0 (no change), as the edge of the shared grid repeats.
    """
    there = Frame.of(mesh, shared_mesh(mesh, neutral_ctrl, layout), shape, layout)
    made = ratio_grid(there, mesh, faces, neutral_ctrl, expression, layout, image_warp)
    here = Frame.of(mesh, dst, shape, layout)
    return here.ratio(image_warp(made, there.at, here.at, mesh, here.grid), shape)


#: the ratio a method's details apply, by the name its row gives it (:attr:`exprclone.methods.Method.ratio`): Liu et
#: al.'s ERI in FI's geometry, or Song et al.'s mesh image.
RATIOS: Final[dict[str, Callable[..., Ratio]]] = {"eri": ratio_image, "mesh": mesh_image}
