"""How far apart the thin-plate spline's grid nodes may be (``exprclone.imaging.tps.GRID_STEP``), and what the spline costs.

    python tools/tps_grid.py [--data ../shared/data] [--pairs 20] [--steps 8,8 8,4 8,2 4,4]

For London pairs (seed 0), the e+md geometry of the smile cloned onto the target at full
size (1350 pixels) gives the control points; for each pair of grid steps (the face's and the
mouth's; the whole image's is ``tps.GRID_STEP``), the map interpolated between the nodes
is compared with the spline evaluated at 20,000 random pixels of the face's box and
20,000 of the mouth's (largest and median error, pixels), and the TPS warp of the photo
is timed against the mesh warp (medians of 5 runs, interleaved).
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np
from scipy.interpolate import RBFInterpolator

from exprclone import clone
from exprclone.data import sets as datasets
from exprclone.evaluation.london import Dataset
from exprclone.imaging import piecewise, tps
from exprclone.imaging.warpers import tps_refine
from exprclone.io.images import load_image
from exprclone.landmarks.backends import default_detector
from exprclone.pipeline.clone import Cloner


def control_points(data: Dataset, a: str, b: str):
    """The target photo, its mesh and the control points of A's smile cloned onto it by e+md."""
    photos = [load_image(data.path(a, False)), load_image(data.path(a, True)), load_image(data.path(b, False))]
    points = [default_detector().detect(p) for p in photos]
    result = clone(*photos, method="e+md", landmarks=tuple(points))
    cloner = Cloner(photos[0], points[0], photos[2], points[2])
    return photos[2], cloner.faces.mesh, cloner.fi(result.landmarks["elastic"], cloner.transfer).control


def errors(mesh, control, shape, rng) -> np.ndarray:
    """Distances between the interpolated map and the spline at random pixels of the face's box and of the mouth's."""
    maps = tps.inverse_maps(mesh.points, control, shape, tps_refine(mesh))
    src, dst = tps.merged(mesh.points, control)
    spline = RBFInterpolator(dst, src, kernel="thin_plate_spline")
    samples = []
    for points in (control[: mesh.n_moving], control[mesh.mouth]):
        lo, hi = np.maximum(points.min(0).astype(int), 0), np.minimum(points.max(0).astype(int), (shape[1] - 1, shape[0] - 1))
        samples.append(np.stack([rng.integers(lo[0], hi[0] + 1, 20000), rng.integers(lo[1], hi[1] + 1, 20000)], 1))
    xy = np.concatenate(samples)
    return np.linalg.norm(maps[xy[:, 1], xy[:, 0]] - spline(xy.astype(float)), axis=1)


def timings(image, mesh, control, repeat: int = 5) -> tuple[float, float]:
    times = {"mesh": [], "tps": []}
    for _ in range(repeat + 1):
        for name, fn in (
            ("mesh", lambda: piecewise.warp(image, mesh.points, control, mesh.triangles)),
            ("tps", lambda: tps.warp(image, mesh.points, control, None, tps_refine(mesh))),
        ):
            t = time.perf_counter()
            fn()
            times[name].append(time.perf_counter() - t)
    return tuple(1000 * statistics.median(times[k][1:]) for k in ("mesh", "tps"))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser)
    parser.add_argument("--pairs", type=int, default=20)
    parser.add_argument("--steps", nargs="+", default=["8,8", "8,4", "8,2", "4,4"], help="grid steps: face, mouth")
    args = parser.parse_args()
    data = Dataset.open(Path(args.data) / "london")
    rng = np.random.default_rng(0)
    found = {step: [] for step in args.steps}
    ms = {step: [] for step in args.steps}
    for a, b in data.pairs(args.pairs, seed=0):
        image, mesh, control = control_points(data, a, b)
        for step in args.steps:
            tps.FACE_STEP, tps.MOUTH_STEP = (int(s) for s in step.split(","))
            found[step].append(errors(mesh, control, image.shape[:2], rng))
            ms[step].append(timings(image, mesh, control))
    for step in args.steps:
        e, (mesh_ms, tps_ms) = np.concatenate(found[step]), np.median(ms[step], axis=0)
        accuracy = f"error max {e.max():.3f} px, median {np.median(e):.4f} px"
        print(f"grid steps {step}: {accuracy}; mesh warp {mesh_ms:.1f} ms, TPS {tps_ms:.1f} ms ({tps_ms / mesh_ms:.2f}x)")


if __name__ == "__main__":
    main()
