"""The expression editor's controls: named motions of a face's landmarks, each from 0 (the face as it is) to 1.

Each control moves the landmarks of one region of the face (:data:`CONTROLS`), in the face's own frame
(:func:`exprclone.geometry.expression_shape.normalised`: the eye line level, the outer eye corners one unit apart),
so that a control is the same motion on a small face or a tilted one. Where real faces show the motion, it is learnt
from them (``made == "learnt"``); where they do not, it is built from the face's anatomy (``"built"``):

- ``smile``, learnt from the London Set's 72 smiles: how a face of these proportions smiles
  (:meth:`exprclone.geometry.expression_shape.ExpressionShape.predicted`), as broad as the upper quartile of the
  people's own smiles (:attr:`Motions.smile_share`);
- ``mouth_open``, ``pucker``, ``eyes_closed``, learnt from the GRID clips' frames: each frame's landmarks (the face mesh's
  68 points) regressed on its blendshape scores (``jawOpen``, ``mouthPucker``, the eyes' ``eyeBlink``), so that each
  motion is what goes with its score alone, the others held; 1 is the largest rise of its score the clips show;
- ``frown``, ``brows_up``, ``brows_down``, ``wink_left``, ``wink_right``, built: the landmarks a muscle moves (the
  depressor anguli oris pulls the mouth corners down, the frontalis lifts the brows, the corrugator draws them down and
  in, one eye's orbicularis closes its lids as a blink does), along a direction and by an amount calibrated with the
  blendshape judge (:mod:`exprclone.landmarks.blendshapes`) so that the control's named score rises, and the other
  regions' scores move least for it: the brows drawn down hold the upper lids up (the levator palpebrae), since the
  warp alone drags the lids' skin down with the brows, which the judge reads as a squint; the brows raised hold the
  eyes down (their upper lids and corners), since the warp stretches the lashes' band up with the brows and the face
  mesh then places the eyes higher, which the judge reads as eyes opened wider (``eyeSquint`` falls).

``tools/train_expression_controls.py`` learns and calibrates them (``exprclone/data/expression_controls.npz``). The
eyes' motions are scaled by the face's own eye opening against the clips' (a narrow eye's lids travel less), and an
eye closes no further than the clips' closed eyes (:func:`limit_lids`).
"""

from __future__ import annotations

import functools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ExprCloneError, quoted
from ..geometry.expression_shape import ExpressionShape, default_model, normalised
from ..geometry.global_warp import remove_head_motion
from ..landmarks.layout import Layout


@dataclass(frozen=True)
class Control:
    """One control of the editor.

    Attributes
    ----------
    name : str
    sentence : str
        What it does, in a sentence (``exprclone edit --list``, the page).
    made : str
        ``"learnt"`` from real faces or ``"built"`` from the face's anatomy.
    source : str
        From what, in words.
    region : str
        The region of the face it moves (a key of :data:`exprclone.landmarks.blendshapes.REGIONS`).
    scores : tuple of str
        The blendshape scores it raises (:data:`exprclone.landmarks.blendshapes.NAMES`): their mean is its judge.
    """

    name: str
    sentence: str
    made: str
    source: str
    region: str
    scores: tuple[str, ...]


GRID = "the GRID clips' frames, their landmarks regressed on their blendshape scores"
#: the controls, in the order they are listed.
CONTROLS = (
    Control("smile", "the mouth corners rise and pull back, the cheeks lift", "learnt",
            "the London Set's 72 smiles, as a face of these proportions smiles", "mouth", ("mouthSmileLeft", "mouthSmileRight")),
    Control("mouth_open", "the jaw drops and the lips part", "learnt", GRID, "mouth", ("jawOpen",)),
    Control("frown", "the mouth corners are pulled down and out", "built",
            "the depressor anguli oris and the platysma: the corners down and out, the lips' sides with them", "mouth",
            ("mouthFrownLeft", "mouthFrownRight")),
    Control("pucker", "the lips gather and push forward, as for a kiss", "learnt", GRID, "mouth", ("mouthPucker",)),
    Control("brows_up", "the brows rise", "built",
            "the frontalis: the brows lifted, evenly; the eyes' upper lids and corners held where they are", "brows",
            ("browInnerUp", "browOuterUpLeft", "browOuterUpRight")),
    Control("brows_down", "the brows are drawn down and together", "built",
            "the corrugator and the procerus: the brows down, their inner ends toward the nose; the upper lids held up",
            "brows",
            ("browDownLeft", "browDownRight")),
    Control("eyes_closed", "both eyes close", "learnt", GRID, "eyes", ("eyeBlinkLeft", "eyeBlinkRight")),
    Control("wink_left", "the left eye (the person's own left) closes", "built",
            "one side's orbicularis oculi: the learnt blink on that eye's lids", "eyes", ("eyeBlinkLeft",)),
    Control("wink_right", "the right eye (the person's own right) closes", "built",
            "one side's orbicularis oculi: the learnt blink on that eye's lids", "eyes", ("eyeBlinkRight",)),
)  # fmt: skip
#: the controls by name.
BY_NAME = {c.name: c for c in CONTROLS}
#: the controls whose motion is read from the data file (the smile's is the smile model's).
STORED = tuple(c.name for c in CONTROLS if c.name != "smile")
#: the smile at 1 is as broad as this quantile of the people's own smiles (their share of their predicted smile).
SMILE_QUANTILE = 0.75
#: an eye is closed no further than this share of its own opening, its lids never crossing (the GRID clips' closed eyes
#: keep about 0.14 of their opening, the lashes' line).
CLOSED = 0.1


def check_values(values: Mapping[str, object]) -> dict[str, float]:
    """Each control's value, checked: a known name, a number from 0 to 1; ExprCloneError about the name otherwise.

    >>> check_values({"smile": 0.5, "brows_up": 1})
    {'smile': 0.5, 'brows_up': 1.0}
    >>> check_values({"smiel": 0.5})  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    exprclone.errors.ExprCloneError: smiel: unknown control; the controls are: smile, mouth_open, ..., wink_right
    """
    checked = {}
    for name, value in values.items():
        if name not in BY_NAME:
            raise ExprCloneError(name, f"unknown control; the controls are: {', '.join(BY_NAME)}")
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 <= value <= 1:
            raise ExprCloneError(name, f"must be a number from 0 to 1, got {quoted(value)}")
        checked[name] = float(value)
    return checked


def parse_values(text: str) -> dict[str, float]:
    """``NAME=VALUE[,NAME=VALUE...]`` as control values (checked by :func:`check_values`).

    >>> parse_values("smile=0.5, brows_up=1")
    {'smile': 0.5, 'brows_up': 1.0}
    """
    values: dict[str, object] = {}
    for part in (p.strip() for p in text.split(",") if p.strip()):
        name, equals, number = (s.strip() for s in part.partition("="))
        try:
            values[name] = float(number) if equals else None
        except ValueError:
            values[name] = number
    return check_values(values)


def eye_opening(points: np.ndarray, layout: Layout) -> np.ndarray:
    """Each eye's opening, ``(2,)``: the mean distance between the facing points of its upper and lower lid (in the
    units of ``points``); the eyes in the layout's order (the person's right, then left)."""
    return np.array([np.mean([np.linalg.norm(points[a] - points[b]) for a, b in lids]) for lids in lid_pairs(layout)])


def lid_pairs(layout: Layout) -> tuple[tuple[tuple[int, int], ...], ...]:
    """For each eye, its upper lid's points paired with the lower lid's facing them (the eye's points run round it
    from the outer corner: the second and third face the sixth and fifth)."""
    return tuple(((eye[1], eye[5]), (eye[2], eye[4])) for eye in layout.eyes)


def limit_lids(neutral: np.ndarray, motion: np.ndarray, layout: Layout) -> np.ndarray:
    """``motion`` (normalised, of the face whose normalised neutral landmarks are ``neutral``) with each eye's motion
    scaled down, if need be, so that the eye keeps at least :data:`CLOSED` of its opening: its lids never cross.

    An eye's opening changes under a motion by the mean change of its facing lid points' distance along the line that
    joins them at rest (negative: it closes), which is linear in the motion.

    >>> from exprclone.landmarks.layout import DLIB68
    >>> face = np.zeros((68, 2))
    >>> face[list(range(36, 48)), 1] = [0, -1, -1, 0, 1, 1, 0, -1, -1, 0, 1, 1]
    >>> motion = np.zeros((68, 2))
    >>> motion[[37, 38], 1] = 3.0  # the right eye's upper lid far through the lower
    >>> eye_opening(face + limit_lids(face, motion, DLIB68), DLIB68).round(6).tolist()  # CLOSED of its opening of 2
    [0.2, 2.0]
    """
    out = motion.copy()
    for eye, pairs, opening in zip(layout.eyes, lid_pairs(layout), eye_opening(neutral, layout)):
        units = [(neutral[b] - neutral[a]) / max(float(np.linalg.norm(neutral[b] - neutral[a])), 1e-12) for a, b in pairs]
        change = float(np.mean([(motion[b] - motion[a]) @ unit for (a, b), unit in zip(pairs, units)]))
        if opening + change < CLOSED * opening:
            out[list(eye)] *= (CLOSED - 1) * opening / change
    return out


def smile_share(model: ExpressionShape, faces: Sequence[tuple[np.ndarray, np.ndarray]], layout: Layout) -> float:
    """The share of its own predicted smile (:meth:`~exprclone.geometry.expression_shape.ExpressionShape.split`) that
    people's real smiles reach at :data:`SMILE_QUANTILE`: ``faces`` are their neutral and smile landmarks (pixels)."""
    shares = []
    for neutral, smile in faces:
        motion = normalised(neutral, remove_head_motion(neutral, smile, layout) - neutral, layout, vectors=True)
        shares.append(model.split(normalised(neutral, neutral, layout), motion)[0])
    return float(np.quantile(shares, SMILE_QUANTILE))


@dataclass(frozen=True)
class Motions:
    """The controls' motions: each stored control's motion at 1, in the normalised frame (see the module's notes).

    Attributes
    ----------
    stored : dict of str to ndarray of shape (N, 2)
        The motion at 1 of each control of :data:`STORED`.
    smile_share : float
        The smile at 1 is this many times the face's predicted smile (the upper quartile of the people's own shares).
    opening : float
        The clips' eyes' mean opening (normalised): the eyes' motions are scaled by a face's own opening over it.
    """

    stored: dict[str, np.ndarray]
    smile_share: float
    opening: float

    def motion(self, name: str, neutral: np.ndarray, layout: Layout, model: ExpressionShape | None = None) -> np.ndarray:
        """Control ``name``'s motion at 1 on the face whose normalised neutral landmarks are ``neutral``, normalised:
        the smile by ``model`` (the shipped one if None), the others as stored, the eyes' scaled by their opening."""
        if name == "smile":
            return self.smile_share * (model or default_model()).predicted(neutral)
        motion = self.stored[name].copy()
        if BY_NAME[name].region == "eyes":
            for eye, opening in zip(layout.eyes, eye_opening(neutral, layout)):
                motion[list(eye)] *= opening / self.opening
        return motion

    def save(self, path: str | Path) -> None:
        arrays: dict[str, Any] = {"smile_share": self.smile_share, "opening": self.opening, **self.stored}
        np.savez_compressed(path, **arrays)

    @classmethod
    def load(cls, path: str | Path) -> Motions:
        with np.load(path) as f:
            return cls({name: f[name] for name in STORED}, float(f["smile_share"]), float(f["opening"]))


@functools.cache
def default_motions() -> Motions:
    """The motions shipped with the package (``tools/train_expression_controls.py``)."""
    with resources.as_file(resources.files("exprclone") / "data" / "expression_controls.npz") as path:
        return Motions.load(path)
