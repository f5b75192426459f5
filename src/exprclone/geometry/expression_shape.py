"""How a face of given proportions makes an expression: the source's motion re-expressed as the target's own, learnt from
real faces (not in the paper).

A smile is partly everyone's (the corners rise and pull back, the cheeks rise, the lower lids
follow) and partly the person's: how far a wide mouth widens, how thick lips thin, how far the
corners travel all depend on the face. Carried from one face to another, the source's own part
makes the target a stranger (``../shared/notes/identity.md``). So, in each face's own frame
(:func:`normalised`: the eye line level, the outer eye corners one unit apart):

1. a linear map learnt from people's neutral faces and their own smiles predicts how a face
   smiles from its neutral shape, ``f(N) = mean motion + (N - mean neutral) W`` (ridge
   regression, :meth:`ExpressionShape.fit`);
2. the source's motion ``m_s`` is split into its smile, ``k f(N_s)`` with ``k`` the least-squares
   share of its own predicted smile (at least 0), how far its lips part beyond that smile,
   ``c p`` (``p`` the motion that goes with the inner lips' parting over the people learnt
   from, a regression of the rest on it: teeth shown or not is the expression's, not the
   person's), and the rest ``r_s = m_s - k f(N_s) - c p``;
3. the target takes the smile as its own face would make it, ``k f(N_t)``, its lips parted along
   ``p`` as far as the source's part (its smile's parting along ``p`` and its own beyond it, ``c``),
   and of the rest only what stands out of the people's own variation: ``r_s``
   shrunk at each landmark by :data:`SPREAD` times the spread of the rest over the people
   learnt from (:func:`shrink`). A smile's individual style is
   dropped; raised brows or a wink (well beyond that spread) keep most of themselves.

The source's expression is kept about as the paper's stages keep it (the blendshape judge,
:mod:`exprclone.evaluation.blendshape_judge`: the clone's change from the target's neutral face
0.005 +/- 0.011 nearer the source's change than theirs on the pairs below, 0.010 +/- 0.013 further
on those ``docs/results`` reports), with most of the identity gained (0.037 +/- 0.004 less excess
over a real smile as wide). :data:`RIDGE` and
:data:`SPREAD` were chosen on held-out pairs that ``docs/results`` does not report
(``exprclone evaluate --held-out 4`` with ``--seed 1`` and ``--seed 2``, 500 pairs, E+MD): with a
ridge of 1 and the rest shrunk by twice the spread, the clone's change lay 0.028 +/- 0.007 further
from the source's, for 0.003 +/- 0.002 less identity excess. The identity is gained by the rest
shrunk alone: the target's predicted smile in place of the source's (``k f(N_t)`` for
``k f(N_s)``, at a ridge of 1) moved the clone's change 0.019 +/- 0.007 away from the source's and
the identity excess by 0.000 +/- 0.001 (``docs/explanation/fidelity.rst``).

:meth:`ExpressionShape.transfer` gives the target's motion in its photo's pixels. The model
shipped (``exprclone/data/expression_shape.npz``) is learnt from the London Set's 72 people by
``tools/train_expression_shape.py``; ``exprclone evaluate --held-out`` judges models learnt
without the people it clones.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np

from ..landmarks import align
from ..landmarks.layout import Layout
from . import global_warp

#: the ridge penalty of the map from a neutral shape to its smile (in the normalised frame). Held out (four folds of the
#: London Set), the predicted smile at its best share lies as near a person's own as the people's mean smile does at
#: any ridge from 1 up (the mouth's error 0.020 outer-eye-corner distances, 0.022 at 0.1); at 1 the map lets through a
#: person-to-person variation (0.05, beside a smile of 0.19; 0.013 at 10) that the blendshape judge reads as another
#: expression than the source's, with no identity gained (the module's notes).
RIDGE = 10.0
#: the rest of the source's motion is shrunk by this many times the people's own spread of it, at each landmark.
SPREAD = 1.0


def shrink(vectors: np.ndarray, amount: np.ndarray | float) -> np.ndarray:
    """Each vector shortened by ``amount``, and zero if it is shorter (soft thresholding).

    Donoho's soft threshold of a noisy signal, applied to the length of each vector:
    what lies within the noise is dropped, what stands out keeps its direction.

    Parameters
    ----------
    vectors : ndarray of shape (N, 2)
    amount : float or ndarray of shape (N,)

    Returns
    -------
    ndarray of shape (N, 2)

    Examples
    --------
    >>> shrink(np.array([[3.0, 4.0], [0.3, 0.4]]), 1.0).round(6).tolist()
    [[2.4, 3.2], [0.0, 0.0]]
    """
    length = np.linalg.norm(vectors, axis=1)
    keep = np.maximum(1.0 - np.asarray(amount) / np.maximum(length, 1e-12), 0.0)
    return vectors * keep[:, None]


def normalised(neutral: np.ndarray, points: np.ndarray, layout: Layout, vectors: bool = False) -> np.ndarray:
    """``points`` (or, with ``vectors``, motions) in the frame of the face whose neutral landmarks are ``neutral``: the
    eye line along x, the outer eye corners one unit apart, their midpoint at the origin."""
    axes, iod = align.face_axes(neutral, layout), align.interocular(neutral, layout)
    i, j = layout.eye_corners
    origin = 0.0 if vectors else (neutral[i] + neutral[j]) / 2
    return (np.asarray(points, float) - origin) @ axes.T / iod


def parting(points: np.ndarray, layout: Layout) -> float:
    """How far the inner lips part: the mean distance between the inner-lip points facing each other (``layout.lip_pairs``)."""
    return float(np.mean([np.linalg.norm(points[a] - points[b]) for a, b in layout.lip_pairs]))


def in_pixels(neutral: np.ndarray, motion: np.ndarray, layout: Layout) -> np.ndarray:
    """A motion in the normalised frame of the face ``neutral`` (:func:`normalised`) back in its photo's pixels."""
    return motion * align.interocular(neutral, layout) @ align.face_axes(neutral, layout)


@dataclass(frozen=True)
class ExpressionShape:
    """How a face's neutral shape predicts its expression's motion (see the module's notes).

    Attributes
    ----------
    mean_neutral, mean_motion : ndarray of shape (N, 2)
        The people's mean neutral face and mean motion, normalised (:func:`normalised`).
    weights : ndarray of shape (2N, 2N)
        The ridge map from a neutral face's departure from the mean to its motion's.
    parting : ndarray of shape (N, 2)
        The motion beyond the predicted one that goes with the inner lips' parting, of unit norm.
    spread : ndarray of shape (N,)
        The root-mean-square length, at each landmark, of the people's own motion beyond their predicted one and its
        lips' parting.
    """

    mean_neutral: np.ndarray
    mean_motion: np.ndarray
    weights: np.ndarray
    parting: np.ndarray
    spread: np.ndarray

    @classmethod
    def fit(cls, neutrals: Sequence[np.ndarray], motions: Sequence[np.ndarray], layout: Layout, ridge: float = RIDGE) -> ExpressionShape:
        """The model of people's normalised neutral faces and their own motions (:func:`normalised`), ``(N, 2)`` each."""
        x = np.array([n.ravel() for n in neutrals])
        y = np.array([m.ravel() for m in motions])
        mx, my = x.mean(0), y.mean(0)
        xc = x - mx
        weights = np.linalg.solve(xc.T @ xc + ridge * np.eye(x.shape[1]), xc.T @ (y - my))
        shape = neutrals[0].shape
        model = cls(mx.reshape(shape), my.reshape(shape), weights, np.zeros(shape), np.zeros(shape[0]))
        rest = np.array([model.split(n, m)[1].ravel() for n, m in zip(neutrals, motions)])
        parted = np.array([parting(n + m, layout) - parting(n, layout) for n, m in zip(neutrals, motions)])
        direction = (parted - parted.mean()) @ (rest - rest.mean(0))
        direction /= max(float(np.linalg.norm(direction)), 1e-12)
        beyond = (rest - np.outer(rest @ direction, direction)).reshape(len(rest), *shape)
        return cls(model.mean_neutral, model.mean_motion, weights, direction.reshape(shape), np.sqrt((beyond**2).sum(2).mean(0)))

    @classmethod
    def learn(cls, faces: Sequence[tuple[np.ndarray, np.ndarray]], layout: Layout, ridge: float = RIDGE) -> ExpressionShape:
        """The model of people's own neutral and expression landmarks (``(N, 2)`` pixels each, a pair of photos a
        person; the head's motion between them removed, :func:`exprclone.geometry.global_warp.remove_head_motion`)."""
        neutrals = [normalised(n, n, layout) for n, _ in faces]
        motions = [normalised(n, global_warp.remove_head_motion(n, e, layout) - n, layout, vectors=True) for n, e in faces]
        return cls.fit(neutrals, motions, layout, ridge)

    def predicted(self, neutral: np.ndarray) -> np.ndarray:
        """The motion a face of this normalised neutral shape makes: ``f(N)``, ``(N, 2)``."""
        return self.mean_motion + ((neutral - self.mean_neutral).ravel() @ self.weights).reshape(neutral.shape)

    def split(self, neutral: np.ndarray, motion: np.ndarray) -> tuple[float, np.ndarray]:
        """A normalised motion's share ``k >= 0`` of its face's predicted one, and the rest ``motion - k f(N)``."""
        own = self.predicted(neutral)
        share = max(0.0, float(motion.ravel() @ own.ravel()) / max(float(own.ravel() @ own.ravel()), 1e-12))
        return share, motion - share * own

    def transfer(self, source_neutral: np.ndarray, source_motion: np.ndarray, target_neutral: np.ndarray, layout: Layout) -> np.ndarray:
        """The source's motion (``(N, 2)``, pixels, its head's motion removed) as the target's face makes it, in the
        target's pixels: ``k f(N_t)``, the lips parted along ``p`` as far as the source's part (its smile's parting and
        its own beyond it), and the rest shrunk by :data:`SPREAD` times the people's spread."""
        neutral = normalised(source_neutral, source_neutral, layout)
        share, rest = self.split(neutral, normalised(source_neutral, source_motion, layout, vectors=True))
        own, target = self.predicted(neutral), self.predicted(normalised(target_neutral, target_neutral, layout))
        beyond = float(rest.ravel() @ self.parting.ravel())
        parted = beyond + share * float((own - target).ravel() @ self.parting.ravel())
        moved = share * target + parted * self.parting + shrink(rest - beyond * self.parting, SPREAD * self.spread)
        return in_pixels(target_neutral, moved, layout)

    def save(self, path: str | Path) -> None:
        np.savez_compressed(
            path,
            mean_neutral=self.mean_neutral,
            mean_motion=self.mean_motion,
            weights=self.weights,
            parting=self.parting,
            spread=self.spread,
        )

    @classmethod
    def load(cls, path: str | Path) -> ExpressionShape:
        with np.load(path) as f:
            return cls(f["mean_neutral"], f["mean_motion"], f["weights"], f["parting"], f["spread"])


@functools.cache
def default_model() -> ExpressionShape:
    """The model shipped with the package, learnt from the London Set's smiles (``tools/train_expression_shape.py``)."""
    with resources.as_file(resources.files("exprclone") / "data" / "expression_shape.npz") as path:
        return ExpressionShape.load(path)
