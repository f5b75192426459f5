"""The source's photos in the wrong roles (:mod:`exprclone.pipeline.role_check`): two people, or the smile given as the neutral face."""

import json
import subprocess
import sys

import pytest

from exprclone import data as samples
from exprclone.landmarks.layout import DLIB68
from exprclone.pipeline.role_check import Photo, expressiveness, identity_distance, judge_roles

PEOPLE = samples.PEOPLE


@pytest.fixture(scope="module")
def photos(photo):
    return {(i, kind): Photo.of(*photo(i, kind), DLIB68) for i in PEOPLE for kind in ("neutral", "smile")}


def test_one_persons_photos_in_the_right_order_raise_nothing(photos):
    for i in PEOPLE:
        assert judge_roles(photos[i, "neutral"], photos[i, "smile"], DLIB68) == [], i


def test_two_people_are_told(photos):
    for i in PEOPLE:
        own = identity_distance(photos[i, "neutral"], photos[i, "smile"], DLIB68)
        for j in PEOPLE:
            if j != i:
                assert identity_distance(photos[i, "neutral"], photos[j, "smile"], DLIB68) > own
                assert "another person" in judge_roles(photos[i, "neutral"], photos[j, "smile"], DLIB68)[0]


def test_a_smile_is_more_expressive_than_the_neutral_face(photos):
    for i in PEOPLE:
        assert expressiveness(photos[i, "smile"].points, DLIB68) > expressiveness(photos[i, "neutral"].points, DLIB68), i
    said = judge_roles(photos["126", "smile"], photos["126", "neutral"], DLIB68)
    assert said == ["source_neutral: looks more expressive than source_expression; are the source's two photos swapped?"]


def test_the_cli_warns_on_one_line_and_the_record_keeps_it(tmp_path):
    neutral, smile, target = samples.path("126"), samples.path("126", "smile"), samples.path("003")
    command = [sys.executable, "-m", "exprclone", "clone", str(smile), str(neutral), str(target), "-o", str(tmp_path / "out.png")]
    done = subprocess.run([*command, "--save-json", str(tmp_path / "out.json"), "--method", "elastic"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    lines = [line for line in done.stderr.splitlines() if "swapped" in line]
    assert lines == [
        "exprclone: warning: source_neutral: looks more expressive than source_expression; are the source's two photos swapped?"
    ]
    assert json.loads((tmp_path / "out.json").read_text())["warnings"] == [lines[0].removeprefix("exprclone: warning: ")]
