"""Only the expression is cloned: what changed between the source's photos for another reason is not."""

import numpy as np
import pytest
from changes import lock_of_hair

import exprclone
from exprclone.details import eri, gate
from exprclone.evaluation.scores import material_swaps
from exprclone.landmarks import align
from exprclone.landmarks.layout import DLIB68
from exprclone.pipeline.cloner import Cloner
from exprclone.testing.lighting import relit


def forehead_spots(landmarks):
    """Two places on the forehead (above each brow), and the radius of a lock of hair there."""
    iod = align.interocular(landmarks, DLIB68)
    return landmarks[19] - (0, 0.25 * iod), landmarks[24] - (0, 0.25 * iod), 0.1 * iod


@pytest.fixture(scope="module")
def changes(photo):
    """Source 001 (no fringe) and target 003: the source's neutral photo changed for no expression's sake."""
    (sn, sn_lm), (se, se_lm), (tn, tn_lm) = photo("001"), photo("001", "smile"), photo("003")
    a, b, radius = forehead_spots(sn_lm)
    return {
        "light": (sn, relit(sn, sn_lm)),
        "hair": (lock_of_hair(sn, a, radius), lock_of_hair(sn, b, radius)),  # a lock that moved
    }, (sn, sn_lm, se, se_lm, tn, tn_lm)


@pytest.mark.parametrize("change", ["light", "hair"])
def test_a_change_that_is_no_expression_leaves_the_geometry_alone(changes, change):
    """The expression photo is the neutral one changed: the clone is the geometry-only result."""
    photos, (_, sn_lm, _, _, tn, tn_lm) = changes
    neutral, changed = photos[change]
    results = exprclone.clone_methods(neutral, changed, tn, ("global", "elastic+eri", "e+md"), landmarks=(sn_lm, sn_lm, tn_lm))
    for method in ("elastic+eri", "e+md"):
        assert np.abs(results[method].image.astype(int) - results["global"].image).max() <= 1, method


@pytest.mark.parametrize("change", ["light", "hair"])
def test_a_change_that_is_no_expression_leaves_a_real_smile_alone(changes, change):
    """With a real smile, the same change to both of the source's photos changes nothing of the clone's shading."""
    photos, (sn, sn_lm, se, se_lm, tn, tn_lm) = changes
    if change == "light":  # the smile photo lit from the side
        neutral, smile = sn, relit(se, se_lm)
    else:  # a lock of hair on the neutral photo's forehead, moved on the smile photo's
        a, _, radius = forehead_spots(sn_lm)
        _, b, _ = forehead_spots(se_lm)
        neutral, smile = lock_of_hair(sn, a, radius), lock_of_hair(se, b, radius)
    plain = exprclone.clone(sn, se, tn, method="e+md", landmarks=(sn_lm, se_lm, tn_lm), mouth=False)
    changed = exprclone.clone(neutral, smile, tn, method="e+md", landmarks=(sn_lm, se_lm, tn_lm), mouth=False)
    assert np.abs(plain.eri - 1).max() > 0.1  # the smile has shading to transfer
    assert np.abs(changed.eri - plain.eri).max() < 0.02
    assert np.abs(changed.image.astype(int) - plain.image).max() <= 5


def test_a_fringe_that_moved_prints_nothing(photo, monkeypatch):
    """Source 143's fringe sits higher in his smile: where hair and skin swapped, the target takes no ratio."""
    (sn, sn_lm), (se, se_lm), (tn, tn_lm) = photo("143"), photo("143", "smile"), photo("063")
    result = exprclone.clone(sn, se, tn, method="e+md", landmarks=(sn_lm, se_lm, tn_lm))
    # hair against skin: one photo at least twice as bright as the other there (no shading is: the ERI
    # is clamped to [0.7, 1.4]), on the face
    swapped = material_swaps(result, sn, se, DLIB68)
    assert swapped.sum() > 0.05 * align.interocular(result.landmarks["final"], DLIB68) ** 2  # the fringe moved
    assert np.abs(result.eri[swapped] - 1).max() < 0.01
    # without the tests of what is there, the fringe would print
    monkeypatch.setattr(gate, "moved", lambda labelling, *a: np.ones(labelling.labels.shape, np.float32))
    monkeypatch.setattr(gate, "skin", lambda colour, chroma, trust, weight, *a, **k: np.ones(weight.shape, np.float32))
    monkeypatch.setattr(eri, "texture", lambda energy, mean, window: np.ones_like(mean))
    ungated = exprclone.clone(sn, se, tn, method="e+md", landmarks=(sn_lm, se_lm, tn_lm))
    assert np.abs(ungated.eri[swapped] - 1).max() > 0.1


def test_the_neutral_faces_are_measured_once_for_every_expression(photo, monkeypatch):
    """The colours of the two neutral photos are measured when a Cloner first needs them, not again for each
    expression (each frame of a video): only the expression's is measured per clone."""
    (sn, sn_lm), (se, se_lm), (tn, tn_lm) = photo("126"), photo("126", "smile"), photo("003")
    measured = []
    colour = gate.colour
    monkeypatch.setattr(gate, "colour", lambda rgb, sigma: measured.append(rgb.shape) or colour(rgb, sigma))
    cloner = Cloner(sn, sn_lm, tn, tn_lm)
    results = [cloner.changed(lambda_k=0.0).clone_methods(se, se_lm, ("e+md",))["e+md"] for _ in range(3)]
    assert len(measured) == 2 + 3
    assert np.abs(results[0].eri - 1).max() > 0.1  # the ratio was made
    assert all(np.array_equal(r.image, results[0].image) for r in results[1:])
