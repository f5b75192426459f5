"""The editor's controls: their values checked, their motions in the face's own frame, the eyes never closed through."""

import dataclasses

import numpy as np
import pytest

from exprclone.errors import ExprCloneError
from exprclone.expressions import controls
from exprclone.expressions.controls import CLOSED, CONTROLS, STORED, Motions, default_motions, eye_opening, limit_lids, parse_values
from exprclone.geometry.expression_shape import default_model, in_pixels, normalised
from exprclone.landmarks.blendshapes import NAMES, REGIONS
from exprclone.landmarks.layout import DLIB68


@pytest.mark.parametrize(
    "text, subject",
    [("smiel=0.5", "smiel"), ("smile=1.5", "smile"), ("smile=-0.1", "smile"), ("smile", "smile"), ("smile=much", "smile")],
)
def test_a_bad_value_names_its_control(text, subject):
    with pytest.raises(ExprCloneError) as e:
        parse_values(text)
    assert e.value.subject == subject


def test_values_are_read_as_written():
    assert parse_values("") == {}
    assert parse_values("mouth_open=0.25,wink_left=1, smile = 0") == {"mouth_open": 0.25, "wink_left": 1.0, "smile": 0.0}


def test_every_control_names_scores_of_its_own_region_and_says_how_it_was_made():
    for control in CONTROLS:
        assert set(control.scores) <= set(REGIONS[control.region]) and set(control.scores) <= set(NAMES)
        assert control.made in ("learnt", "built") and control.sentence and control.source


def test_each_shipped_motion_moves_its_own_region_alone(points):
    """A mouth control moves the lips (and the jaw that carries them), an eye control the lids, a brow control the brows
    (and the eyes' upper lids and corners it may hold); none is still. (The smile moves the whole face as people's smiles do, its mouth
    most.)"""
    face = normalised(points("003"), points("003"), DLIB68)
    shipped = default_motions()
    smile = np.linalg.norm(shipped.motion("smile", face, DLIB68), axis=1)
    assert smile.argmax() in DLIB68.regions["mouth"]
    for control in (c for c in CONTROLS if c.name in STORED):
        moved = np.flatnonzero(np.linalg.norm(shipped.motion(control.name, face, DLIB68), axis=1) > 1e-9)
        upper_lids = tuple(upper for eye in controls.lid_pairs(DLIB68) for upper, _ in eye)
        held = {"mouth": DLIB68.jaw, "brows": upper_lids + tuple(eye[k] for eye in DLIB68.eyes for k in (0, 3))}
        own = DLIB68.regions[control.region] + held.get(control.region, ())
        assert len(moved) and set(moved) <= set(own), control.name


def test_the_smile_is_the_faces_own_predicted_smile_made_broader(points):
    face = normalised(points("001"), points("001"), DLIB68)
    shipped = default_motions()
    assert shipped.smile_share > 1  # the upper quartile of the people's own shares: broader than the mean smile
    assert np.allclose(shipped.motion("smile", face, DLIB68), shipped.smile_share * default_model().predicted(face))


def test_a_narrower_eye_closes_with_a_shorter_travel(points):
    """The eyes' motions scale with the face's own eye opening: an eye half as open travels half as far."""
    face = normalised(points("003"), points("003"), DLIB68)
    narrow = face.copy()
    for eye in DLIB68.eyes:  # the lids half as far from the eye's corners' line (y is down the face)
        middle = (face[eye[0], 1] + face[eye[3], 1]) / 2
        narrow[list(eye), 1] = middle + (face[list(eye), 1] - middle) / 2
    ratio = eye_opening(narrow, DLIB68) / eye_opening(face, DLIB68)
    shipped = default_motions()
    for name in ("eyes_closed", "wink_left", "wink_right"):
        for eye, r in zip(DLIB68.eyes, ratio):
            wide, thin = (np.abs(shipped.motion(name, f, DLIB68)[list(eye)]).sum() for f in (face, narrow))
            assert thin == pytest.approx(r * wide), name


def test_an_eye_closed_twice_keeps_its_lids_apart(points):
    """Both eyes closed and the left one winked (twice a closing): the left eye's lids stop CLOSED of its opening apart,
    along the lines that join them at rest, in their order (the upper lid above the lower); the right eye, closed once,
    no closer."""
    face = normalised(points("001"), points("001"), DLIB68)
    shipped = default_motions()
    total = shipped.motion("eyes_closed", face, DLIB68) + shipped.motion("wink_left", face, DLIB68)
    moved = face + limit_lids(face, total, DLIB68)
    (right, left), opening = controls.lid_pairs(DLIB68), eye_opening(face, DLIB68)
    gaps = [[(moved[b] - moved[a]) @ (face[b] - face[a]) / np.linalg.norm(face[b] - face[a]) for a, b in eye] for eye in (right, left)]
    assert np.mean(gaps[1]) == pytest.approx(CLOSED * opening[1]) and min(gaps[1]) > 0
    assert np.mean(gaps[0]) >= CLOSED * opening[0] - 1e-12


def test_a_control_is_the_same_motion_on_a_face_twice_as_large_and_turned(points):
    """In the face's own frame: scaled by 2 and turned by 20 degrees, the face moves twice as far, turned."""
    face = points("003")
    turn = np.deg2rad(20)
    rotation = 2 * np.array([[np.cos(turn), -np.sin(turn)], [np.sin(turn), np.cos(turn)]])
    other = face @ rotation.T + (300.0, -40.0)
    shipped = default_motions()
    for name in ("smile", "brows_down", "eyes_closed"):
        moved = [in_pixels(f, shipped.motion(name, normalised(f, f, DLIB68), DLIB68), DLIB68) for f in (face, other)]
        assert np.allclose(moved[0] @ rotation.T, moved[1], atol=1e-6), name


def test_the_motions_are_saved_and_read_back(tmp_path):
    shipped = default_motions()
    changed = dataclasses.replace(shipped, stored={**shipped.stored, "frown": shipped.stored["frown"] * 2}, smile_share=1.2)
    changed.save(tmp_path / "m.npz")
    back = Motions.load(tmp_path / "m.npz")
    assert back.smile_share == 1.2 and back.opening == shipped.opening
    assert all(np.array_equal(back.stored[n], changed.stored[n]) for n in STORED)


def test_the_smile_share_is_the_upper_quartile_of_the_peoples_own(points):
    """The sample people's smiles: the share is the quantile of each one's share of their own predicted smile."""
    model = default_model()
    faces = [(points(p), points(p, "smile")) for p in ("001", "003", "126")]
    shares = [controls.smile_share(model, [face], DLIB68) for face in faces]
    assert controls.smile_share(model, faces, DLIB68) == pytest.approx(np.quantile(shares, controls.SMILE_QUANTILE))
    assert min(shares) > 0
