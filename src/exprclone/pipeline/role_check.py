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

Which photo is the neutral face, judged by what any expression does to a face (not by how much it
looks like a smile alone: a sad or a surprised face is no smile, a speaker's open mouth neither). Five
views, each saying how far the photos look swapped:

- :func:`rise`: the blendshape scores (:mod:`exprclone.landmarks.blendshapes`, MediaPipe's 52
  named expressions, from the mesh fitted at the face's landmarks: :func:`scores`), each in units
  of how far people's faces at rest score apart (:data:`REST`, the London Set's neutral photos):
  an expression raises the scores of what it does (``jawOpen``, ``mouthFrownLeft``,
  ``browInnerUp``, ``mouthSmileLeft``, ...) far more than it lowers others; the sum of the
  :data:`TOP` largest rises and the :data:`TOP` largest falls from the "neutral" photo to the
  "expression" is negative when the two are swapped;
- :func:`from_rest`: how far a face's scores lie from people's at rest (root-mean-square, in the
  same units): the "neutral" photo lies farther when the two are swapped;
- :func:`expressiveness`: how far a face's moving landmarks (brows, lids, lips) lie from
  :data:`NEUTRAL_FACE`, the mean neutral face of the London Set, once its rigid landmarks are
  aligned on it (root-mean-square, in eye distances): any expression moves them;
- :func:`smiling`: the two smile scores (``mouthSmileLeft``, ``mouthSmileRight``): the commonest
  expression, whose weakest forms the three views above hardly see; the "neutral" photo smiles
  more when the two are swapped;
- :func:`width`: the distance between the mouth's corners (in eye distances): a smile, even
  one the scores hardly see, pulls them apart; the "neutral" photo's mouth is the wider when the two
  are swapped. A pucker narrows the mouth, and a speaker's open mouth often does: of such an expression
  in the right order this view alone says "swapped".

Each view's say (:func:`says`) is counted in units of what a change of light alone gives it
(:data:`MARGINS`: the spread of its value between a London photo and the same photo made grey,
relit by +-15% from one ear to the other, or given another white balance), positive for
"swapped"; each is clipped to +-:data:`CAP` and the five summed: the photos look swapped when the
sum reaches :data:`SWAPPED`. The cap keeps one view from deciding alone: the mouth's width moves by
about ten margins with a London smile (the median), and the wrong way by up to eight with a speaker's
open mouth and ten with the expression editor's pucker; capped, it warns only when the other four
do not lean against it (their sum 0 or more); and a view that says "right order" takes from the
others' say, where a count of votes would not hear it. A face at rest is not quite still in any one view
(a speaker's closed mouth presses its lips, a weak smile hardly moves the blendshapes); the views
seldom err together. A pucker is the expression the check misjudges most: of the London Set's
neutral photos puckered by the editor, in the right order, a third to nearly a half are flagged.

The rates this gives on the London Set (the mean face and the scores at rest learnt without the
person judged), on its photos made grey, relit or given another white balance, on its neutral
photos edited into other expressions by the expression editor, and on GRID's speakers (a closed
frame as the neutral face, each open-mouth frame as the expression) are measured by
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
from ..landmarks import align, blendshapes
from ..landmarks.dlib import model_path
from ..landmarks.layout import DLIB68, Layout
from ..mouth import measure
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
#: the blendshape scores whose rises and falls say which way a pair of photos goes (:func:`rise`): an expression's
#: few (the blendshape judge's "scores each source raises most").
TOP = 4
#: the least spread of a score at rest (:data:`REST`): a score that no neutral face raises is not told apart to finer
#: than the scorer's own steps (its scores move by 0.006 in the median, up to 0.035, with the light alone).
REST_FLOOR = 0.02
#: the smile scores :func:`smiling` adds.
SMILE = blendshapes.indices(("mouthSmileLeft", "mouthSmileRight"))
#: the views' units (:func:`says`): one standard deviation of the change that light alone makes to :func:`rise`,
#: :func:`from_rest` (score units at rest), :func:`expressiveness` (eye distances), :func:`smiling` (scores) and
#: :func:`width` (eye distances) (a London photo against itself made grey, relit or given another white balance:
#: ``tools/role_check.py --noise``).
MARGINS = (1.74, 0.148, 0.0029, 0.037, 0.0095)
#: the most any one view says (in its margins, either way) in :func:`swapped`'s sum. It and :data:`SWAPPED` were chosen
#: on the London Set alone: any cap from 1.5 to 3 with any sum from 1 to 4 tells its 72 swaps and none of its right
#: orders, in every light.
CAP = 2.0
#: the sum of the views' capped says (margins) from which the photos look swapped.
SWAPPED = 2.0


def _learnt() -> dict[str, Any]:
    with resources.as_file(resources.files("exprclone") / "data" / "neutral_face.json") as path:
        return dict(json.loads(path.read_text()))


_LEARNT = _learnt()
#: the mean neutral face of the London Set's 72 people (dlib's 68 points, outer eye corners at (0, 0) and (1, 0)),
#: written by ``tools/role_check.py --write-template``.
NEUTRAL_FACE = np.array(_LEARNT["landmarks"], float)
#: the places of the expression's scores among the 52 (:data:`exprclone.landmarks.blendshapes.EXPRESSION`: no gaze).
EXPRESSION = blendshapes.indices(blendshapes.EXPRESSION)
#: people's faces at rest: the mean of each expression score (:data:`EXPRESSION`) over the London Set's neutral photos,
#: and its spread (the standard deviation and :data:`REST_FLOOR` added in quadrature), written with :data:`NEUTRAL_FACE`.
REST = (np.array(_LEARNT["rest_mean"], float), np.array(_LEARNT["rest_spread"], float))


def scores(image: np.ndarray, points: np.ndarray, layout: Layout) -> np.ndarray:
    """The blendshape scores ``(52,)`` of the face with these landmarks in an ``(H, W, 3)`` uint8 RGB photo
    (:meth:`exprclone.landmarks.blendshapes.Blendshapes.scores_at`: the mesh fitted where the landmarks are)."""
    return blendshapes.shared().scores_at(image, points, layout.eye_corners)


@dataclass(frozen=True)
class Face:
    """A face as the role check sees it: its landmarks, its eye-aligned grey crop
    (:func:`exprclone.geometry.eigenface.crop`), and the photo for its descriptor and its blendshape scores, each made
    when first asked for.

    The door keeps it with its photo (:meth:`exprclone.pipeline.request.Photo.seen`).
    """

    points: np.ndarray
    crop: np.ndarray
    image: np.ndarray = field(repr=False, compare=False)
    layout: Layout = field(default=DLIB68, repr=False, compare=False)

    @classmethod
    def of(cls, image: np.ndarray, points: np.ndarray, layout: Layout) -> Face:
        """The role check's view of an ``(H, W, 3)`` photo with its ``(N, 2)`` landmarks."""
        return cls(points, crop(image, points, layout), image, layout)

    @functools.cached_property
    def descriptor(self) -> np.ndarray:
        """Its face's :func:`descriptor`."""
        return descriptor(self.image, self.points)

    @functools.cached_property
    def scores(self) -> np.ndarray:
        """Its face's blendshape :func:`scores` ``(52,)``."""
        return scores(self.image, self.points, self.layout)


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


def from_rest(face: np.ndarray) -> float:
    """How far a face's blendshape scores ``(52,)`` lie from people's at rest (:data:`REST`): the root-mean-square over
    the expression's scores of their departures, each over its spread at rest; more for an expression."""
    mean, spread = REST
    return float(np.sqrt((((face[EXPRESSION] - mean) / spread) ** 2).mean()))


def rise(neutral: np.ndarray, expression: np.ndarray) -> float:
    """How much the scores ``(52,)`` rise from ``neutral`` to ``expression``: the sum of the :data:`TOP` largest changes
    and the :data:`TOP` smallest (the largest falls), each over its spread at rest (:data:`REST`); positive for an
    expression after its neutral face, negative for the two swapped."""
    change = np.sort((expression[EXPRESSION] - neutral[EXPRESSION]) / REST[1])
    return float(change[-TOP:].sum() + change[:TOP].sum())


def smiling(face: np.ndarray) -> float:
    """How much a face smiles: the sum of its blendshape scores ``(52,)`` named :data:`SMILE`."""
    return float(face[SMILE].sum())


def width(points: np.ndarray, layout: Layout) -> float:
    """How wide a face's mouth is: the distance between its corners (:func:`exprclone.mouth.measure.mouth_width`), in
    eye distances."""
    return measure.mouth_width(points, layout) / align.interocular(points, layout)


def says(neutral: Face, expression: Face, layout: Layout) -> np.ndarray:
    """How far each view says the source's photos are swapped (the module's notes), in its margins (:data:`MARGINS`),
    positive for "swapped" ``(5,)``: the scores' fall (:func:`rise`), how much farther from rest the "neutral" photo's
    scores lie (:func:`from_rest`) and its landmarks from the mean neutral face (:func:`expressiveness`), how much more
    it smiles (:func:`smiling`) and how much wider its mouth is (:func:`width`)."""
    n, e = neutral.scores, expression.scores
    views = (
        -rise(n, e),
        from_rest(n) - from_rest(e),
        expressiveness(neutral.points, layout) - expressiveness(expression.points, layout),
        smiling(n) - smiling(e),
        width(neutral.points, layout) - width(expression.points, layout),
    )
    return np.array(views) / np.array(MARGINS)


def swapped(neutral: Face, expression: Face, layout: Layout) -> bool:
    """Whether the source's photos look swapped: the views' :func:`says`, each clipped to +-:data:`CAP`, sum to
    :data:`SWAPPED` or more."""
    return float(np.clip(says(neutral, expression, layout), -CAP, CAP).sum()) >= SWAPPED


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
    if swapped(neutral, expression, layout):
        return [f"{SOURCE_NEUTRAL}: looks more expressive than {SOURCE_EXPRESSION}; are the source's two photos swapped?"]
    return []
