"""Whether the source's two photos are in their roles: one person, its "neutral" face the less expressive of the two.

Not in the paper, which takes its inputs as given. Photos given in the wrong order (the smile as
the source's neutral, or two people as the source) give a clone that frowns or smears with no
error, so :func:`judge_roles` says when they look wrong; the clone goes on (a warning, not an error).

Two measures, on the photos and their landmarks:

- identity (:func:`identity_distance`): the two photos' faces differ by more than an expression
  changes one face. It adds the distance between the two grey crops of the upper face (eye centres
  aligned, :func:`exprclone.geometry.eigenface.crop`; the rows from the brows to the upper lip, which a
  smile changes least; zero mean and unit norm each, so the light's level and contrast drop out)
  and :data:`SHAPE_WEIGHT` times the root-mean-square distance between the eye corners and nose
  bridge of the two faces, similarity-aligned, in eye distances (a face's proportions);
- expressiveness (:func:`expressiveness`): how far a face's moving landmarks (brows, lids,
  lips) lie from :data:`NEUTRAL_FACE`, the mean neutral face of the London Set, once the
  face's rigid landmarks are aligned on it (root-mean-square, in eye distances). One person's
  proportions move both photos alike, so of two photos of one person the more expressive is the
  farther.

The bounds (:data:`MAX_IDENTITY`, :data:`MIN_SWAP`) and the rates they give on the London Set
(right order flagged, swapped or mismatched caught) are measured by ``tools/role_check.py``.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from importlib import resources

import numpy as np

from ..geometry.eigenface import crop, normalise
from ..landmarks import align
from ..landmarks.layout import Layout

#: rows of the 64-pixel eye-aligned crop compared for identity: from the brows to the upper lip.
IDENTITY_ROWS = slice(8, 44)
#: the weight of the landmarks' distance (eye distances) beside the crops' (unit-norm) in the identity distance.
SHAPE_WEIGHT = 20.0
#: the identity distance over which the source's two photos look like two people.
MAX_IDENTITY = 1.13
#: how much more expressive (eye distances) the "neutral" photo must look than the "expression" to be called swapped.
MIN_SWAP = 0.007


def _neutral_face() -> np.ndarray:
    with resources.as_file(resources.files("exprclone") / "data" / "neutral_face.json") as path:
        return np.array(json.loads(path.read_text())["landmarks"], float)


#: the mean neutral face of the London Set's 72 people (dlib's 68 points, outer eye corners at (0, 0) and (1, 0)),
#: written by ``tools/role_check.py --write-template``.
NEUTRAL_FACE = _neutral_face()


@dataclass(frozen=True)
class Photo:
    """What the role check takes of a photo: its landmarks and its eye-aligned grey crop (:func:`exprclone.geometry.eigenface.crop`).

    A clone whose lambda_k the DB metric chooses compares the same crop of the source's expression
    (:func:`exprclone.geometry.db_metric.choose_lambda`): :func:`exprclone.clone_methods` makes it once for both.
    """

    points: np.ndarray
    crop: np.ndarray

    @classmethod
    def of(cls, image: np.ndarray, points: np.ndarray, layout: Layout) -> Photo:
        """The role check's view of an ``(H, W, 3)`` photo with its ``(N, 2)`` landmarks."""
        return cls(points, crop(image, points, layout))


def identity_distance(a: Photo, b: Photo, layout: Layout) -> float:
    """How unlike two faces are, beyond an expression (see the module's notes): 0 for one photo twice."""
    crops = normalise(np.stack([p.crop[IDENTITY_ROWS] for p in (a, b)]))
    idx = [k for k in layout.rigid if k not in layout.jaw]  # the nose bridge and the eye corners
    pa, pb = (p.points / align.interocular(p.points, layout) for p in (a, b))
    aligned = align.apply(align.fit_similarity(pa[idx], pb[idx]), pa[idx])
    shape = float(np.sqrt(((aligned - pb[idx]) ** 2).sum(1).mean()))
    return float(np.linalg.norm(crops[0] - crops[1])) + SHAPE_WEIGHT * shape


def expressiveness(points: np.ndarray, layout: Layout) -> float:
    """How far a face's moving landmarks lie from :data:`NEUTRAL_FACE`, its rigid landmarks aligned on it (eye distances)."""
    unit = points / align.interocular(points, layout)
    aligned = align.apply(align.fit_rigid(unit, NEUTRAL_FACE, layout), unit)
    moving = [k for organ in (*layout.brows, *layout.eyes, layout.mouth_outer, layout.mouth_inner) for k in organ if k not in layout.rigid]
    return float(np.sqrt(((aligned[moving] - NEUTRAL_FACE[moving]) ** 2).sum(1).mean()))


def judge_roles(neutral: Photo, expression: Photo, layout: Layout) -> list[str]:
    """What looks wrong with the source's two photos, as messages (none when they look right).

    Parameters
    ----------
    neutral, expression : Photo
        The source's photos as given: its neutral face, and its expression.
    layout : Layout

    Returns
    -------
    list of str
        "two different people" when :func:`identity_distance` is over :data:`MAX_IDENTITY`; "the
        neutral face looks more expressive" when its :func:`expressiveness` exceeds the
        expression's by :data:`MIN_SWAP` (only for one person: two people's faces differ anyway).
    """
    if identity_distance(neutral, expression, layout) > MAX_IDENTITY:
        return ["source_expression: looks like another person than source_neutral; the source's two photos should show one person"]
    if expressiveness(neutral.points, layout) - expressiveness(expression.points, layout) > MIN_SWAP:
        return ["source_neutral: looks more expressive than source_expression; are the source's two photos swapped?"]
    return []
