"""How much of the expression is transferred, and where: expression strength and ``only`` (not in the paper).

A clone carries three things from the source to the target: landmark motion, the
expression ratio image, and the mouth interior pasted into an opened mouth. With
strength ``S`` and regions ``R`` (:class:`exprclone.options.Options`), each is scaled by
a weight ``w = S * r``, where ``r`` says how much a place belongs to the regions named
(1 inside them, 0 in the other regions, a smooth transition in between; :func:`region_share`):

- the landmarks of the shape stages move ``w`` times as far from the target's neutral
  landmarks (:meth:`Transfer.landmarks`);
- the ERI becomes ``ERI ** w`` (in the log domain, so ``w = 0`` is no change and
  ``w = 2`` doubles each fold's contrast; :meth:`Transfer.ratio`);
- the mouth interior fades in with the opening the scaled motion produces, as it does
  for the whole expression (:mod:`exprclone.mouth.paste`), and with the share of the mouth's
  motion transferred, ``min(1, w)`` on the mouth (:attr:`Transfer.paste`): at ``S = 0`` no
  source teeth enter a target whose neutral lips are already parted.

``S = 0`` leaves the target photo as it is; the mouth opening grows steadily with ``S``.
The elasticity ratio lambda_k is chosen on the whole expression: strength scales the
result of the shape stages, it does not change them.

The transition between regions: a place at distances ``d_in`` from the nearest landmark
of the regions named and ``d_out`` from the nearest of the other regions has
``r = d_out**2 / (d_in**2 + d_out**2)`` (inverse-distance weighting, Shepard 1968, power 2:
smooth, flat at the landmarks, 1/2 half-way). Landmarks in no region (the jaw, the nose)
take the ``r`` of where they are: with ``only=("mouth",)`` the chin follows the mouth,
the bridge of the nose stays with the eyes.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from ..landmarks.layout import Layout

#: the detail weight is evaluated on a grid of this many pixels and interpolated: it
#: changes over inter-ocular distances, hundreds of pixels.
FIELD_STEP = 8


def region_share(places: np.ndarray, landmarks: np.ndarray, layout: Layout, only: tuple[str, ...]) -> np.ndarray:
    """How much each place belongs to the regions ``only`` (the module's rule), ``(K,)`` in [0, 1].

    Parameters
    ----------
    places : ndarray of shape (K, 2)
    landmarks : ndarray of shape (N, 2)
        The face's landmarks (the target's neutral ones).
    layout : Layout
    only : tuple of str
        Names of :attr:`Layout.regions`.

    Examples
    --------
    >>> from exprclone.landmarks.layout import DLIB68
    >>> face = np.zeros((68, 2))
    >>> for name, y in (("mouth", 10), ("eyes", -10), ("brows", -20)):
    ...     face[list(DLIB68.regions[name])] = (0, y)
    >>> region_share(np.array([[0, 10], [0, 0], [0, -10]]), face, DLIB68, ("mouth",)).tolist()
    [1.0, 0.5, 0.0]
    """
    named = [i for name in only for i in layout.regions[name]]
    others = [i for name, idx in layout.regions.items() if name not in only for i in idx]
    if not others:
        return np.ones(len(places))
    nearest = [np.min(np.sum((places[:, None] - landmarks[idx][None]) ** 2, axis=2), axis=1) for idx in (named, others)]
    d_in, d_out = nearest
    total = d_in + d_out
    return np.where(total > 0, d_out / np.where(total > 0, total, 1.0), 0.5)


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
    def build(cls, strength: float, only: tuple[str, ...] | None, neutral: np.ndarray, shape: tuple[int, ...], layout: Layout) -> Transfer:
        """The weights of ``strength`` on the regions ``only`` (None: all) on the target face with ``neutral`` landmarks,
        in a photo of ``shape``."""
        s = strength
        if s == 1 and only is None:  # the whole expression everywhere, as in the paper
            return cls(neutral)
        if only is None:
            return cls(neutral, np.full(len(neutral), s), s, min(1.0, s))
        h, w = shape[:2]
        ys, xs = np.arange(0, h + FIELD_STEP, FIELD_STEP), np.arange(0, w + FIELD_STEP, FIELD_STEP)
        grid = np.stack(np.meshgrid(xs, ys), axis=-1).reshape(-1, 2).astype(float)
        coarse = (s * region_share(grid, neutral, layout, only)).reshape(len(ys), len(xs)).astype(np.float32)
        # node (i, j) of the grid is pixel (j, i) * FIELD_STEP: an exact affine resampling
        scale = np.array([[1.0 / FIELD_STEP, 0, 0], [0, 1.0 / FIELD_STEP, 0]])
        field = cv2.warpAffine(coarse, scale, (w, h), flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP, borderMode=cv2.BORDER_REPLICATE)
        motion = s * region_share(neutral, neutral, layout, only)
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
