"""Derive the table that gives dlib's 68 points from MediaPipe's 468-point mesh (``MESH_TO_68``).

The mesh landmarker (``exprclone.landmarks.facemesh``) fits the 468 mesh points on each neutral photo of
the London Set; the manual 189-point template of that photo, mapped to the 68 points
(``exprclone.io.frl_template``), is the truth. The fit uses only the training people of
``exprclone.evaluation.accuracy.split`` (two of every three by sorted id); the others are held
out, and their error is printed beside the training error.

For each of the 68 points the candidates are the mesh points of the same contour (jaw: the face
oval; each brow; each eyelid, upper points from the upper lid and lower from the lower; each lip
contour likewise, so that an opened mouth or eye keeps its two lids or lips apart), among the
``NEAREST`` of them nearest to the truth on average: one point, or the convex combination of two
or three consecutive ones along the contour (on the nose, which is no contour, any one to three)
whose weights (summing to 1) fit the training faces best by least squares. Consecutive points
keep a combination on its contour when the face moves: the templates show closed mouths, where
any two inner-lip points would fit. More points are kept only if they lower the mean training
error by ``GAIN`` outer-eye distances. The points of ``ANCHORS`` are pinned to the mesh point of
the same anatomical definition.

Run from the repository root, and paste the printed table into ``src/exprclone/mesh_layout.py``::

    PYTHONPATH=src python tools/derive_mesh_map.py [--data DIR]

DIR defaults to $EXPRCLONE_DATA, else ``../shared/data`` beside the checkout.
"""

from __future__ import annotations

import argparse
import itertools

import numpy as np

from exprclone.data import sets as datasets
from exprclone.evaluation.accuracy import point_errors, region_errors, split, templates
from exprclone.io.images import load_image
from exprclone.landmarks.facemesh import MeshDetector
from exprclone.landmarks.mesh_layout import BROWS, EYE_LIDS, FACE_OVAL, INNER_LIPS, NOSE, OUTER_LIPS

#: candidates kept per point, nearest first, before combinations are tried.
NEAREST = 8
#: the drop in mean training error (outer-eye distances) that justifies one more mesh point.
GAIN = 0.002


def _closed(contour: tuple[int, ...]) -> tuple[int, ...]:
    """A closed contour, its first two points repeated at its end so that windows wrap round."""
    return contour + contour[:2]


#: for each of the 68 points, the contours (ordered mesh points) it may be made of: one point, or
#: two or three consecutive ones. The nose is no contour: any one to three of its points.
CANDIDATES = (
    *[(_closed(FACE_OVAL),)] * 17,
    *[(BROWS[0],)] * 5,
    *[(BROWS[1],)] * 5,
    *[None] * 9,
    *(EYE_LIDS[0], EYE_LIDS[0][:1], EYE_LIDS[0][:1], EYE_LIDS[0], EYE_LIDS[0][1:], EYE_LIDS[0][1:]),
    *(EYE_LIDS[1], EYE_LIDS[1][:1], EYE_LIDS[1][:1], EYE_LIDS[1], EYE_LIDS[1][1:], EYE_LIDS[1][1:]),
    OUTER_LIPS,
    *[OUTER_LIPS[:1]] * 5,
    OUTER_LIPS,
    *[OUTER_LIPS[1:]] * 5,
    INNER_LIPS,
    *[INNER_LIPS[:1]] * 3,
    INNER_LIPS,
    *[INNER_LIPS[1:]] * 3,
)


#: points with the same anatomical definition in both layouts, pinned instead of fitted: the eye
#: corners (the face's axis and scale, :attr:`exprclone.landmarks.layout.Layout.eye_corners`), the outer and
#: inner mouth corners, the chin.
ANCHORS = {8: 152, 36: 33, 39: 133, 42: 362, 45: 263, 48: 61, 54: 291, 60: 78, 64: 308}


def combinations(i: int, nearest: set[int]) -> set[tuple[int, ...]]:
    """The one to three mesh points point ``i`` may be made of, among ``nearest`` (:data:`CANDIDATES`)."""
    if CANDIDATES[i] is None:
        return {c for size in (1, 2, 3) for c in itertools.combinations(sorted(nearest), size)}
    windows = set()
    for contour in CANDIDATES[i]:
        for size in (1, 2, 3):
            windows |= {contour[k : k + size] for k in range(len(contour) - size + 1)}
    return {w for w in windows if set(w) <= nearest}


def fit_weights(sources: np.ndarray, target: np.ndarray) -> np.ndarray | None:
    """Weights summing to 1 so that their combination of ``sources`` ``(F, k, 2)`` best fits ``target`` ``(F, 2)``; None if not convex."""
    k = sources.shape[1]
    if k == 1:
        return np.ones(1)
    # w_k = 1 - sum of the others: least squares in the k - 1 free weights
    a = (sources[:, :-1] - sources[:, -1:]).transpose(0, 2, 1).reshape(-1, k - 1)
    b = (target - sources[:, -1]).reshape(-1)
    free = np.linalg.lstsq(a, b, rcond=None)[0]
    weights = np.append(free, 1 - free.sum())
    return weights if (weights >= 0).all() else None


def choose(i: int, mesh: np.ndarray, truth: np.ndarray) -> tuple[tuple[int, float], ...]:
    """The table row of point ``i`` from the training faces' meshes ``(F, 468, 2)`` and truths ``(F, 68, 2)``."""
    if i in ANCHORS:
        return ((ANCHORS[i], 1.0),)
    scale = np.linalg.norm(truth[:, 36] - truth[:, 45], axis=1)[:, None, None]
    norm_mesh, target = mesh / scale, truth[:, i] / scale[:, 0]
    pool = NOSE if CANDIDATES[i] is None else {j for contour in CANDIDATES[i] for j in contour}
    nearest = set(sorted(pool, key=lambda j: np.linalg.norm(norm_mesh[:, j] - target, axis=1).mean())[:NEAREST])
    combos = combinations(i, nearest)
    best: tuple[float, tuple] | None = None
    for size in (1, 2, 3):
        found = []
        for combo in (c for c in combos if len(c) == size):
            weights = fit_weights(norm_mesh[:, list(combo)], target)
            if weights is not None:
                error = np.linalg.norm(np.einsum("k,fkd->fd", weights, norm_mesh[:, list(combo)]) - target, axis=1).mean()
                found.append((float(error), tuple(zip(combo, np.round(weights, 3).tolist()))))
        if found:
            candidate = min(found)
            if best is None or candidate[0] < best[0] - GAIN:
                best = candidate
    row = best[1]
    total = sum(w for _, w in row)
    return tuple((j, round(w / total, 3)) for j, w in row)


def apply(table: tuple, mesh: np.ndarray) -> np.ndarray:
    """The ``(F, 68, 2)`` points a table gives for meshes ``(F, 468, 2)``."""
    return np.stack([sum(w * mesh[:, j] for j, w in row) for row in table], axis=1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser, holds="the folder holding london/")
    args = parser.parse_args()

    people = templates(args.data / "london")
    train, held = split(list(people))
    detector = MeshDetector()
    mesh = {i: detector.detect_mesh(load_image(path), str(path)) for i, (path, _) in people.items()}
    truth = {i: points for i, (_, points) in people.items()}
    stack = lambda ids, d: np.array([d[i] for i in ids])  # noqa: E731
    table = tuple(choose(i, stack(train, mesh), stack(train, truth)) for i in range(68))
    print(f"# fitted on {len(train)} people, held out {len(held)}: {' '.join(held)}")
    for name, ids in (("training", train), ("held-out", held)):
        errors = region_errors(point_errors(apply(table, stack(ids, mesh)), stack(ids, truth)))
        print(f"# {name}: " + ", ".join(f"{k} {v:.4f}" for k, v in errors.items()))
    print("MESH_TO_68 = (")
    for i, row in enumerate(table):
        print(f"    {row!r},  # {i}")
    print(")")


if __name__ == "__main__":
    main()
