"""The thin-plate-spline image warp: where the control points go, the identity, smoothness, coincident points."""

import numpy as np
from dots import assert_dots_land, dots, smooth_motion
from scipy.interpolate import RBFInterpolator

from exprclone.imaging import piecewise, tps
from exprclone.imaging.warpers import tps_refine
from exprclone.landmarks.layout import DLIB68


def smile_control(pair):
    """The target photo's mesh, and its control points moved by a smooth displacement (as a clone moves them)."""
    (_, _, target), (_, _, lm) = pair
    mesh = piecewise.build_mesh(lm, target.shape, DLIB68)
    moved = smooth_motion(lm)
    return target, lm, mesh, moved, mesh.control_points(moved)


def test_identity_when_nothing_moves(pair):
    (_, _, target), (_, _, lm) = pair
    mesh = piecewise.build_mesh(lm, target.shape, DLIB68)
    assert np.array_equal(tps.warp(target, mesh.points, mesh.points), target)


def test_landmarks_land_where_asked(pair):
    target, lm, mesh, moved, dst = smile_control(pair)
    out = tps.warp(dots(target.shape, lm), mesh.points, dst, None, tps_refine(mesh))
    assert_dots_land(out, lm, moved)


#: how far the interpolated map may be from the spline: the note of ``tps.FACE_STEP`` (at most 0.46 pixel on 20 London smiles).
DOCUMENTED_ERROR = 0.5


def test_the_map_is_the_spline_between_the_grid_nodes(pair):
    """Interpolating between grid nodes keeps the map as close to the spline as ``tps.FACE_STEP``'s note says."""
    target, lm, mesh, _, dst = smile_control(pair)
    maps = tps.inverse_maps(mesh.points, dst, target.shape[:2], tps_refine(mesh))
    src, dst = tps.merged(mesh.points, dst)
    spline = RBFInterpolator(dst, src, kernel="thin_plate_spline")
    rows, cols = np.random.default_rng(0).integers(0, target.shape[0], (2, 2000))
    exact = spline(np.stack([cols, rows], 1).astype(float))
    error = np.linalg.norm(maps[rows, cols] - exact, axis=1)
    assert error.max() < DOCUMENTED_ERROR and np.median(error) < 0.05


def test_the_spline_is_booksteins(pair):
    """Our thin-plate spline (float32 evaluation) against SciPy's, and through its control points."""
    target, lm, mesh, _, dst = smile_control(pair)
    src, dst = tps.merged(mesh.points, dst)
    ours, scipys = tps.Spline.fit(dst, src - dst), RBFInterpolator(dst, src - dst, kernel="thin_plate_spline")
    anywhere = np.random.default_rng(1).uniform(0, target.shape[0], (5000, 2))
    assert np.abs(ours(anywhere) - scipys(anywhere)).max() < 0.04  # Spline's note: float32 within 0.04 pixel
    assert np.abs(ours(dst) - (src - dst)).max() < 0.04


def test_no_kinks_at_triangle_edges(pair):
    """The mesh warp's map bends only where a row of pixels crosses a triangle edge; the spline's bends no more there
    than anywhere else."""
    target, _, mesh, _, dst = smile_control(pair)
    labels = piecewise.PiecewiseAffine.build(mesh.points, dst, mesh.triangles, target.shape[:2]).labels.astype(int)
    mesh_x, _ = piecewise.inverse_maps(mesh.points, dst, mesh.triangles, target.shape[:2])
    tps_x = tps.inverse_maps(mesh.points, dst, target.shape[:2], tps_refine(mesh))[..., 0]
    face = (slice(300, 1100), slice(300, 1050))
    crossing = (labels[:, :-2] != labels[:, 2:])[face[0], face[1]]  # x - 1 and x + 1 in different triangles
    bend = lambda m: np.abs(np.diff(m.astype(float), 2, axis=1))[face]  # noqa: E731
    mesh_bend, tps_bend = bend(mesh_x), bend(tps_x)
    assert crossing.mean() > 0.01
    assert mesh_bend[crossing].mean() > 100 * mesh_bend[~crossing].mean()
    assert tps_bend[crossing].mean() < 2 * tps_bend[~crossing].mean()


def test_coincident_control_points_are_merged():
    """The inner lips of a closed mouth and the point between them are one point in the output: no singular fit."""
    src = np.array([[0.0, 0], [100, 0], [0, 100], [100, 100], [50, 48], [50, 52], [50, 50]])
    dst = np.array([[0.0, 0], [100, 0], [0, 100], [100, 100], [50, 50], [50, 50], [50, 50]])
    image = np.random.default_rng(0).integers(0, 255, (101, 101), dtype=np.uint8)
    out = tps.warp(image, src, dst)
    assert out.shape == image.shape and np.array_equal(out, image)  # the merged point goes to (50, 50): no motion
