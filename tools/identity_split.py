"""Where a clone stops looking like its target: the split of ``../shared/notes/identity.md`` measured on the London Set.

    python tools/identity_split.py [--data ../shared/data/london] [--pairs 80] [--jobs 2] [--seed 0] [--held-out 4]

Each result's identity distance (dlib's descriptors, against the target's neutral photo) is compared with a real smile
*as wide as itself*: a line fitted on the targets' own real smiles, identity against the mouth's widening
(:func:`exprclone.evaluation.runner.smile_strength`). The rows part what makes a stranger, as the notes do:

- ``e+md``: the source's motion and its shading (the clone as made);
- ``global``: the source's motion without shading;
- ``own shape, source shading``: the target's own real smile's landmarks given as GI (``global_landmarks``), the source's
  ERI and teeth (global+eri);
- ``own shape, source shading, no teeth``: the same without the pasted mouth interior;
- ``own shape, no shading``: the target's own real smile's landmarks given, no shading (global);
- ``self``: each target's own smile cloned onto its own photo (e+md).

Pairs are ordered pairs of different people (seeded) drawn within ``--held-out`` folds of the people, each fold's clones
made with the learnt shape of the expression (:mod:`exprclone.geometry.expression_shape`) learnt from the other folds'
people, never from the people cloned; the self-clones are the pairs' targets. With the code of another commit
importable (``PYTHONPATH=that/src``), the same command measures it (the same pairs; a code without the learnt shape
clones as it did): run it before and after a change. Prints the line and, per row, the mean widening, identity and
excess with a 95% bootstrap interval.
"""

from __future__ import annotations

import argparse
import sys
import warnings

import numpy as np

import exprclone
from exprclone.data import sets as datasets
from exprclone.evaluation.london import Dataset
from exprclone.evaluation.runner import in_parallel, photo, smile_strength
from exprclone.evaluation.statistics import mean_interval
from exprclone.geometry.global_warp import remove_head_motion
from exprclone.io.progress import Bar
from exprclone.landmarks.backends import shared
from exprclone.landmarks.layout import DLIB68
from exprclone.options import Options, names
from exprclone.pipeline.role_check import descriptor, identity_distance

#: the rows: (name, method, whose landmarks are GI (None: the method's own), the mouth interior pasted).
ROWS = (
    ("e+md", "e+md", None, True),
    ("global", "global", None, True),
    ("own shape, source shading", "global+eri", "own", True),
    ("own shape, source shading, no teeth", "global+eri", "own", False),
    ("own shape, no shading", "global", "own", True),
)


#: the landmarks found on each photo, by path (each photo is looked at once per process).
FOUND: dict[str, np.ndarray] = {}


def landmarks(data: Dataset, face: str, smiling: bool) -> np.ndarray:
    path = data.path(face, smiling)
    if path not in FOUND:
        FOUND[path] = shared("dlib").detect(photo(path), path)
    return FOUND[path]


def measured(image: np.ndarray, neutral: np.ndarray, target: np.ndarray) -> tuple[float, float]:
    """A result's widening (from the target's neutral landmarks ``neutral``) and identity distance to ``target``."""
    found = shared("dlib").detect(image, "result")
    return smile_strength(neutral, found), identity_distance(descriptor(image, found), target)


def pair_rows(task: tuple[Dataset, str, str, dict[str, object]]) -> list[tuple[str, float, float]]:
    """The rows of one ordered pair (and the real smile and the self-clone of its target), cloned with ``options``."""
    data, a, b, options = task
    warnings.simplefilter("ignore")
    sn, se, tn = (photo(data.path(f, s)) for f, s in ((a, False), (a, True), (b, False)))
    points = (landmarks(data, a, False), landmarks(data, a, True), landmarks(data, b, False))
    own_smile = landmarks(data, b, True)
    target = descriptor(tn, points[2])
    out = [("real", smile_strength(points[2], own_smile), identity_distance(descriptor(photo(data.path(b, True)), own_smile), target))]
    own = remove_head_motion(points[2], own_smile, DLIB68)  # the real smile's landmarks in the neutral photo's frame
    for name, method, gi, mouth in ROWS:
        given = {} if gi is None else {"global_landmarks": own}
        result = exprclone.clone(sn, se, tn, landmarks=points, method=method, mouth=mouth, **given, **options)
        out.append((name, *measured(result.image, points[2], target)))
    own_photos = (tn, photo(data.path(b, True)), tn)
    self_clone = exprclone.clone(*own_photos, landmarks=(points[2], own_smile, points[2]), method="e+md", **options)
    out.append(("self", *measured(self_clone.image, points[2], target)))
    return out


def learnt(data: Dataset, people: set[str]) -> object:
    """The shape of the expression learnt from ``people`` alone (the code that has it)."""
    from exprclone.geometry.expression_shape import ExpressionShape  # (not in the code before it)

    return ExpressionShape.learn([(landmarks(data, p, False), landmarks(data, p, True)) for p in sorted(people)], DLIB68)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser, "london", holds="the London Set")
    parser.add_argument("--pairs", type=int, default=80)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--held-out", type=int, default=4, help="folds of the people (default 4)")
    args = parser.parse_args()
    data = Dataset.open(args.data)
    rng = np.random.default_rng(args.seed)
    people = list(rng.permutation(data.ids))
    tasks = []
    for fold in (people[k :: args.held_out] for k in range(args.held_out)):
        within = [(a, b) for a in fold for b in fold if a != b]
        chosen = [within[k] for k in sorted(rng.choice(len(within), args.pairs // args.held_out, replace=False))]
        options = {} if "expression_shape" not in names(Options) else {"expression_shape": learnt(data, set(people) - set(fold))}
        tasks += [(data, a, b, options) for a, b in chosen]
    rows = [r for rs in in_parallel(pair_rows, tasks, args.jobs, Bar(sys.stderr, len(tasks), "pairs")) for r in rs]
    pairs = tasks
    real = np.array([(w, i) for name, w, i in rows if name == "real"])
    slope, intercept = np.polyfit(real[:, 0], real[:, 1], 1)
    print(
        f"exprclone {exprclone.__version__}, {len(pairs)} London pairs (seed {args.seed}): real smiles' identity = "
        f"{intercept:.3f} + {slope:.3f} x widening"
    )
    for name in ("real", *(r[0] for r in ROWS), "self"):
        mine = np.array([(w, i) for n, w, i in rows if n == name])
        excess = mine[:, 1] - (intercept + slope * mine[:, 0])
        _, low, high = mean_interval(excess)
        means = f"widening {mine[:, 0].mean():+.3f}  identity {mine[:, 1].mean():.3f}"
        print(f"{name:38s} {means}  excess {excess.mean():+.3f} [{low:+.3f}, {high:+.3f}]")


if __name__ == "__main__":
    main()
