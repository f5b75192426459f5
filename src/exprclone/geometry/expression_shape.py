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
   share of its own predicted smile (at least 0), and the rest ``r_s = m_s - k f(N_s)``;
3. the target takes the smile as its own face would make it, ``k f(N_t)``, and of the rest only
   what stands out of the people's own variation: ``r_s`` shrunk at each landmark by
   :data:`SPREAD` times the spread of the rest over the people learnt from
   (:func:`exprclone.geometry.retarget.shrink`). A smile's individual style is dropped; an
   open mouth, raised brows or a wink (well beyond that spread) keeps most of itself.

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
from .retarget import shrink

#: the ridge penalty of the map from a neutral shape to its smile (in the normalised frame; chosen among 0.01 to 100 by
#: the held-out landmark error of the predicted smiles on the London Set: flat from 0.1 to 10).
RIDGE = 1.0
#: the rest of the source's motion is shrunk by this many times the people's own spread of it, at each landmark.
SPREAD = 2.0


def normalised(neutral: np.ndarray, points: np.ndarray, layout: Layout, vectors: bool = False) -> np.ndarray:
    """``points`` (or, with ``vectors``, motions) in the frame of the face whose neutral landmarks are ``neutral``: the
    eye line along x, the outer eye corners one unit apart, their midpoint at the origin."""
    axes, iod = align.face_axes(neutral, layout), align.interocular(neutral, layout)
    i, j = layout.eye_corners
    origin = 0.0 if vectors else (neutral[i] + neutral[j]) / 2
    return (np.asarray(points, float) - origin) @ axes.T / iod


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
    spread : ndarray of shape (N,)
        The root-mean-square length, at each landmark, of the people's own motion beyond their predicted one.
    """

    mean_neutral: np.ndarray
    mean_motion: np.ndarray
    weights: np.ndarray
    spread: np.ndarray

    @classmethod
    def fit(cls, neutrals: Sequence[np.ndarray], motions: Sequence[np.ndarray], ridge: float = RIDGE) -> ExpressionShape:
        """The model of people's normalised neutral faces and their own motions (:func:`normalised`), ``(N, 2)`` each."""
        x = np.array([n.ravel() for n in neutrals])
        y = np.array([m.ravel() for m in motions])
        mx, my = x.mean(0), y.mean(0)
        xc = x - mx
        weights = np.linalg.solve(xc.T @ xc + ridge * np.eye(x.shape[1]), xc.T @ (y - my))
        shape = neutrals[0].shape
        model = cls(mx.reshape(shape), my.reshape(shape), weights, np.zeros(shape[0]))
        rest = np.array([model.split(n, m)[1] for n, m in zip(neutrals, motions)])
        return cls(model.mean_neutral, model.mean_motion, weights, np.sqrt((rest**2).sum(2).mean(0)))

    @classmethod
    def learn(cls, faces: Sequence[tuple[np.ndarray, np.ndarray]], layout: Layout, ridge: float = RIDGE) -> ExpressionShape:
        """The model of people's own neutral and expression landmarks (``(N, 2)`` pixels each, a pair of photos a
        person; the head's motion between them removed, :func:`exprclone.geometry.global_warp.remove_head_motion`)."""
        neutrals = [normalised(n, n, layout) for n, _ in faces]
        motions = [normalised(n, global_warp.remove_head_motion(n, e, layout) - n, layout, vectors=True) for n, e in faces]
        return cls.fit(neutrals, motions, ridge)

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
        target's pixels: ``k f(N_t)`` and the source's rest shrunk by :data:`SPREAD` times the people's spread."""
        share, rest = self.split(
            normalised(source_neutral, source_neutral, layout), normalised(source_neutral, source_motion, layout, vectors=True)
        )
        motion = share * self.predicted(normalised(target_neutral, target_neutral, layout)) + shrink(rest, SPREAD * self.spread)
        return in_pixels(target_neutral, motion, layout)

    def save(self, path: str | Path) -> None:
        np.savez_compressed(path, mean_neutral=self.mean_neutral, mean_motion=self.mean_motion, weights=self.weights, spread=self.spread)

    @classmethod
    def load(cls, path: str | Path) -> ExpressionShape:
        with np.load(path) as f:
            return cls(f["mean_neutral"], f["mean_motion"], f["weights"], f["spread"])


@functools.cache
def default_model() -> ExpressionShape:
    """The model shipped with the package, learnt from the London Set's smiles (``tools/train_expression_shape.py``)."""
    with resources.as_file(resources.files("exprclone") / "data" / "expression_shape.npz") as path:
        return ExpressionShape.load(path)
