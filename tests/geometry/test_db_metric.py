import numpy as np
import pytest

from exprclone.geometry import db_metric, eigenface, elastic, global_warp, local_warp
from exprclone.geometry.eigenface import default_eigenfaces
from exprclone.imaging import piecewise
from exprclone.landmarks.layout import DLIB68


def test_db_on_the_straight_line_is_smallest_half_way():
    # candidates on the segment from the global result to the source: DB = e^(D-t) + e^t
    src, gl = np.zeros(8), np.full(8, 1.0)
    t = np.linspace(0, 1, 11)[:, None]
    db, to_source, to_global = db_metric.db_metric(gl + t * (src - gl), src, gl)
    assert np.allclose(to_source + to_global, to_source[0])
    assert db.argmin() == 5
    assert db[0] == pytest.approx(np.exp(to_source[0]) + 1)


def test_omega_zero_picks_the_candidate_nearest_the_source():
    rng = np.random.default_rng(0)
    e = rng.normal(size=(6, 16))
    src = e[4] + 0.01
    db, _, _ = db_metric.db_metric(e, src, e[0], omega_db=0.0)
    assert db.argmin() == 4


def test_distances_are_in_units_of_two_training_faces():
    rng = np.random.default_rng(0)
    k = 16
    a, b = rng.normal(size=(2000, k)), rng.normal(size=(2000, k))  # whitened features
    _, d, _ = db_metric.db_metric(a - b, np.zeros(k), np.zeros(k))  # |a_i - b_i| for each pair
    assert np.mean(d**2) == pytest.approx(1.0, rel=0.1)


def test_choose_lambda_on_real_photos(pair):
    (_, se_img, target), (sn, se, tn) = pair
    mesh = piecewise.build_mesh(tn, target.shape, DLIB68)
    gl = global_warp.global_landmarks(sn, se, tn, DLIB68)
    lo = local_warp.local_landmarks(gl, se, DLIB68)
    lambdas = np.array(db_metric.LAMBDAS)
    cands = [elastic.elastic_landmarks(gl, lo, mesh.neighbours(), lam) for lam in lambdas]
    grey = db_metric.target_grey(target, mesh, DLIB68)
    crop = eigenface.crop(se_img, se, DLIB68)
    curve = db_metric.choose_lambda(grey, mesh, cands, lambdas, crop, default_eigenfaces(), DLIB68)
    assert np.isfinite(curve.db).all() and curve.to_global[0] == 0
    assert curve.best == lambdas[curve.db.argmin()]
    assert 0.2 < curve.to_source[0] < 3  # neither flattened nor overflowing
    assert np.all(np.diff(curve.to_global) >= -1e-3)  # candidates move away from GI as lambda grows
    with pytest.raises(ValueError):
        db_metric.choose_lambda(grey, mesh, cands[1:], lambdas[1:], crop, default_eigenfaces(), DLIB68)
