"""GRID's speakers as sources onto London faces: how much of the source's expression the clone makes (issue 57).

    PYTHONPATH=src python tools/grid_sources.py [--data ../shared/data] [--clips lbax4n ...] [--targets 001 003 ...]
                                                [--frames 4] [--method e+md] [--no-retarget]

Each GRID clip gives a source: its most closed frame is the neutral face
(:func:`exprclone.drive.driver.closed_mouth_frame`, as ``exprclone video`` takes it), and its ``--frames`` most open
frames (the widest mouth openings, at least 5 frames apart: :func:`exprclone.drive.driver.strongest_frames`) are its
expressions. Each expression is cloned onto each target's London neutral photo (by default the set's first four people
and its two palest and two darkest), and the blendshape judge (:mod:`exprclone.evaluation.blendshape_judge`) reads the
rise kept: of the :data:`~exprclone.evaluation.blendshape_judge.RISE_TOP` scores the source raises most from its closed
frame to the open one (``jawOpen`` and the like), how much the clone raises them from the target's neutral photo, as a
share of the source's rise. It prints a row per clip (the mean over its frames and targets, the worst target, the names
raised most), a row per target (the mean over every clip's frames, and its share of the judge's ceiling there) and the
mean over the clips; issue 57 asks for 0.7 on every speaker.

Beside each clip's figure, the judge's ceiling (:func:`laid`): the rise kept when the source's own motion, as the
judge's face mesh reads it on the source's two frames, is laid on the target's mesh (similarity-aligned) and scored with
no image at all: what a clone that moved the target's face exactly as the source's moved would be given. The judge
reads one motion with another gain on another face (the same jaw drop raises ``jawOpen`` half as much on some London
faces), so this, not 1, is what a faithful clone can reach.
"""

from __future__ import annotations

import argparse
import collections
from pathlib import Path
from typing import NamedTuple

import numpy as np

from exprclone import clone
from exprclone.data import sets as datasets
from exprclone.drive.driver import closed_mouth_frame, strongest_frames
from exprclone.errors import ExprCloneError
from exprclone.evaluation import blendshape_judge
from exprclone.io.images import load_image
from exprclone.io.video import read_frames
from exprclone.landmarks import align, blendshapes
from exprclone.landmarks.backends import default_detector
from exprclone.landmarks.layout import DLIB68
from exprclone.mouth import measure

#: the default targets: the London Set's first four people, its two palest and its two darkest (by their cheeks' L*,
#: ``tools/colour_check.py --lightness``).
TARGETS = ("001", "003", "005", "006", "083", "112", "137", "096")
#: frames between two expressions of one clip.
SPACING = 5


def source(clip: Path, frames: int) -> tuple[tuple[np.ndarray, np.ndarray], list[tuple[np.ndarray, np.ndarray]]]:
    """A clip's closed frame and its ``frames`` most open ones, each with its landmarks."""
    detect, seen = default_detector().detect, []
    for k, frame in enumerate(read_frames(clip)):
        try:
            seen.append((frame, detect(frame, f"{clip.name} frame {k}")))
        except ExprCloneError:  # no face in the frame
            seen.append((frame, None))
    usable = np.array([p is not None for _, p in seen])
    points = np.array([p if p is not None else np.zeros((68, 2)) for _, p in seen])
    opening = np.array([measure.opening(p, DLIB68) if ok else -np.inf for p, ok in zip(points, usable)])
    closed = closed_mouth_frame(points, usable, DLIB68)
    return (seen[closed][0], points[closed]), [(seen[k][0], points[k]) for k in strongest_frames(opening, usable, frames, SPACING)]


def meshed(image: np.ndarray, name: str) -> np.ndarray | None:
    """An image's face mesh (the blendshape judge's, ``(478, 2)``), None where no face is found."""
    try:
        return blendshapes.shared().mesh.detect_mesh(image, name)
    except ExprCloneError:
        return None


def scored(image: np.ndarray, name: str) -> np.ndarray | None:
    """An image's blendshape scores (as ``exprclone evaluate`` reads them), None where no face is found."""
    mesh = meshed(image, name)
    return None if mesh is None else blendshapes.shared().of_mesh(mesh)


class Target(NamedTuple):
    """A London face cloned onto: its neutral photo, its landmarks, and the judge's mesh and scores of it, read once for
    every clone."""

    image: np.ndarray
    points: np.ndarray
    mesh: np.ndarray
    scores: np.ndarray


def laid(rest: np.ndarray, moved: np.ndarray, target: np.ndarray) -> np.ndarray:
    """The source's mesh motion from ``rest`` to ``moved`` laid on the target's mesh ``target`` (each ``(478, 2)``),
    brought to the target's frame by the least-squares similarity between the two rest meshes: an exact transfer of the
    motion, whose rise kept is the judge's ceiling for a clone."""
    linear = align.fit_similarity(rest, target)[:, :2]
    return target + (moved - rest) @ linear.T


def kept(
    clip: Path, targets: dict[str, Target], frames: int, options: dict
) -> tuple[dict[str, list[float]], dict[str, list[float]], list[str]]:
    """The rise kept of each of a clip's expressions on each target, and the judge's ceiling of each (the rise kept of
    the source's motion :func:`laid` on the target's mesh), both by target; and the names the source raises most."""
    (neutral, neutral_points), expressions = source(clip, frames)
    by_target: dict[str, list[float]] = collections.defaultdict(list)
    ceilings: dict[str, list[float]] = collections.defaultdict(list)
    names: list[str] = []
    rest_mesh = meshed(neutral, f"{clip.name} closed frame")
    if rest_mesh is None:
        return by_target, ceilings, names
    of_mesh = blendshapes.shared().of_mesh
    rest = of_mesh(rest_mesh)
    for frame, points in expressions:
        moved_mesh = meshed(frame, f"{clip.name} open frame")
        if moved_mesh is None:
            continue
        moved = of_mesh(moved_mesh)
        top = np.argsort(-(moved - rest)[blendshape_judge.PLACES["total"]])[: blendshape_judge.RISE_TOP]
        names += [blendshapes.EXPRESSION[i] for i in top]
        for name, target in targets.items():
            made = clone(neutral, frame, target.image, landmarks=(neutral_points, points, target.points), **options)
            result = scored(made.image, f"{name} clone")
            if result is not None:
                by_target[name].append(blendshape_judge.rise_kept(rest, moved, target.scores, result))
                exact = of_mesh(laid(rest_mesh, moved_mesh, target.mesh))
                ceilings[name].append(blendshape_judge.rise_kept(rest, moved, target.scores, exact))
    return by_target, ceilings, names


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    datasets.add_argument(parser, holds="the data folder (grid/ and london/)")
    parser.add_argument("--clips", nargs="*", help="GRID clips by name (default: all)")
    parser.add_argument("--targets", nargs="*", default=list(TARGETS), help="London people cloned onto")
    parser.add_argument("--frames", type=int, default=4, help="open frames per clip (default: 4)")
    parser.add_argument("--method", default="e+md", help="the method (default: e+md)")
    parser.add_argument("--no-retarget", dest="retarget", action="store_false", help="the paper's stages (retarget=False)")
    args = parser.parse_args()
    clips = sorted((args.data / "grid").glob("*.mpg"))
    clips = [c for c in clips if not args.clips or c.stem in args.clips]
    if not clips:
        raise SystemExit(f"no GRID clips in {args.data}/grid (give --data)")
    detect, targets = default_detector().detect, {}
    for name in args.targets:
        image = load_image(args.data / "london" / "neutral_front" / f"{name}_03.jpg")
        mesh = meshed(image, name)
        if mesh is None:  # the judge sees no face on it: no clone of it could be judged
            print(f"{name}: the judge's face mesh finds no face; left out")
            continue
        targets[name] = Target(image, detect(image, name), mesh, blendshapes.shared().of_mesh(mesh))
    options = {"method": args.method, "retarget": args.retarget}
    shown = f"{args.method}{'' if args.retarget else ', --no-retarget'}"
    print(f"{shown}: the rise kept of {args.frames} open frames per clip onto {', '.join(targets)}")
    means, ceilings = [], []
    on_target: dict[str, list[float]] = collections.defaultdict(list)
    target_ceilings: dict[str, list[float]] = collections.defaultdict(list)
    for clip in clips:
        found, ceiling, raised_names = kept(clip, targets, args.frames, options)
        names = collections.Counter(raised_names).most_common(3)
        ceilings.append(float(np.mean([x for v in ceiling.values() for x in v])))
        for name in found:
            on_target[name] += found[name]
            target_ceilings[name] += ceiling[name]
        per_target = {name: float(np.mean(v)) for name, v in found.items() if v}
        mean = float(np.mean([x for v in found.values() for x in v]))
        means.append(mean)
        worst = min(per_target, key=per_target.__getitem__)
        raised = ", ".join(n for n, _ in names)
        print(
            f"{clip.stem:16s} rise kept {mean:5.2f} (worst target {worst} {per_target[worst]:5.2f}; judge's ceiling {ceilings[-1]:5.2f})"
            f"  raised most: {raised}",
            flush=True,
        )
    for name, values in on_target.items():
        rise, most = float(np.mean(values)), float(np.mean(target_ceilings[name]))
        print(f"onto {name:12s} rise kept {rise:5.2f}, judge's ceiling {most:5.2f}: {rise / most:4.2f} of it (over every clip's frames)")
    for name, values in (("rise kept", means), ("judge's ceiling", ceilings)):
        met = sum(m >= 0.7 for m in values)
        print(
            f"{name}: mean over {len(values)} clips {np.mean(values):.2f}; lowest {min(values):.2f}; at 0.7 or more: {met} of {len(values)}"
        )


if __name__ == "__main__":
    main()
