"""The front door (:mod:`exprclone.pipeline.request`): one request checked, its landmarks placed, its roles checked once
per photo unless vouched for, the Cloner made there, nothing given changed."""

import warnings

import numpy as np
import pytest

import exprclone
from exprclone.errors import ExprCloneWarning
from exprclone.pipeline import request as door
from exprclone.pipeline import role_check
from exprclone.pipeline.request import Request


def _warned(*photos, **keywords):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = exprclone.clone(*photos, method="global", **keywords)
    return [str(w.message) for w in caught if issubclass(w.category, ExprCloneWarning)], result


def test_the_roles_are_checked_unless_every_landmark_is_given(photo):
    """Swapped source photos are told when any landmark is placed by the door, or when asked; not when the caller gives
    every landmark (the caller vouches), and the image is the same either way."""
    (sn, sn_lm), (se, se_lm), (tn, tn_lm) = photo("126"), photo("126", "smile"), photo("003")
    placed, _ = _warned(se, sn, tn, landmarks=(se_lm, sn_lm, None))
    vouched, quiet = _warned(se, sn, tn, landmarks=(se_lm, sn_lm, tn_lm))
    asked, loud = _warned(se, sn, tn, landmarks=(se_lm, sn_lm, tn_lm), check_roles=True)
    assert any("swapped" in m for m in placed) and any("swapped" in m for m in asked)
    assert vouched == [] and quiet.warnings == () and loud.warnings
    assert np.array_equal(quiet.image, loud.image)


def test_the_role_check_looks_at_a_photo_once(photo, monkeypatch):
    """What the role check takes of a photo is kept with it: two requests of the same photos (a batch's rows, a
    server's repeated uploads) compute each photo's face descriptor once, whatever the requests."""
    (sn, sn_lm), (se, se_lm), (tn, tn_lm) = photo("001"), photo("003", "smile"), photo("126")  # two people: descriptors
    made = []
    real = role_check.descriptor
    monkeypatch.setattr(role_check, "descriptor", lambda image, points: made.append(1) or real(image, points))
    request = Request.of(sn, se, tn, landmarks=(sn_lm, se_lm, tn_lm), check_roles=True)
    first = door.judge_roles(request)
    second = door.judge_roles(Request(request.source_neutral, request.source_expression, request.target))
    assert first == second and "another person" in first[0]
    assert 0 < len(made) <= 3


def test_the_door_changes_nothing_it_is_given(pair):
    """The photos and landmarks given are left as they were, and a video's pooled mouth interior makes new faces."""
    images, landmarks = pair
    before = [im.copy() for im in images], [p.copy() for p in landmarks]
    results = exprclone.clone_methods(*images, ("global", "e+md"), landmarks=landmarks)
    assert all(np.array_equal(a, b) for a, b in zip(images, before[0]))
    assert all(np.array_equal(a, b) for a, b in zip(landmarks, before[1]))
    cloner = door.pair(Request.of(images[0], None, images[2], landmarks=(landmarks[0], None, landmarks[2])))
    reference = cloner.faces.mouth_reference
    pooled = cloner.faces.pooled([images[1]], [landmarks[1]])
    assert cloner.faces.mouth_reference is reference and pooled.mouth_reference is not reference
    assert results["e+md"].image.shape == images[2].shape


def test_a_request_of_a_performance_makes_the_faces_alone(pair):
    """A request without an expression gives the two neutral faces (the Cloner), its landmarks placed by the door, and
    no clone: preparing it says what is missing."""
    images, landmarks = pair
    request = Request.of(images[0], None, images[2])
    cloner = door.pair(request)
    assert np.allclose(cloner.faces.t_neu[:17], landmarks[2][:17])  # placed as the detector places them (jaw: untouched)
    with pytest.raises(exprclone.ExprCloneError, match="source_expression: missing"):
        door.prepare(request)


def test_a_clone_on_prepared_faces_is_the_clone_made_at_once(pair):
    """A batch's rows are cloned on faces prepared once (``cloner=``): the same image as a clone made from scratch."""
    images, landmarks = pair
    request = Request.of(*images, landmarks=landmarks)
    cloner = door.pair(request)
    on_faces = door.prepare(request, ("e+md",), cloner=cloner).render()["e+md"]
    whole = exprclone.clone(*images, landmarks=landmarks, method="e+md")
    assert np.array_equal(on_faces.image, whole.image) and on_faces.lambda_k == whole.lambda_k
