"""An expression judge: does a face in a photo smile? A classifier on its landmarks, trained on other people.

A clone can be close to the target's face because it barely changed it ("no change" is
the closest of all); whether it still reads as a smile needs a judge that looks at the
result alone. This one reads the 68 landmarks detected on a photo:

1. the landmarks are brought into one frame by the similarity that aligns their rigid
   points (``layout.rigid``) with the training set's mean, in outer-eye-corner distances;
2. the points that carry an expression (lips, eyes, brows) are reduced to their first
   :data:`COMPONENTS` principal components over the training photos;
3. a logistic regression (L2 penalty :data:`PENALTY` on standardised components, fitted by
   Newton's method) gives the probability that the face smiles.

It is trained on the neutral and smiling photos of people other than the ones it judges
(:func:`exprclone.evaluation.report.score_pair` leaves out the pair's two people). On the
London Set's 72 people, trained on the other 71 each time, it calls 92% of the 144 photos
right (6 neutral photos called smiling, 6 smiles called neutral: the faintest) and gives
every person's smile a higher probability than their neutral photo. Two feature sets were
tried once each, before any clone was judged: these components (92%) and five measures
of the mouth and eyes (width, corner lift, opening, eye aperture: 89%).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..landmarks import align
from ..landmarks.layout import DLIB68, Layout
from .london import Dataset

#: principal components of the expression's landmarks the judge reads.
COMPONENTS = 10
#: L2 penalty of the logistic regression, on standardised components.
PENALTY = 1.0
#: Newton steps of the fit (it converges in fewer than 10).
STEPS = 25
#: a judge needs at least this many people to learn from, each with both photos.
MIN_PEOPLE = 10
#: a face is judged to smile from this probability on.
SMILING = 0.5


def expression_points(layout: Layout) -> list[int]:
    """The landmarks an expression moves most: the lips, eyes and brows."""
    return list(layout.mouth_outer + layout.mouth_inner) + [i for group in layout.eyes + layout.brows for i in group]


@dataclass(frozen=True)
class SmileJudge:
    """A trained judge (:meth:`train`); calling it on a face's landmarks gives the probability that it smiles."""

    reference: np.ndarray
    mean: np.ndarray
    components: np.ndarray
    scale: np.ndarray
    weights: np.ndarray
    layout: Layout = DLIB68

    @classmethod
    def train(cls, neutral: list[np.ndarray], smiling: list[np.ndarray], layout: Layout = DLIB68) -> SmileJudge:
        """Fit on the landmarks of people's neutral and smiling photos.

        Parameters
        ----------
        neutral, smiling : list of ndarray of shape (N, 2)
            Landmarks of the photos of each kind.
        layout : Layout

        Examples
        --------
        >>> rng = np.random.default_rng(0)
        >>> face = rng.uniform(0, 100, (68, 2))
        >>> wide = face.copy(); wide[48] -= (5, 3); wide[54] += (5, -3)
        >>> judge = SmileJudge.train([face + rng.normal(0, 1, face.shape) for _ in range(20)],
        ...                          [wide + rng.normal(0, 1, face.shape) for _ in range(20)])
        >>> bool(judge(wide) > 0.9 > 0.1 > judge(face))
        True
        """
        shapes = list(neutral) + list(smiling)
        reference = np.mean([align.apply(align.fit_rigid(s, shapes[0], layout), s) for s in shapes], axis=0)
        x = np.array([_aligned(s, reference, layout) for s in shapes])
        mean = x.mean(axis=0)
        components = np.linalg.svd(x - mean, full_matrices=False)[2][:COMPONENTS]
        z = (x - mean) @ components.T
        scale = z.std(axis=0) + 1e-12
        y = np.r_[np.zeros(len(neutral)), np.ones(len(smiling))]
        return cls(reference, mean, components, scale, _logistic(z / scale, y), layout)

    def __call__(self, points: np.ndarray) -> float:
        """The probability that the face with these landmarks smiles."""
        z = (_aligned(points, self.reference, self.layout) - self.mean) @ self.components.T / self.scale
        return float(1.0 / (1.0 + np.exp(-(z @ self.weights[:-1] + self.weights[-1]))))


def _aligned(points: np.ndarray, reference: np.ndarray, layout: Layout) -> np.ndarray:
    """The expression's landmarks in the reference's frame, in its outer-eye-corner distances, flattened."""
    placed = align.apply(align.fit_rigid(points, reference, layout), points) / align.interocular(reference, layout)
    return placed[expression_points(layout)].ravel()


def _logistic(z: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Weights (and the intercept, last) of a logistic regression with an L2 penalty on the weights, by Newton's method."""
    design = np.c_[z, np.ones(len(z))]
    penalty = PENALTY * np.diag(np.r_[np.ones(z.shape[1]), 0.0])
    w = np.zeros(design.shape[1])
    for _ in range(STEPS):
        p = 1.0 / (1.0 + np.exp(-design @ w))
        hessian = (design * (p * (1 - p))[:, None]).T @ design + penalty
        w -= np.linalg.solve(hessian, design.T @ (p - y) + penalty @ w)
    return w


def trained_without(data: Dataset, landmarks: dict[str, np.ndarray], leave_out: tuple[str, ...]) -> SmileJudge | None:
    """The judge trained on every person of ``data`` whose two photos have ``landmarks`` (by path) but those ``leave_out``;
    None with fewer than :data:`MIN_PEOPLE`."""
    people = [p for p in data.ids if p not in leave_out and all(data.path(p, s) in landmarks for s in (False, True))]
    if len(people) < MIN_PEOPLE:
        return None
    return SmileJudge.train([landmarks[data.path(p, False)] for p in people], [landmarks[data.path(p, True)] for p in people])
