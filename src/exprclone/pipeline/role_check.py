"""Whether the three photos are in their roles: the source's two one person, its "neutral" face the less expressive.

Not in the paper, which takes its inputs as given. Photos given in the wrong boxes (the smile as
the source's neutral, two people as the source, the target's photo as one of the source's) give a
clone that frowns or smears with no error, so :func:`judge_roles` says when they look wrong; the
clone goes on (a warning, not an error).

Who a face is:

- :func:`identity_distance`: the distance between two faces' 128-d descriptors from dlib's ResNet
  (:func:`descriptor`; the model shipped in ``face-recognition-models``, released into the public
  domain by its author), which was trained to put each person's faces within 0.6 of each other
  (:data:`SAME_PERSON`), whatever their expression;
- :func:`appearance_distance`, a quick first look: the distance between the two grey crops of the
  upper face (eye centres aligned, :func:`exprclone.geometry.eigenface.crop`; the rows from the brows
  to the upper lip, which a smile changes least; zero mean and unit norm each) plus
  :data:`SHAPE_WEIGHT` times the root-mean-square distance between the eye corners and nose bridge
  of the two faces, similarity-aligned, in eye distances. Two photos closer than
  :data:`SURELY_SAME` are one person's, and the descriptors (about 0.2 s a photo) are not computed.

Which photo is the neutral face:

- :func:`expressiveness`: how far a face's moving landmarks (brows, lids, lips) lie from
  :data:`NEUTRAL_FACE`, the mean neutral face of the London Set, once its rigid landmarks are
  aligned on it (root-mean-square, in eye distances): any expression moves them;
- :func:`smile`: how far they lie along :data:`SMILE`, the direction in which the London Set's
  smiles move them from each person's neutral face (a ridge regression). A weak smile hardly
  changes the expressiveness, but it always moves the landmarks this way.

The source's photos look swapped when the "neutral" one is more expressive by over
:data:`MIN_SWAP`, or when it smiles more and is not clearly less expressive (by :data:`GATE`:
an expression that is no smile, a surprise, may smile less than a neutral face, but it moves the
face far more).

The bounds, and the rates they give on the London Set for every kind of mistake (the smile's
direction and the mean face learnt without the person judged), are measured by
``tools/role_check.py``.
"""

from __future__ import annotations

import functools
import json
from dataclasses import dataclass, field
from importlib import resources
from typing import Any

import numpy as np

from ..geometry.eigenface import crop, normalise
from ..landmarks import align
from ..landmarks.dlib import model_path
from ..landmarks.layout import Layout
from ..roles import SOURCE_EXPRESSION, SOURCE_NEUTRAL, TARGET_NEUTRAL

#: rows of the 64-pixel eye-aligned crop compared for appearance: from the brows to the upper lip.
IDENTITY_ROWS = slice(8, 44)
#: the weight of the landmarks' distance (eye distances) beside the crops' (unit-norm) in the appearance distance.
SHAPE_WEIGHT = 20.0
#: the appearance distance under which two photos are taken for one person's without their descriptors (no two
#: people of the London Set come closer than 0.66; one person's two photos: 44% of them).
SURELY_SAME = 0.6
#: the descriptors' distance under which two faces are one person's (dlib's: its model was trained to it).
SAME_PERSON = 0.6
#: how much more expressive (eye distances) the "neutral" photo must look than the "expression" to be called swapped.
MIN_SWAP = 0.01
#: how much less expressive the "neutral" photo may look, and still be called swapped when it smiles more.
GATE = 0.01


def _learnt() -> dict[str, Any]:
    with resources.as_file(resources.files("exprclone") / "data" / "neutral_face.json") as path:
        return dict(json.loads(path.read_text()))


_LEARNT = _learnt()
#: the mean neutral face of the London Set's 72 people (dlib's 68 points, outer eye corners at (0, 0) and (1, 0)),
#: written by ``tools/role_check.py --write-template``.
NEUTRAL_FACE = np.array(_LEARNT["landmarks"], float)
#: the direction in which a smile moves the moving landmarks (:func:`moving`) of a face aligned on
#: :data:`NEUTRAL_FACE`, written with it: a smile's :func:`smile` exceeds its neutral face's.
SMILE = np.array(_LEARNT["smile"], float)


@dataclass(frozen=True)
class Face:
    """A face as the role check sees it: its landmarks, its eye-aligned grey crop
    (:func:`exprclone.geometry.eigenface.crop`), and the photo for its descriptor, made when first asked for.

    The door keeps it with its photo (:meth:`exprclone.pipeline.request.Photo.seen`).
    """

    points: np.ndarray
    crop: np.ndarray
    image: np.ndarray = field(repr=False, compare=False)

    @classmethod
    def of(cls, image: np.ndarray, points: np.ndarray, layout: Layout) -> Face:
        """The role check's view of an ``(H, W, 3)`` photo with its ``(N, 2)`` landmarks."""
        return cls(points, crop(image, points, layout), image)

    @functools.cached_property
    def descriptor(self) -> np.ndarray:
        """Its face's :func:`descriptor`."""
        return descriptor(self.image, self.points)


@functools.cache
def _model():  # type: ignore[no-untyped-def]  # (dlib has no type information)
    import dlib  # (heavy: loaded when a face is looked at)

    return dlib.face_recognition_model_v1(model_path("dlib_face_recognition_resnet_model_v1.dat"))


def descriptor(image: np.ndarray, points: np.ndarray) -> np.ndarray:
    """dlib's 128-d descriptor of the face with these 68 landmarks in an ``(H, W, 3)`` uint8 RGB photo."""
    import dlib  # (heavy: loaded when a face is looked at)

    lo, hi = points.min(0), points.max(0)
    box = dlib.rectangle(*(int(v) for v in (lo[0], lo[1], hi[0], hi[1])))
    shape = dlib.full_object_detection(box, [dlib.point(int(round(x)), int(round(y))) for x, y in points])
    return np.array(_model().compute_face_descriptor(np.ascontiguousarray(image), shape))


def identity_distance(a: np.ndarray, b: np.ndarray) -> float:
    """The distance between two :func:`descriptor` s: under :data:`SAME_PERSON` for one person's faces."""
    return float(np.linalg.norm(a - b))


def appearance_distance(a: Face, b: Face, layout: Layout) -> float:
    """How unlike two faces look, beyond an expression (see the module's notes): 0 for one photo twice."""
    crops = normalise(np.stack([p.crop[IDENTITY_ROWS] for p in (a, b)]))
    idx = [k for k in layout.rigid if k not in layout.jaw]  # the nose bridge and the eye corners
    pa, pb = (p.points / align.interocular(p.points, layout) for p in (a, b))
    aligned = align.apply(align.fit_similarity(pa[idx], pb[idx]), pa[idx])
    shape = float(np.sqrt(((aligned - pb[idx]) ** 2).sum(1).mean()))
    return float(np.linalg.norm(crops[0] - crops[1])) + SHAPE_WEIGHT * shape


def one_person(a: Face, b: Face, layout: Layout) -> bool:
    """Whether two photos show one person: alike at a first look (:data:`SURELY_SAME`), or by their descriptors."""
    return appearance_distance(a, b, layout) < SURELY_SAME or identity_distance(a.descriptor, b.descriptor) < SAME_PERSON


def moving(points: np.ndarray, layout: Layout) -> np.ndarray:
    """A face's moving landmarks (brows, lids, lips; not the rigid ones), in eye distances, its rigid landmarks aligned
    on :data:`NEUTRAL_FACE`: ``(M, 2)``."""
    unit = points / align.interocular(points, layout)
    aligned = align.apply(align.fit_rigid(unit, NEUTRAL_FACE, layout), unit)
    organs = (*layout.brows, *layout.eyes, layout.mouth_outer, layout.mouth_inner)
    return aligned[[k for organ in organs for k in organ if k not in layout.rigid]]


def expressiveness(points: np.ndarray, layout: Layout) -> float:
    """How far a face's :func:`moving` landmarks lie from :data:`NEUTRAL_FACE`'s (root-mean-square, eye distances)."""
    return float(np.sqrt(((moving(points, layout) - moving(NEUTRAL_FACE, layout)) ** 2).sum(1).mean()))


def smile(points: np.ndarray, layout: Layout) -> float:
    """How far a face's :func:`moving` landmarks lie along :data:`SMILE`: more for a smile than for its neutral face."""
    return float(moving(points, layout).ravel() @ SMILE)


def swapped(neutral: np.ndarray, expression: np.ndarray, layout: Layout) -> bool:
    """Whether the source's photos with these landmarks look swapped (the module's notes)."""
    more = expressiveness(neutral, layout) - expressiveness(expression, layout)
    return more > MIN_SWAP or (smile(neutral, layout) > smile(expression, layout) and more > -GATE)


def judge_roles(neutral: Face, expression: Face, layout: Layout, target: Face | None = None) -> list[str]:
    """What looks wrong with the photos, as messages (none when they look right).

    Parameters
    ----------
    neutral, expression : Face
        The source's photos as given: its neutral face, and its expression.
    layout : Layout
    target : Face, optional
        The target's photo as given: when the source's two photos show two people, whether it shows one of them says
        which photos were swapped.

    Returns
    -------
    list of str
        Two people (:func:`one_person`), and which boxes look swapped when the target's photo shows one of them; else
        "the neutral face looks more expressive" when the two look swapped (:func:`swapped`).
    """
    if not one_person(neutral, expression, layout):
        for odd, kept, photo in ((SOURCE_NEUTRAL, SOURCE_EXPRESSION, expression), (SOURCE_EXPRESSION, SOURCE_NEUTRAL, neutral)):
            if target is not None and one_person(target, photo, layout):  # the target's photo shows the one kept
                return [
                    f"{odd}: looks like another person than {kept}, and {TARGET_NEUTRAL} like the same person as {kept};"
                    f" are {odd} and {TARGET_NEUTRAL} swapped?"
                ]
        return [f"{SOURCE_EXPRESSION}: looks like another person than {SOURCE_NEUTRAL}; the source's two photos should show one person"]
    if swapped(neutral.points, expression.points, layout):
        return [f"{SOURCE_NEUTRAL}: looks more expressive than {SOURCE_EXPRESSION}; are the source's two photos swapped?"]
    return []
