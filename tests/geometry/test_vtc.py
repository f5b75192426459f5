import pickle
import tracemalloc

import numpy as np
import pytest
import scipy.sparse
from scipy.spatial import Delaunay

from exprclone.geometry import global_warp, vtc
from exprclone.imaging import piecewise
from exprclone.landmarks import align, lips
from exprclone.landmarks.layout import DLIB68


def tents_of(points, shape):
    """The target's tents as the pipeline makes them: over its mesh's landmarks (:attr:`exprclone.pipeline.faces.Faces.tents`)."""
    return vtc.Tents.of(points, piecewise.build_mesh(points, shape, DLIB68).neighbours())


@pytest.fixture(scope="module")
def faces(pair_points):
    """Source 001 (neutral, smile) and target 003, inner lips made valid as the pipeline makes them, and the target's tents."""
    (sn, se, tn), shape = pair_points
    sn, se, tn = (lips.uncross(p, DLIB68) for p in (sn, se, tn))
    return sn, se, tn, tents_of(tn, shape)


def test_a_source_without_expression_leaves_the_target_as_it_is(faces):
    sn, _, tn, tents = faces
    assert np.allclose(vtc.vtc_landmarks(sn, sn, tn, DLIB68, tents), tn, atol=1e-6)


def test_head_motion_alone_is_not_an_expression(faces):
    sn, _, tn, tents = faces
    turned = align.apply(np.array([[0.98, -0.17, 30.0], [0.17, 0.98, -12.0]]), sn)
    assert np.allclose(vtc.vtc_landmarks(sn, turned, tn, DLIB68, tents), tn, atol=1e-6)


def test_one_affine_map_of_the_whole_face_is_the_targets_map(faces):
    """Every tent of the source changes by the one map A, so the target's do: the target is A of its neutral face,
    placed where the anchors are moved by the map too."""
    sn, _, tn, tents = faces
    a, shift = np.array([[1.08, 0.05], [-0.03, 0.93]]), np.array([4.0, -7.0])
    maps = tents.maps(sn, sn @ a.T + shift)
    assert np.allclose(maps, a, atol=1e-7)
    anchors = list(DLIB68.rigid)
    out = tents.solve(maps, anchors, tn[anchors] @ a.T + shift)
    assert np.allclose(out, tn @ a.T + shift, atol=1e-6)


def test_the_anchors_fix_the_translation_alone(faces):
    """Moving the anchors' targets by a shift moves the result by that shift; the shape does not change."""
    sn, se, tn, tents = faces
    maps, anchors = tents.maps(sn, se), list(DLIB68.rigid)
    here, there = (tents.solve(maps, anchors, tn[anchors] + d) for d in (0.0, np.array([10.0, -3.0])))
    assert np.allclose(there - here, [10.0, -3.0], atol=1e-8)
    assert np.allclose(here[anchors].mean(0), tn[anchors].mean(0))


def test_a_source_cloned_onto_itself_or_a_similar_face_is_the_similarity_transfer(faces, pair_points):
    """Where the target's tents are the source's, scaled and turned, each tent's change is exactly the source's: the
    paper's GI (matching the edges instead of the maps would lose part of the smile here)."""
    sn, se, _, _ = faces
    for t in (np.eye(2, 3), np.array([[0.0, -1.5, 900.0], [1.5, 0.0, 100.0]])):
        tn = align.apply(t, sn)
        tents = tents_of(tn, (2200, 2200))
        assert np.allclose(vtc.vtc_landmarks(sn, se, tn, DLIB68, tents), global_warp.global_landmarks(sn, se, tn, DLIB68), atol=1e-6)


def test_a_real_smile_widens_the_target_in_its_own_shape(faces):
    """001's smile on 003 (a real London pair): the mouth widens about as the similarity transfer widens it, and the
    motion follows the target's tents, so it is not the similarity transfer's."""
    sn, se, tn, tents = faces
    out = vtc.vtc_landmarks(sn, se, tn, DLIB68, tents)
    gi = global_warp.global_landmarks(sn, se, tn, DLIB68)
    width = lambda p: np.linalg.norm(p[54] - p[48])  # noqa: E731
    assert width(se) / width(sn) > 1.05  # the source really smiles
    assert width(out) / width(tn) > 1.05
    assert width(out) / width(tn) == pytest.approx(width(gi) / width(tn), abs=0.03)
    assert np.abs(out - gi).max() > 0.005 * align.interocular(tn, DLIB68)


def test_an_opening_mouth_opens_the_target(points, pair_points):
    """126 opens the mouth; the mouth is a hole in the mesh, so 001's closed lips open too."""
    _, shape = pair_points
    sn, se, tn = (lips.uncross(points(*k), DLIB68) for k in (("126",), ("126", "smile"), ("001",)))
    out = vtc.vtc_landmarks(sn, se, tn, DLIB68, tents_of(tn, shape))
    gap = lambda p: np.linalg.norm(p[66] - p[62])  # noqa: E731
    gi = global_warp.global_landmarks(sn, se, tn, DLIB68)
    assert gap(tn) < 0.1 * gap(gi)
    assert gap(out) > 0.5 * gap(gi)


def test_the_system_is_solved_sparsely():
    """A mesh of 10,000 vertices: a dense matrix of its size squared would take 800 MB; the tents and their solve take
    a small share of one."""
    side = 100
    grid = np.stack(np.meshgrid(np.arange(side), np.arange(side)), -1).reshape(-1, 2).astype(float)
    grid += np.random.default_rng(0).uniform(-0.2, 0.2, grid.shape)
    starts, rings = Delaunay(grid).vertex_neighbor_vertices
    n = len(grid)
    tracemalloc.start()
    try:
        tents = vtc.Tents.of(grid, np.split(rings, starts[1:-1]))
        bent = grid + 0.05 * np.sin(grid[:, ::-1] / 7.0)
        out = tents.solve(tents.maps(grid, bent), [0, 1, side], bent[[0, 1, side]])
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert scipy.sparse.issparse(tents.system) and tents.system.nnz < 40 * n
    assert peak < n * n * 8 / 20
    assert np.abs(out - bent).max() < 1e-3  # a smooth bend of the plane (0.05 deep) is carried: nearly affine in each tent


def test_a_mesh_in_parts_is_refused():
    points = np.array([[0.0, 0], [1, 0], [0, 1], [10, 10], [11, 10], [10, 11]])
    rings = [np.array([1, 2]), np.array([0, 2]), np.array([0, 1]), np.array([4, 5]), np.array([3, 5]), np.array([3, 4])]
    with pytest.raises(ValueError, match="2 parts"):
        vtc.Tents.of(points, rings)


def test_the_tents_travel_to_another_process(faces):
    """Pickled (a prepared clone sent to a worker), the tents are made again: the factor SciPy cannot pickle with them."""
    sn, se, tn, tents = faces
    again = pickle.loads(pickle.dumps(tents))
    assert np.array_equal(again.solve(again.maps(sn, se), [0], tn[:1]), tents.solve(tents.maps(sn, se), [0], tn[:1]))
