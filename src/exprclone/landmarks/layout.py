"""The 68-point landmark layout (iBUG 300-W, as fitted by dlib) as data.

Every index the method needs lives here: which points form each organ for local
re-shaping (Eqs. 1-2), which points are rigid enough to align two photos of one head,
and which points place each key muscle area of the MD model (Eqs. 9-11). A second
landmark scheme is a second `Layout` value, not new code.

Indices are 0-based. "Right" and "left" are the subject's: the subject's right eye is
on the image's left.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class MuscleArea:
    """A key muscle area of the MD model (paper Fig. 10 a).

    The centre is the mean of ``centre`` landmarks plus ``offset`` times the
    inter-ocular distance along the face's (right, down) axes; the radius ``r`` of
    Eq. (11) is ``radius`` times the inter-ocular distance. ``motion`` lists the
    landmarks whose neutral-to-expression motion sets the area's strength ``h``.
    """

    name: str
    centre: tuple[int, ...]
    offset: tuple[float, float]
    radius: float
    motion: tuple[int, ...]


@dataclass(frozen=True)
class Layout:
    """Index tables of one landmark scheme."""

    n_points: int
    jaw: tuple[int, ...]
    brows: tuple[tuple[int, ...], ...]
    eyes: tuple[tuple[int, ...], ...]
    nose: tuple[int, ...]
    mouth_outer: tuple[int, ...]
    mouth_inner: tuple[int, ...]
    #: (upper, lower) inner-lip points that face each other across the mouth opening.
    lip_pairs: tuple[tuple[int, int], ...]
    #: (upper outer, upper inner, lower inner, lower outer) lip points stacked in one column.
    lip_columns: tuple[tuple[int, int, int, int], ...]
    #: points that barely move with expression: used to remove head motion.
    rigid: tuple[int, ...]
    #: the two outer eye corners: the face's horizontal axis and scale.
    eye_corners: tuple[int, int]
    #: for each point, its mirror image across the face's vertical midline (itself on the midline).
    mirror: tuple[int, ...]
    muscle_areas: tuple[MuscleArea, ...]

    @property
    def mouth_corners(self) -> tuple[int, int]:
        """The two outer mouth corners: the first outer-lip point and the one half-way round."""
        return self.mouth_outer[0], self.mouth_outer[len(self.mouth_outer) // 2]

    @property
    def organs(self) -> dict[str, tuple[int, ...]]:
        """Organs re-shaped independently by local warping (Eqs. 1-2).

        The outer and inner lips form one organ so the inner lips stay inside the
        outer ones after re-shaping.
        """
        return {
            "right_brow": self.brows[0],
            "left_brow": self.brows[1],
            "right_eye": self.eyes[0],
            "left_eye": self.eyes[1],
            "nose": self.nose,
            "mouth": self.mouth_outer + self.mouth_inner,
        }

    @property
    def regions(self) -> dict[str, tuple[int, ...]]:
        """Regions whose motion can be transferred alone (``only``, :mod:`exprclone.geometry.weights`): the mouth, the eyes, the brows.

        The other landmarks (jaw, nose) belong to no region: they follow the regions
        around them.
        """
        organs = self.organs
        return {
            "mouth": organs["mouth"],
            "eyes": organs["right_eye"] + organs["left_eye"],
            "brows": organs["right_brow"] + organs["left_brow"],
        }


def weight_matrix(table: Sequence[Sequence[tuple[int, float]]], n_from: int) -> np.ndarray:
    """A table that makes each point of one layout from points of another as a matrix.

    Parameters
    ----------
    table : sequence of sequences of (int, float)
        For each point of the layout made, ``((index in the other layout, weight), ...)``.
    n_from : int
        The other layout's number of points.

    Returns
    -------
    ndarray of shape (len(table), n_from)
        Its product with the other layout's ``(n_from, 2)`` points gives this layout's.

    Examples
    --------
    >>> weight_matrix((((0, 1.0),), ((0, 0.5), (2, 0.5))), 3) @ np.array([[0.0, 0], [1, 1], [2, 4]])
    array([[0., 0.],
           [1., 2.]])
    """
    weights = np.zeros((len(table), n_from))
    for i, row in enumerate(table):
        for j, w in row:
            weights[i, j] = w
    return weights


def _r(a: int, b: int) -> tuple[int, ...]:
    return tuple(range(a, b))


DLIB68 = Layout(
    n_points=68,
    jaw=_r(0, 17),
    brows=(_r(17, 22), _r(22, 27)),
    eyes=(_r(36, 42), _r(42, 48)),
    nose=_r(27, 36),
    mouth_outer=_r(48, 60),
    mouth_inner=_r(60, 68),
    lip_pairs=((61, 67), (62, 66), (63, 65)),
    lip_columns=((50, 61, 67, 58), (51, 62, 66, 57), (52, 63, 65, 56)),
    rigid=(0, 1, 15, 16, 27, 28, 29, 30, 36, 39, 42, 45),
    eye_corners=(36, 45),
    mirror=(
        *range(16, -1, -1),  # jaw
        *range(26, 16, -1),  # brows
        *(27, 28, 29, 30, 35, 34, 33, 32, 31),  # nose bridge, nostrils
        *(45, 44, 43, 42, 47, 46, 39, 38, 37, 36, 41, 40),  # eyes
        *(54, 53, 52, 51, 50, 49, 48, 59, 58, 57, 56, 55),  # outer lips
        *(64, 63, 62, 61, 60, 67, 66, 65),  # inner lips
    ),
    muscle_areas=(
        # frontalis: above the middle of each brow
        MuscleArea("forehead_right", (19,), (0.0, -0.35), 0.30, (18, 19, 20)),
        MuscleArea("forehead_left", (24,), (0.0, -0.35), 0.30, (23, 24, 25)),
        # corrugator / procerus: between the brows
        MuscleArea("brow_centre", (21, 22), (0.0, -0.05), 0.22, (20, 21, 22, 23)),
        # orbicularis oculi: crow's feet beside the outer eye corners
        MuscleArea("eye_corner_right", (36,), (-0.18, 0.02), 0.16, (36, 37, 41)),
        MuscleArea("eye_corner_left", (45,), (0.18, 0.02), 0.16, (45, 44, 46)),
        # zygomaticus over the cheekbones
        MuscleArea("cheek_right", (1, 31, 41), (0.0, 0.0), 0.25, (48, 49, 31)),
        MuscleArea("cheek_left", (15, 35, 46), (0.0, 0.0), 0.25, (54, 53, 35)),
        # levator labii: the nasolabial folds between nose wing and mouth corner
        MuscleArea("nasolabial_right", (31, 48), (-0.06, 0.0), 0.20, (48, 49, 31)),
        MuscleArea("nasolabial_left", (35, 54), (0.06, 0.0), 0.20, (54, 53, 35)),
        # risorius / buccinator: the mouth corners
        MuscleArea("mouth_corner_right", (48,), (-0.06, 0.0), 0.15, (48, 59, 49)),
        MuscleArea("mouth_corner_left", (54,), (0.06, 0.0), 0.15, (54, 55, 53)),
        # mentalis: the chin
        MuscleArea("chin", (8, 57), (0.0, 0.0), 0.22, (7, 8, 9, 57)),
    ),
)
