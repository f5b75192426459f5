"""How much of the expression is transferred, and where: the strengths, whole and per region (not in the paper).

A clone carries three things from the source to the target: landmark motion, the
expression ratio image, and the mouth interior pasted into an opened mouth. Each region
(mouth, eyes, brows) has a strength (:attr:`exprclone.options.Options.region_strengths`:
its own, else the whole expression's ``S``, 0 for a region that ``only`` leaves out), and
each place of the face a weight ``w`` that blends them (1 inside a region of strength 1,
a smooth transition between regions; :func:`weight`):

- the landmarks of the shape stages move ``w`` times as far from the target's neutral
  landmarks (:meth:`Transfer.landmarks`);
- the ERI becomes ``ERI ** (w * shading)`` (in the log domain, so ``w = 0`` is no change and
  ``w = 2`` doubles each fold's contrast; :meth:`Transfer.ratio`), ``shading`` a factor on the
  details alone (``strength_shading``; 0: the motion without its folds and shadows);
- the mouth interior fades in with the opening the scaled motion produces, as it does
  for the whole expression (:mod:`exprclone.mouth.paste`), and with the share of the mouth's
  motion transferred, ``min(1, w)`` on the mouth (:attr:`Transfer.paste`): at ``S = 0`` no
  source teeth enter a target whose neutral lips are already parted.

``S = 0`` leaves the target photo as it is, and a region of strength 0 its own part of it;
the mouth opening grows steadily with the mouth's strength. The elasticity ratio lambda_k is
chosen on the whole expression: the strengths scale the result of the shape stages, they do
not change them.

The transition between regions: regions of equal strength make one group, and a place at
squared distance ``d_g`` from the nearest landmark of group ``g`` takes the group's strength
with the share ``(1 / d_g) / sum(1 / d_h)`` (inverse-distance weighting, Shepard 1968, power 2:
smooth, flat at the landmarks; with two groups, ``d_2 / (d_1 + d_2)``, 1/2 half-way;
:func:`group_shares`). Landmarks in no region (the jaw, the nose) take the ``w`` of where they
are: with ``only=("mouth",)`` the chin follows the mouth, the bridge of the nose stays with the
eyes.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import cv2
import numpy as np

from ..landmarks.layout import Layout

#: the detail weight is evaluated on a grid of this many pixels and interpolated: it
#: changes over inter-ocular distances, hundreds of pixels.
FIELD_STEP = 8


def group_shares(places: np.ndarray, landmarks: np.ndarray, groups: list[list[int]]) -> np.ndarray:
    """How much each place belongs to each group of landmarks (the module's rule), ``(G, K)``, each column summing to 1.

    With ``d_g`` the squared distance from a place to the nearest landmark of group ``g``, its share is
    ``prod(d_h, h != g) / sum over g' of prod(d_h, h != g')``: ``(1 / d_g) / sum(1 / d_h)`` without dividing by 0 at a
    landmark (two groups: ``d_2 / (d_1 + d_2)``). A place at landmarks of several groups at once shares equally.

    Parameters
    ----------
    places : ndarray of shape (K, 2)
    landmarks : ndarray of shape (N, 2)
        The face's landmarks (the target's neutral ones).
    groups : list of lists of int
        Indices into ``landmarks``, one list per group.

    Examples
    --------
    >>> face = np.array([[0.0, 10], [0, -10], [0, -20]])
    >>> group_shares(np.array([[0, 10], [0, 0], [0, -10]]), face, [[0], [1, 2]]).round(3).tolist()
    [[1.0, 0.5, 0.0], [0.0, 0.5, 1.0]]
    """
    if len(groups) == 1:
        return np.ones((1, len(places)))
    d = np.stack([np.min(np.sum((places[:, None] - landmarks[idx][None]) ** 2, axis=2), axis=1) for idx in groups])
    numerators = np.stack([np.prod(np.delete(d, g, axis=0), axis=0) for g in range(len(groups))])
    total = numerators.sum(axis=0)
    return np.where(total > 0, numerators / np.where(total > 0, total, 1.0), 1.0 / len(groups))


def weight(places: np.ndarray, landmarks: np.ndarray, layout: Layout, strengths: Mapping[str, float]) -> np.ndarray:
    """The weight ``w`` of each place, ``(K,)``: the regions' strengths blended by :func:`group_shares` of the groups of
    regions with equal strength.

    Examples
    --------
    >>> from exprclone.landmarks.layout import DLIB68
    >>> face = np.zeros((68, 2))
    >>> for name, y in (("mouth", 10), ("eyes", -10), ("brows", -20)):
    ...     face[list(DLIB68.regions[name])] = (0, y)
    >>> weight(np.array([[0, 10], [0, 0], [0, -10]]), face, DLIB68, {"mouth": 1.0, "eyes": 0.0, "brows": 0.0}).tolist()
    [1.0, 0.5, 0.0]
    """
    levels = sorted(set(strengths.values()), reverse=True)
    groups = [[i for name, s in strengths.items() if s == level for i in layout.regions[name]] for level in levels]
    shares = group_shares(places, landmarks, groups)
    total: np.ndarray = sum((level * share for level, share in zip(levels, shares)), np.zeros(len(places)))
    return total


@dataclass(frozen=True)
class Transfer:
    """The weights of one pair of faces' transfer (the module's notes); :meth:`build` makes it.

    Attributes
    ----------
    neutral : ndarray of shape (N, 2)
        The target's neutral landmarks, from which motion is scaled.
    motion : ndarray of shape (N,) or None
        Each landmark's weight ``w``; None: the whole motion (1 everywhere).
    details : ndarray of shape (H, W), float or None
        The ERI's exponent per pixel of the target photo (or one for all); None: 1.
    paste : float
        Factor on the mouth interior's weight: ``min(1, w)`` on the mouth.
    """

    neutral: np.ndarray
    motion: np.ndarray | None = None
    details: np.ndarray | float | None = None
    paste: float = 1.0

    @classmethod
    def build(cls, strengths: Mapping[str, float], shading: float, neutral: np.ndarray, shape: tuple[int, ...], layout: Layout) -> Transfer:
        """The weights of the regions' ``strengths`` (:attr:`exprclone.options.Options.region_strengths`), the details'
        scaled by ``shading``, on the target face with ``neutral`` landmarks, in a photo of ``shape``."""
        levels = set(strengths.values())
        if len(levels) == 1:
            (s,) = levels
            if s == 1 and shading == 1:  # the whole expression everywhere, as in the paper
                return cls(neutral)
            return cls(neutral, np.full(len(neutral), s), s * shading, min(1.0, s))
        h, w = shape[:2]
        ys, xs = np.arange(0, h + FIELD_STEP, FIELD_STEP), np.arange(0, w + FIELD_STEP, FIELD_STEP)
        grid = np.stack(np.meshgrid(xs, ys), axis=-1).reshape(-1, 2).astype(float)
        coarse = weight(grid, neutral, layout, strengths).reshape(len(ys), len(xs)).astype(np.float32)
        if shading != 1:
            coarse *= np.float32(shading)
        # node (i, j) of the grid is pixel (j, i) * FIELD_STEP: an exact affine resampling
        scale = np.array([[1.0 / FIELD_STEP, 0, 0], [0, 1.0 / FIELD_STEP, 0]])
        field = cv2.warpAffine(coarse, scale, (w, h), flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP, borderMode=cv2.BORDER_REPLICATE)
        motion = weight(neutral, neutral, layout, strengths)
        mouth = float(motion[list(layout.regions["mouth"])].mean())
        return cls(neutral, motion, field, min(1.0, mouth))

    def landmarks(self, points: np.ndarray) -> np.ndarray:
        """The shape ``points`` with each landmark's motion from the neutral face scaled by its weight."""
        return points if self.motion is None else self.neutral + self.motion[:, None] * (points - self.neutral)

    def ratio(self, eri: np.ndarray, box: tuple[slice, slice]) -> np.ndarray:
        """``eri ** w`` (float32), the exponent per pixel; ``box`` (where ``eri`` is not 1) is all that changes."""
        if self.details is None:
            return eri
        exponent = self.details[box] if isinstance(self.details, np.ndarray) else self.details
        out = eri.copy()
        out[box] = np.exp(exponent * np.log(eri[box]))
        return out

    def tint(self, tint: np.ndarray, box: tuple[slice, slice]) -> np.ndarray:
        """``w tint``: the ERI's tint (``(h, w, 2)``, a shift of logarithms over ``box``) scaled as its ratio is."""
        if self.details is None:
            return tint
        exponent = self.details[box] if isinstance(self.details, np.ndarray) else self.details
        scaled: np.ndarray = (np.asarray(exponent, np.float32)[..., None] * tint).astype(np.float32)
        return scaled
