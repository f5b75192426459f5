import numpy as np
import pytest

from exprclone.details import muscle
from exprclone.geometry import global_warp
from exprclone.landmarks.layout import DLIB68


def test_mask_follows_eq_10_and_11():
    centres, radii, h = np.array([[100.0, 80.0]]), np.array([20.0]), np.array([0.8])
    m = muscle.importance_mask((200, 300), centres, radii, h)
    assert m[80, 100] == pytest.approx(1.8)  # 1 + h at the centre
    assert m[80, 120] == pytest.approx(1 + 0.8 / np.sqrt(2), rel=1e-5)  # sigma = r / sqrt(ln 2)
    assert m[80, 100 + int(round(20 * np.sqrt(2)))] == pytest.approx(1.4, abs=0.02)
    assert m[0, 299] == 1.0 and m[199, 0] == 1.0  # 1 far from every area
    assert m.min() >= 1.0


def test_overlapping_areas_take_the_strongest():
    m = muscle.importance_mask((100, 100), np.array([[50.0, 50.0], [52.0, 50.0]]), np.array([10.0, 10.0]), np.array([0.5, 0.9]))
    assert m.max() == pytest.approx(1.9, abs=1e-3)


def test_areas_sit_on_the_face(pair):
    (_, _, target), (_, _, lm) = pair
    centres, radii = muscle.areas(lm, DLIB68)
    assert len(centres) == len(DLIB68.muscle_areas) == len(radii)
    lo, hi = lm.min(0), lm.max(0)
    names = [a.name for a in DLIB68.muscle_areas]
    for name, (x, y) in zip(names, centres):
        assert lo[0] < x < hi[0], name
        assert lo[1] - 0.5 * (hi[1] - lo[1]) < y < hi[1], name
    # right-side areas are on the image's left of the nose
    for name, (x, _) in zip(names, centres):
        if name.endswith("_right"):
            assert x < lm[30, 0], name
        if name.endswith("_left"):
            assert x > lm[30, 0], name


def test_strength_grows_with_muscle_motion(pair):
    _, (sn, se, _) = pair
    assert np.all(muscle.strengths(sn, sn, DLIB68) == 0)
    h = muscle.strengths(sn, global_warp.remove_head_motion(sn, se, DLIB68), DLIB68)
    assert np.all((h >= 0) & (h <= muscle.H_MAX))
    names = [a.name for a in DLIB68.muscle_areas]
    # a smile works the mouth corners more than the forehead
    assert h[names.index("mouth_corner_left")] > h[names.index("forehead_left")]


def test_mask_drawn_in_strips_is_the_maximum_of_whole_bumps():
    """Strip by strip, cut at 4 sigma: the same as Eq. (10) evaluated everywhere."""
    shape = (333, 250)  # not a whole number of strips
    centres = np.array([[60.0, 70.0], [180.0, 200.0], [120.0, 150.0], [240.0, 10.0]])
    radii = np.array([25.0, 40.0, 30.0, 15.0])
    h = np.array([0.5, 0.3, 0.0, 0.8])
    ys, xs = np.mgrid[: shape[0], : shape[1]]
    sigma = radii / np.sqrt(np.log(2.0))
    bumps = h[:, None, None] * np.exp(
        -((xs - centres[:, 0, None, None]) ** 2 + (ys - centres[:, 1, None, None]) ** 2) / (2 * sigma[:, None, None] ** 2)
    )
    m = muscle.importance_mask(shape, centres, radii, h)
    assert m.shape == shape and m.dtype == np.float32
    assert np.abs(m - (1 + bumps.max(axis=0))).max() < h.max() * np.exp(-8)  # what lies past 4 sigma


def test_mask_on_a_coarser_grid_stays_within_its_bound():
    """Drawn at the step a clone uses and enlarged, the mask is Eq. (10) to within h / 144 on one bump, h / 20 where two
    meet (muscle.SIGMA_PIXELS)."""
    shape = (333, 250)
    centres, radii, h = np.array([[60.0, 70.0], [120.0, 150.0]]), np.array([25.0, 30.0]), np.array([0.5, 0.5])
    step = muscle.mask_step(radii)
    assert step == 5  # the narrowest sigma, 25 / sqrt(ln 2) = 30 px, spans 6 blocks of 5
    # the first and the last partial block are extrapolated: the mask inside the ERI's box, well inside the photo, counts
    inner = (slice(step, shape[0] // step * step - step), slice(step, shape[1] // step * step - step))
    for areas, bound in ((slice(0, 1), h[0] / 144), (slice(0, 2), h.max() / 20)):
        exact = muscle.importance_mask(shape, centres[areas], radii[areas], h[areas])
        coarse = muscle.importance_mask(shape, centres[areas], radii[areas], h[areas], step)
        assert coarse.shape == shape and coarse.min() >= 1.0
        assert np.abs(coarse - exact)[inner].max() < bound
