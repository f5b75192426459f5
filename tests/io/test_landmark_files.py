"""Landmark files on the real London Set: .tem templates, their 68-point mapping, JSON I/O and bad input."""

import json
from pathlib import Path

import numpy as np
import pytest

from exprclone import data as samples
from exprclone.errors import ExprCloneError
from exprclone.io.frl_template import FRL189_TO_DLIB68, frl_to_68
from exprclone.io.landmarks import read_landmarks, read_tem, write_landmarks
from exprclone.landmarks.dlib import Detector

SHAPE = (1350, 1350, 3)
FACE = "001"


@pytest.fixture(scope="module")
def tem_path() -> Path:
    return samples.template(FACE)


@pytest.fixture(scope="module")
def detected() -> np.ndarray:
    """dlib's 68 landmarks on the photo that the template belongs to."""
    return Detector().detect(samples.photo(FACE))


def test_read_tem_gives_189_points_inside_the_image_with_the_pupils_first(tem_path):
    points = read_tem(tem_path)
    assert points.shape == (189, 2) and points.dtype == np.float64
    assert (points >= 0).all() and (points < 1350).all()
    right_pupil, left_pupil = points[0], points[1]  # subject's right pupil is on the image's left
    dx = left_pupil[0] - right_pupil[0]
    assert dx > 100
    # over the 72 London templates the pupils' height difference is at most 0.09 of their distance
    assert abs(left_pupil[1] - right_pupil[1]) < 0.15 * dx


def test_the_mapped_template_lies_on_dlibs_landmarks(tem_path, detected):
    points = read_tem(tem_path)
    mapped = frl_to_68(points)
    assert mapped.shape == (68, 2)
    # tools/derive_frl_map.py measured the per-face mean error over the 72 neutral photos at
    # median 0.028, p90 0.033, max 0.055 outer eye-corner distances, so 0.06 holds on every
    # one of them; swapping the eyes (0.16) or reversing the jaw (0.28) fails it.
    eye_corners = np.linalg.norm(detected[36] - detected[45])
    assert np.linalg.norm(mapped - detected, axis=1).mean() / eye_corners < 0.06

    nose_tip, mouth_right, mouth_left = mapped[30], mapped[48], mapped[54]
    assert mouth_right[0] < nose_tip[0] < mouth_left[0]
    assert mouth_right[1] > nose_tip[1] and mouth_left[1] > nose_tip[1]

    # eye centroids lie within 0.05 inter-pupil distances of the pupils on all 72 templates
    ipd = np.linalg.norm(points[0] - points[1])
    for eye, pupil, other in ((slice(36, 42), points[0], points[1]), (slice(42, 48), points[1], points[0])):
        centre = mapped[eye].mean(axis=0)
        assert np.linalg.norm(centre - pupil) < 0.1 * ipd < np.linalg.norm(centre - other)


def test_the_table_is_made_of_convex_combinations():
    assert len(FRL189_TO_DLIB68) == 68
    for row in FRL189_TO_DLIB68:
        assert len(row) in (1, 2)
        assert abs(sum(w for _, w in row) - 1) < 1e-9 and all(0 <= j < 189 and 0 < w <= 1 for j, w in row)


def test_read_landmarks_maps_a_tem_file_to_the_68_points(tem_path):
    assert np.array_equal(read_landmarks(tem_path, SHAPE), frl_to_68(read_tem(tem_path)))


def test_json_round_trip_is_exact(tmp_path, tem_path):
    landmarks = frl_to_68(read_tem(tem_path)) + np.random.default_rng(0).uniform(-0.5, 0.5, (68, 2))
    path = tmp_path / "landmarks.json"
    write_landmarks(path, landmarks)
    assert json.loads(path.read_text()).keys() == {"landmarks"}
    assert np.array_equal(read_landmarks(path, SHAPE), landmarks)
    assert [p.name for p in tmp_path.iterdir()] == ["landmarks.json"]  # no temporary file left behind

    plain = tmp_path / "plain.json"
    plain.write_text(json.dumps(landmarks.tolist()))
    assert np.array_equal(read_landmarks(plain, SHAPE), landmarks)


GOOD = [[100.0 + i, 200.0] for i in range(68)]


@pytest.mark.parametrize(
    "name,content,needle",
    [
        ("few.json", json.dumps({"landmarks": GOOD[:2]}), "found 2 landmarks, expected 68"),
        ("nan.json", json.dumps(GOOD[:67] + [[float("nan"), 5.0]]), "point 67 has a non-finite coordinate"),
        ("inf.json", json.dumps(GOOD[:10] + [[5.0, float("inf")]] + GOOD[11:]), "point 10 has a non-finite coordinate"),
        ("out.json", json.dumps(GOOD[:67] + [[2000, 5]]), "landmark 67 at (2000, 5) is outside the 1350x1350 image"),
        ("broken.json", "{not json", "not JSON"),
        ("triples.json", "[[1, 2, 3]]", "list of [x, y] pairs"),
        ("keys.json", '{"points": []}', "list of [x, y] pairs"),
        ("text.json", '[["1", "2"]]', "list of [x, y] pairs"),
        ("points.txt", json.dumps(GOOD), "unknown landmark file type '.txt'"),
        ("count.tem", "179\n1 2\n", "179 template points, expected the 189-point"),
        ("short.tem", "189\n" + "1 2\n" * 100, "found 100 point lines, expected 189"),
        ("word.tem", "189\n" + "1 2\n" * 5 + "x y\n" + "1 2\n" * 183, "line 7 should be 'x y'"),
        ("nan.tem", "189\n" + "1\t2\n" * 188 + "nan 2\n", "point 188 has a non-finite coordinate"),
        ("empty.tem", "", "first line must be the point count"),
    ],
)
def test_bad_landmark_files_name_the_file_and_the_problem(tmp_path, name, content, needle):
    path = tmp_path / name
    path.write_text(content)
    with pytest.raises(ExprCloneError) as error:
        read_landmarks(path, SHAPE)
    message = str(error.value)
    assert str(path) in message and needle in message and "\n" not in message


def test_a_missing_file_is_named(tmp_path):
    for name in ("none.json", "none.tem"):
        with pytest.raises(ExprCloneError, match="no such file") as error:
            read_landmarks(tmp_path / name, SHAPE)
        assert str(tmp_path / name) in str(error.value)


def test_a_tem_with_tabs_and_trailing_blank_lines_reads(tmp_path, tem_path):
    points = read_tem(tem_path)
    path = tmp_path / "tabs.tem"
    path.write_text("189\n" + "".join(f"{x!r}\t {y!r}\n" for x, y in points.tolist()) + "0\n\n\n")
    assert np.array_equal(read_tem(path), points)
