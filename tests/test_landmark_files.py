import json

import numpy as np
import pytest

from exprclone import geometry
from exprclone.errors import ExprCloneError
from exprclone.frl_template import FRL189_TO_DLIB68, frl_to_68
from exprclone.landmark_files import read_landmarks, read_tem, write_landmarks
from exprclone.layout import DLIB68

SHAPE = (1350, 1350, 3)


def tem(london, face_id="005"):
    return london / "neutral_front" / f"{face_id}_03.tem"


def test_read_tem_gives_the_189_points_with_the_pupils_first(london):
    points = read_tem(tem(london))
    assert points.shape == (189, 2)
    assert (points >= 0).all() and (points < 1350).all()
    left, right = points[0], points[1]
    assert left[0] < right[0] and abs(left[1] - right[1]) < 0.1 * (right[0] - left[0])


def test_template_maps_onto_the_detected_landmarks(london, photo):
    # tools/derive_frl_map.py measured a median of 0.021 inter-pupil distances on the inner
    # face over all 72 photos; on any one photo the mean stays well under 0.06
    points = read_tem(tem(london))
    mapped = frl_to_68(points)
    _, detected = photo("005")
    ipd = np.linalg.norm(points[0] - points[1])
    inner = np.linalg.norm(mapped[17:] - detected[17:], axis=1) / ipd
    assert inner.mean() < 0.06
    assert mapped[48, 0] < mapped[30, 0] < mapped[54, 0] and mapped[48, 1] > mapped[30, 1]
    right_eye = mapped[list(DLIB68.eyes[0])].mean(0)
    assert np.linalg.norm(right_eye - points[0]) < 0.15 * ipd  # the image-left eye holds pupil 0


def test_the_table_is_made_of_convex_combinations():
    assert len(FRL189_TO_DLIB68) == 68
    for row in FRL189_TO_DLIB68:
        assert abs(sum(w for _, w in row) - 1) < 1e-9 and all(0 <= j < 189 and 0 < w <= 1 for j, w in row)


def test_read_landmarks_takes_a_tem_file(london):
    lm = read_landmarks(tem(london), SHAPE)
    assert lm.shape == (68, 2) and geometry.interocular(lm, DLIB68) > 100


def test_json_round_trip(tmp_path, photo):
    _, lm = photo("005")
    path = tmp_path / "lm.json"
    write_landmarks(path, lm)
    assert np.allclose(read_landmarks(path, SHAPE), lm, atol=1e-3)
    plain = tmp_path / "plain.json"
    plain.write_text(json.dumps(lm.tolist()))
    assert np.array_equal(read_landmarks(plain, SHAPE), lm)


@pytest.mark.parametrize(
    "content,needle",
    [
        ('{"landmarks": [[1, 2], [3, 4]]}', "2 landmarks, expected 68"),
        ("[[1, 2, 3]]", "list of [x, y] pairs"),
        ("{not json", "invalid JSON"),
        ('{"points": []}', "list of [x, y] pairs"),
        (json.dumps([[10, 10]] * 67 + [[float("nan"), 5]]).replace("NaN", "NaN"), "landmark 67"),
        (json.dumps([[10, 10]] * 67 + [[2000, 5]]), "landmark 67 at (2000, 5) is outside the 1350x1350 image"),
    ],
)
def test_bad_landmark_files_name_the_file_and_the_problem(tmp_path, content, needle):
    path = tmp_path / "bad.json"
    path.write_text(content)
    with pytest.raises(ExprCloneError, match=r"bad\.json") as e:
        read_landmarks(path, SHAPE)
    assert needle in str(e.value)


def test_missing_and_malformed_tem(tmp_path):
    with pytest.raises(ExprCloneError, match="no such file"):
        read_landmarks(tmp_path / "none.json", SHAPE)
    bad = tmp_path / "bad.tem"
    bad.write_text("3\n1 2\n3\n")
    with pytest.raises(ExprCloneError, match=r"bad\.tem: not a \.tem template"):
        read_tem(bad)
    short = tmp_path / "short.tem"
    short.write_text("2\n1 2\n3 4\n")
    with pytest.raises(ExprCloneError, match="2 template points, expected the 189-point"):
        read_landmarks(short, SHAPE)
