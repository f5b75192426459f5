"""The photos in the wrong boxes (:mod:`exprclone.pipeline.role_check`): two people, the smile given as the neutral face,
the target's photo in a source's box."""

import json
import subprocess
import sys

import pytest

from exprclone import data as samples
from exprclone.landmarks.layout import DLIB68
from exprclone.pipeline.role_check import (
    SAME_PERSON,
    SURELY_SAME,
    Face,
    appearance_distance,
    expressiveness,
    identity_distance,
    judge_roles,
    one_person,
    smile,
)

PEOPLE = samples.PEOPLE


@pytest.fixture(scope="module")
def photos(photo):
    return {(i, kind): Face.of(*photo(i, kind), DLIB68) for i in PEOPLE for kind in ("neutral", "smile")}


def test_one_persons_photos_in_the_right_order_raise_nothing(photos):
    for i in PEOPLE:
        for j in PEOPLE:  # the target anyone, the source's own person too
            assert judge_roles(photos[i, "neutral"], photos[i, "smile"], DLIB68, photos[j, "neutral"]) == [], (i, j)


def test_two_people_are_told_by_their_descriptors(photos):
    for i in PEOPLE:
        assert identity_distance(photos[i, "neutral"].descriptor, photos[i, "smile"].descriptor) < SAME_PERSON
        for j in PEOPLE:
            if j != i:
                assert identity_distance(photos[i, "neutral"].descriptor, photos[j, "smile"].descriptor) > SAME_PERSON
                assert appearance_distance(photos[i, "neutral"], photos[j, "smile"], DLIB68) > SURELY_SAME  # never taken unseen
                assert not one_person(photos[i, "neutral"], photos[j, "smile"], DLIB68)
                assert "another person" in judge_roles(photos[i, "neutral"], photos[j, "smile"], DLIB68)[0]


def test_a_smile_is_more_expressive_and_smiles_more_than_the_neutral_face(photos):
    for i in PEOPLE:
        neutral, smiling = photos[i, "neutral"].points, photos[i, "smile"].points
        assert expressiveness(smiling, DLIB68) > expressiveness(neutral, DLIB68), i
        assert smile(smiling, DLIB68) > smile(neutral, DLIB68), i
        said = judge_roles(photos[i, "smile"], photos[i, "neutral"], DLIB68)
        assert said == ["source_neutral: looks more expressive than source_expression; are the source's two photos swapped?"], i


def test_the_target_in_a_source_box_is_named(photos):
    """The target's photo given as a source's, and that source's photo as the target: the warning names the two boxes."""
    source, target = "126", "003"
    n, s, t = photos[source, "neutral"], photos[source, "smile"], photos[target, "neutral"]
    assert "are source_neutral and target_neutral swapped?" in judge_roles(t, s, DLIB68, n)[0]
    assert "are source_expression and target_neutral swapped?" in judge_roles(n, t, DLIB68, s)[0]


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
