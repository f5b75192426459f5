"""A clone's inputs gathered from files or bytes sent (:mod:`exprclone.io.inputs`): the door's request, the same whatever
the surface."""

import numpy as np
import pytest

import exprclone
from exprclone import data as samples
from exprclone.io.inputs import Seen, Source, gather, placed
from exprclone.io.landmarks import write_landmarks
from exprclone.landmarks import backends
from exprclone.options import Options
from exprclone.pipeline import request as door

ROLES_OF_SAMPLES = (samples.path("126"), samples.path("126", "smile"), samples.path("003"))


def test_files_and_bytes_give_the_clone_of_the_arrays(photo, tmp_path):
    """Photos named as files or sent as bytes, a landmark file read for its photo: the same clone as the arrays give."""
    (sn, sn_lm), (se, _), (tn, _) = photo("126"), photo("126", "smile"), photo("003")
    write_landmarks(tmp_path / "sn.json", sn_lm)
    files = gather([Source(str(p)) for p in ROLES_OF_SAMPLES], [Source(str(tmp_path / "sn.json")), None, None], Options(method="global"))
    sent = gather([Source(p.stem, p.read_bytes()) for p in ROLES_OF_SAMPLES], options=Options(method="global"))
    assert np.array_equal(files.source_neutral.points, sn_lm) and files.source_expression.points is None and files.check_roles
    expected = exprclone.clone(sn, se, tn, method="global").image
    for request in (files, sent):
        assert np.array_equal(door.prepare(request).render()["global"].image, expected)


def test_a_photo_sent_again_is_not_looked_at_again(monkeypatch):
    """A process that has seen a photo's bytes keeps its landmarks (and its faces, for a target), whatever role it
    comes in next; a file is read each time."""
    calls = []
    detector = backends.shared("dlib")
    real = type(detector).detect
    monkeypatch.setattr(type(detector), "detect", lambda self, image, subject="image": calls.append(subject) or real(self, image, subject))
    seen, portrait = Seen(), Source("portrait", samples.path("003").read_bytes())
    first = placed(portrait, Options(), seen)
    again = placed(Source("source_neutral", portrait.content), Options(), seen)
    assert calls == ["portrait"] and again.name == "source_neutral" and np.array_equal(first.points, again.points)
    assert placed(portrait, Options(), seen, every=True).found is not None  # every face looked for: another look
    assert Seen.key(Source(str(samples.path("003"))), False, "dlib") is None


def test_a_built_in_expression_needs_the_targets_photo_alone():
    request = gather([None, None, Source(str(samples.path("003")))], expression="smile")
    assert request.source_expression.points is not None and request.target.points is None
    assert not request.check_roles  # the role check judges the source's pair, and a built-in one is shipped as made
    with pytest.raises(exprclone.ExprCloneError, match="source_expression: missing"):
        gather([Source(str(samples.path("126"))), None, Source(str(samples.path("003")))])


def test_an_input_that_cannot_be_read_is_named(tmp_path):
    bad = tmp_path / "marks.json"
    bad.write_text("[[1, 2]]")
    with pytest.raises(exprclone.ExprCloneError, match=str(tmp_path / "missing.jpg")):
        gather([Source(str(tmp_path / "missing.jpg")), Source(str(ROLES_OF_SAMPLES[1])), Source(str(ROLES_OF_SAMPLES[2]))])
    with pytest.raises(exprclone.ExprCloneError, match="marks.json"):
        gather([Source(str(p)) for p in ROLES_OF_SAMPLES], [Source("marks.json", bad.read_bytes(), ".json"), None, None])
