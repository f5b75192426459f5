import numpy as np
import pytest

from exprclone.geometry import elastic, global_warp, local_warp
from exprclone.imaging import piecewise
from exprclone.landmarks.layout import DLIB68


@pytest.fixture(scope="module")
def springs(pair_points):
    (sn, se, tn), shape = pair_points
    mesh = piecewise.build_mesh(tn, shape, DLIB68)
    gl = global_warp.global_landmarks(sn, se, tn, DLIB68)
    return gl, local_warp.local_landmarks(gl, se, DLIB68), mesh.neighbours()


def force_norm(points, gl, lo, neighbours, lambda_k):
    index, count = elastic.pad_neighbours(neighbours)
    springs = elastic.spring_force(points[:, None], gl, gl[index], count)
    return np.linalg.norm(elastic.net_force(points[:, None], lo, springs, lambda_k)[:, 0], axis=-1)


def test_lambda_zero_gives_global_and_k_n_zero_gives_local(springs):
    gl, lo, nb = springs
    assert np.allclose(elastic.elastic_landmarks(gl, lo, nb, 0.0), gl)
    assert np.array_equal(elastic.elastic_landmarks(gl, lo, nb, np.inf), lo)


def test_no_force_from_neighbours_at_the_global_position(springs):
    gl, lo, nb = springs
    assert force_norm(gl, gl, lo, nb, 0.0).max() < 1e-9
    assert force_norm(lo, gl, lo, nb, 1e9).max() < 1e-3 * 1e9  # only A' pulls at A'


@pytest.mark.parametrize("lambda_k", [0.2, 1.0, 5.0])
def test_p_opt_balances_best_inside_the_window(springs, lambda_k):
    gl, lo, nb = springs
    p = elastic.elastic_landmarks(gl, lo, nb, lambda_k)
    lo_box, hi_box = np.minimum(gl, lo), np.maximum(gl, lo)
    assert ((p >= lo_box - 1e-9) & (p <= hi_box + 1e-9)).all()  # Eq. (5): P in Win
    f = force_norm(p, gl, lo, nb, lambda_k)
    assert (f <= force_norm(gl, gl, lo, nb, lambda_k) + 1e-9).all()
    assert (f <= force_norm(lo, gl, lo, nb, lambda_k) + 1e-9).all()
    # the grid search finds the window's minimum: no random point in it does better
    rng = np.random.default_rng(1)
    for _ in range(50):
        q = lo_box + rng.uniform(size=gl.shape) * (hi_box - lo_box)
        assert (f <= force_norm(q, gl, lo, nb, lambda_k) + 0.05 * (1 + lambda_k)).all()


def test_points_that_local_warping_leaves_stay(springs):
    gl, lo, nb = springs
    p = elastic.elastic_landmarks(gl, lo, nb, 1.0)
    same = np.all(gl == lo, axis=1)
    assert same.sum() >= 17 and np.array_equal(p[same], gl[same])


def test_larger_lambda_moves_closer_to_local(springs):
    gl, lo, nb = springs
    dist = [np.linalg.norm(elastic.elastic_landmarks(gl, lo, nb, lam) - lo) for lam in (0.0, 0.5, 2.0, 10.0)]
    assert all(a > b for a, b in zip(dist, dist[1:]))


def test_many_lambdas_at_once_equal_one_at_a_time(springs):
    gl, lo, nb = springs
    lambdas = np.array([0.0, 0.3, 2.0, np.inf])
    together = elastic.elastic_landmarks(gl, lo, nb, lambdas)
    assert together.shape == (4, 68, 2)
    for lam, p in zip(lambdas, together):
        assert np.allclose(p, elastic.elastic_landmarks(gl, lo, nb, lam))


def test_spring_force_sums_each_points_own_neighbours(springs):
    """Points are visited in order of neighbour count inside; the result keeps the caller's order."""
    gl, _, nb = springs
    index, count = elastic.pad_neighbours(nb)
    p = gl[:, None] + np.array([[[3.0, -2.0]]])
    force = elastic.spring_force(p, gl, gl[index], count)[:, 0]
    for i in (0, 30, 48, 67):
        d = gl[nb[i]] - p[i, 0]
        rest = np.linalg.norm(gl[nb[i]] - gl[i], axis=1)
        length = np.linalg.norm(d, axis=1)
        assert np.allclose(force[i], ((length - rest) / length) @ d)
