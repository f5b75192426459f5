"""Learn and calibrate the expression editor's controls, shipped in src/exprclone/data/expression_controls.npz.

    python tools/train_expression_controls.py [--data ../shared/data] [-o src/exprclone/data/expression_controls.npz]

What it makes (:mod:`exprclone.expressions.controls`), every motion in the face's own frame
(:func:`exprclone.geometry.expression_shape.normalised`):

1. **Learnt from the GRID clips** (Cooke et al. 2006, CC BY 4.0; ``--data``'s ``grid/*.mpg``): on every frame, the
   face mesh's 68 points (:data:`exprclone.landmarks.mesh_layout.MESH_TO_68`; dlib's do not follow a blink on these
   360x288 frames: they close an eye half-way where the mesh closes it) and the blendshape scores read from the same
   mesh. Within each clip, each frame's motion from the clip's median shape (its head's motion removed) is regressed
   on its scores' departures from the clip's means, over all clips at once: ``jawOpen``, ``mouthPucker`` and the
   eyes' mean ``eyeBlink`` (:data:`REGRESSORS`), so that each coefficient is the motion that goes with its score alone,
   the others held. A control's motion at 1 is its coefficient times the largest rise of its score in any clip (the
   widest opening, the fullest pucker, the closed eyes), kept on its region's landmarks (the mouth's and the jaw's, or
   the eyes'); the eyes' mean opening over the clips is kept to scale a face's own.
2. **The smile's breadth** (London Set, DeBruine and Jones 2017, CC BY 4.0): the smile at 1 is the shipped smile
   model's predicted smile times the upper quartile of the 72 people's own shares of theirs
   (:func:`exprclone.expressions.controls.smile_share`; the people's landmarks by dlib, as the model was learnt).
3. **Built from the anatomy** (:data:`ANATOMY`): for each control, the landmarks a muscle moves and a few candidate
   directions of them (the person's right side given, the left mirrored). Each candidate is rendered by the editor
   at growing amounts (:data:`AMOUNTS`, outer-eye-corner distances at the landmark moved most) on :data:`CALIBRATION`
   London people who do not judge the editor (:func:`exprclone.evaluation.editor_judge.held_out`), and scored by the
   blendshape model: a candidate's amount is the least at which its named scores rise by :data:`TARGET` on average;
   the candidate kept is the one whose other regions' scores move least for that rise (the score of another region
   that moves most, on average, over the rise; :meth:`Calibration.calibrate`); the amounts stay within what the
   muscles do (the brows lowered by about a centimetre at most). A wink is the learnt blink on one
   eye's lids (one side's orbicularis oculi): its eye closed at 1, as ``eyes_closed`` closes both; its rise is printed.

It prints what it learnt and every candidate's scores.
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import numpy as np

from exprclone.data import sets as datasets
from exprclone.evaluation.editor_judge import held_out, others
from exprclone.evaluation.london import Dataset
from exprclone.expressions import editor as editing
from exprclone.expressions.controls import BY_NAME, STORED, Motions, eye_opening, smile_share
from exprclone.geometry.expression_shape import default_model, normalised
from exprclone.geometry.global_warp import remove_head_motion
from exprclone.io.images import load_image
from exprclone.io.video import read_frames
from exprclone.landmarks.backends import shared
from exprclone.landmarks.blendshapes import Blendshapes, indices
from exprclone.landmarks.layout import DLIB68
from exprclone.landmarks.mesh_layout import MESH_POINTS, to_68

ROOT = Path(__file__).resolve().parents[1]
#: each learnt control and the scores whose mean is its regressor.
REGRESSORS = {"mouth_open": ("jawOpen",), "pucker": ("mouthPucker",), "eyes_closed": ("eyeBlinkLeft", "eyeBlinkRight")}
#: a clip shows a motion when its score rises this much within it (said, for the record).
SHOWN = 0.2
#: London people a built control is calibrated on (none of those who judge the editor).
CALIBRATION = 12
#: the mean rise of its named scores a built control is calibrated to reach at 1.
TARGET = 0.35
#: the amounts tried, in outer-eye-corner distances at the landmark a candidate moves most.
AMOUNTS = {"brows_up": (0.06, 0.08, 0.10, 0.12, 0.14, 0.16), "brows_down": (0.04, 0.06, 0.08, 0.10, 0.12)}
AMOUNTS["frown"] = (0.1, 0.125, 0.15, 0.175, 0.2, 0.225, 0.25)
R_BROW = (17, 18, 19, 20, 21)
#: the upper lid's points of the person's right eye.
R_UPPER_LID = (37, 38)
#: the upper lid's points and the corners of the person's right eye.
R_UPPER_EYE = (36, 37, 38, 39)
#: the lips' points on the person's right, the corner pulled down and out, the others less as they lie nearer the middle.
STRETCH = {
    48: (-0.6, 0.8),
    60: (-0.55, 0.75),
    49: (-0.3, 0.35),
    59: (-0.35, 0.45),
    61: (-0.15, 0.2),
    67: (-0.2, 0.3),
    50: (-0.1, 0.1),
    58: (-0.15, 0.2),
}
#: the built controls' candidates: the person's right side's landmarks (and the midline's), each with its direction
#: (x toward the person's left, y down), the left side mirrored (:attr:`exprclone.landmarks.layout.Layout.mirror`).
ANATOMY: dict[str, dict[str, dict[int, tuple[float, float]]]] = {
    "brows_up": {  # the frontalis lifts the brows: evenly, more at their inner ends, or more at their outer ends
        "even": dict.fromkeys(R_BROW, (0.0, -1.0)),
        "inner": dict(zip(R_BROW, ((0.0, -0.4), (0.0, -0.6), (0.0, -0.8), (0.0, -1.0), (0.0, -1.0)))),
        "outer": dict(zip(R_BROW, ((0.0, -1.0), (0.0, -1.0), (0.0, -0.9), (0.0, -0.7), (0.0, -0.5)))),
        # a raised brow lifts the upper lid's skin and widens the eye a little: the lid follows the brow by a tenth
        "even, the lid lifted with it": {**dict.fromkeys(R_BROW, (0.0, -1.0)), **dict.fromkeys(R_UPPER_LID, (0.0, -0.1))},
        # the eye held where it is (the lid's margin is the levator's, the corners the canthal tendons', not the
        # frontalis'): the warp stretches the lashes' band up with the brow, and the face mesh (dlib too) then places the
        # eye higher, its upper lid most, which the blendshape model reads as an eye opened wider (eyeSquint falls); the
        # upper lid's points, or the lid's and the corners', lowered by a share of the brow's lift keep it where it was read
        **{
            f"even, the {held} held ({share:g})": {**dict.fromkeys(R_BROW, (0.0, -1.0)), **dict.fromkeys(points, (0.0, share))}
            for held, points in (("lid", R_UPPER_LID), ("lid and corners", R_UPPER_EYE))
            for share in (0.1, 0.2, 0.3)
        },
    },
    "brows_down": {  # the corrugator draws the inner brows down and toward the midline; the procerus lowers them
        "down and in": dict(zip(R_BROW, ((0.0, 0.2), (0.0, 0.3), (0.15, 0.5), (0.35, 0.8), (0.5, 1.0)))),
        "down and in, evenly": dict(zip(R_BROW, ((0.0, 1.0), (0.1, 1.0), (0.2, 1.0), (0.35, 1.0), (0.5, 1.0)))),
        # the same, the upper lid held up (the levator palpebrae): the warp alone drags the lid's skin down with the brow,
        # which the blendshape model reads as a squint
        "down and in, evenly, the lid held up": {
            **dict(zip(R_BROW, ((0.0, 1.0), (0.1, 1.0), (0.2, 1.0), (0.35, 1.0), (0.5, 1.0)))),
            **dict.fromkeys(R_UPPER_LID, (0.0, -0.4)),
        },
        "even": dict.fromkeys(R_BROW, (0.0, 1.0)),
    },
    "frown": {  # the depressor anguli oris pulls the mouth corners down, the platysma and risorius out; the lips follow
        "down and out": STRETCH,
        "down, half out": {k: (0.5 * dx, dy) for k, (dx, dy) in STRETCH.items()},
        "lower lip down": {
            48: (-0.3, 1.0),
            60: (-0.3, 1.0),
            59: (-0.2, 1.0),
            58: (-0.1, 0.7),
            57: (0.0, 0.5),
            67: (-0.2, 0.9),
            66: (0.0, 0.5),
            49: (-0.15, 0.4),
            61: (-0.1, 0.3),
        },
    },
}


def mirrored(side: dict[int, tuple[float, float]], n: int) -> np.ndarray:
    """A candidate's motion ``(n, 2)``: the given side, and its mirror image across the face's midline; its largest
    vector of length 1."""
    motion = np.zeros((n, 2))
    for i, (dx, dy) in side.items():
        motion[i] = dx, dy
        motion[DLIB68.mirror[i]] = -dx if DLIB68.mirror[i] != i else dx, dy
    return motion / np.linalg.norm(motion, axis=1).max()


def clip(path: Path, judge: Blendshapes) -> tuple[np.ndarray, np.ndarray, float]:
    """A clip's frames' motions ``(T, 68, 2)`` from its median shape (normalised, the head's motion removed), their
    scores ``(T, 52)`` (the face mesh on each frame), and the median shape's eye opening (normalised)."""
    meshes = [judge.mesh.detect_mesh(frame, str(path)) for frame in read_frames(path)]
    points = np.array([to_68(m[:MESH_POINTS]) for m in meshes])
    scores = np.array([judge.of_mesh(m) for m in meshes])
    reference = np.median(points, axis=0)
    motions = np.array([normalised(reference, remove_head_motion(reference, p, DLIB68) - reference, DLIB68, vectors=True) for p in points])
    return motions, scores, float(eye_opening(normalised(reference, reference, DLIB68), DLIB68).mean())


def learn_from_clips(folder: Path, judge: Blendshapes) -> tuple[dict[str, np.ndarray], float]:
    """The learnt controls' motions at 1 and the clips' mean eye opening (the module's notes, 1)."""
    x, y, openings = [], [], []
    rises: dict[str, list[float]] = {name: [] for name in REGRESSORS}
    for path in sorted(folder.glob("*.mpg")):
        motions, scores, opening = clip(path, judge)
        regressors = np.stack([scores[:, indices(names)].mean(1) for names in REGRESSORS.values()], 1)
        x.append(regressors - regressors.mean(0))
        y.append((motions - motions.mean(0)).reshape(len(motions), -1))
        openings.append(opening)
        for name, column in zip(REGRESSORS, regressors.T):
            rises[name].append(float(column.max() - column.min()))
        print(f"  {path.name}: {len(motions)} frames, rises " + ", ".join(f"{n} {r[-1]:.2f}" for n, r in rises.items()))
    xs, ys = np.concatenate(x), np.concatenate(y)
    coefficients, *_ = np.linalg.lstsq(xs, ys, rcond=None)
    explained = 1 - np.sum((ys - xs @ coefficients) ** 2) / np.sum(ys**2)
    print(f"  {len(xs)} frames of {len(x)} clips: the scores explain {explained:.2f} of the motions' variance")
    learnt = {}
    for name, coefficient in zip(REGRESSORS, coefficients):
        largest = max(rises[name])
        region = DLIB68.regions[BY_NAME[name].region] + (DLIB68.jaw if BY_NAME[name].region == "mouth" else ())
        motion = np.zeros((DLIB68.n_points, 2))
        motion[list(region)] = (coefficient.reshape(-1, 2) * largest)[list(region)]
        learnt[name] = motion
        shown = sum(r >= SHOWN for r in rises[name])
        print(f"  {name}: 1 is a rise of {largest:.2f} (the largest of a clip; {shown} clips show it), motion {np.linalg.norm(motion):.3f}")
    return learnt, float(np.mean(openings))


@dataclasses.dataclass
class Calibration:
    """The calibration people's editors, their scores with every control at 0, and the blendshape judge."""

    editors: list[editing.Editor]
    still: list[np.ndarray]
    judge: Blendshapes

    def rise(self, name: str, motions: Motions) -> tuple[float, float]:
        """The mean rise of control ``name``'s named scores at 1 with ``motions``, and the largest mean move of another
        region's score (:func:`exprclone.evaluation.editor_judge.others`)."""
        changes = []
        for editor, still in zip(self.editors, self.still):
            editor.at_one[name] = motions.motion(name, editor.normalised, editor.cloner.faces.layout)
            changes.append(self.judge.scores(editor.render({name: 1.0}).image) - still)
        return float(np.mean(np.array(changes)[:, indices(BY_NAME[name].scores)])), others(np.array(changes), BY_NAME[name].region)[0]

    def calibrate(self, name: str, motions: Motions, candidates: dict[str, np.ndarray], amounts: tuple[float, ...]) -> np.ndarray:
        """Control ``name``'s motion at 1: each candidate (a motion of unit amount) tried at growing ``amounts`` until its
        rise reaches :data:`TARGET`; of the tries that reach it, the one whose other regions' scores move least for its
        rise (if none does, the largest rise). Every try is printed."""
        tried = []
        for label, direction in candidates.items():
            for amount in amounts:
                motion = amount * direction
                rise, moved = self.rise(name, dataclasses.replace(motions, stored={**motions.stored, name: motion}))
                print(f"  {name}, {label}, {amount:g}: rise {rise:.3f}, another region's score {moved:.3f}")
                tried.append((rise >= TARGET, float(np.linalg.norm(motion)), rise, moved, label, motion))
                if rise >= TARGET:
                    break
        reached = [t for t in tried if t[0]]
        chosen = min(reached, key=lambda t: t[3] / t[2]) if reached else max(tried, key=lambda t: t[2])
        print(f"  {name}: {chosen[4]}, motion {chosen[1]:.3f}, rise {chosen[2]:.3f}, another region's score {chosen[3]:.3f}")
        return chosen[5]


def one_eye(motion: np.ndarray, eye: tuple[int, ...]) -> np.ndarray:
    """``motion`` on one eye's landmarks alone."""
    out = np.zeros_like(motion)
    out[list(eye)] = motion[list(eye)]
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser, holds="the data sets (london/ and grid/)")
    parser.add_argument("-o", "--output", default=str(ROOT / "src/exprclone/data/expression_controls.npz"))
    args = parser.parse_args()
    judge, detect = Blendshapes(), shared("dlib").detect
    print("the GRID clips:")
    learnt, opening = learn_from_clips(Path(args.data) / "grid", judge)
    data = Dataset.open(Path(args.data) / "london")
    faces = {i: tuple(detect(load_image(p), p) for p in (data.path(i, False), data.path(i, True))) for i in data.ids}
    share = smile_share(default_model(), list(faces.values()), DLIB68)
    print(f"the smile: {share:.3f} times a face's predicted smile (the upper quartile of {len(faces)} people's shares)")
    judging = held_out(data.ids)
    people = [i for i in data.ids if i not in judging][:: (len(data.ids) - len(judging)) // CALIBRATION][:CALIBRATION]
    print(f"calibrated on {', '.join(people)} (not among the {len(judging)} who judge the editor)")
    zero = np.zeros((DLIB68.n_points, 2))
    motions = Motions({name: learnt.get(name, zero) for name in STORED}, share, opening)
    editors = [editing.Editor.of(editing.request(load_image(data.path(i, False)), faces[i][0]), motions) for i in people]
    calibration = Calibration(editors, [judge.scores(e.render({}).image) for e in editors], judge)
    built = {name: calibration.calibrate(name, motions, {k: mirrored(v, DLIB68.n_points) for k, v in sides.items()}, AMOUNTS[name])
             for name, sides in ANATOMY.items()}  # fmt: skip
    for name, eye in (("wink_left", DLIB68.eyes[1]), ("wink_right", DLIB68.eyes[0])):  # a wink closes its eye: the whole blink
        built[name] = one_eye(learnt["eyes_closed"], eye)
        rise, moved = calibration.rise(name, dataclasses.replace(motions, stored={**motions.stored, name: built[name]}))
        print(f"  {name}: the learnt blink on one eye: rise {rise:.3f}, another region's score {moved:.3f}")
    shipped = dataclasses.replace(motions, stored={**motions.stored, **built})
    shipped.save(args.output)
    print(f"{args.output}: {', '.join(STORED)} and the smile's breadth")


if __name__ == "__main__":
    main()
