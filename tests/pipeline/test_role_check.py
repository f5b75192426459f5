"""The photos in the wrong boxes (:mod:`exprclone.pipeline.role_check`): two people, the smile given as the neutral face,
the target's photo in a source's box; and photos in the right boxes that are no smile, or in another light."""

import json
import subprocess
import sys

import numpy as np
import pytest
from conftest import GRID, need_full_data

from exprclone import data as samples
from exprclone.drive.driver import closed_mouth_frame
from exprclone.io.video import read_frames
from exprclone.landmarks.backends import default_detector
from exprclone.landmarks.layout import DLIB68
from exprclone.mouth import measure
from exprclone.pipeline.role_check import (
    CAP,
    MARGINS,
    SAME_PERSON,
    SURELY_SAME,
    Face,
    appearance_distance,
    expressiveness,
    from_rest,
    identity_distance,
    judge_roles,
    one_person,
    rise,
    says,
    smiling,
    swapped,
    width,
)
from exprclone.testing.lighting import changes

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


def test_a_smile_departs_from_rest_in_every_view_and_swapped_is_told(photos):
    """A smile raises its scores from its neutral face's, lies farther from people's faces at rest, moves its
    landmarks farther from the mean neutral face and widens the mouth; swapped, two views at least say so beyond their
    margins (003's weak smile hardly raises the scores), in the right order none."""
    for i in PEOPLE:
        neutral, smile = photos[i, "neutral"], photos[i, "smile"]
        assert rise(neutral.scores, smile.scores) > 0 and from_rest(smile.scores) > from_rest(neutral.scores), i
        assert expressiveness(smile.points, DLIB68) > expressiveness(neutral.points, DLIB68), i
        assert smiling(smile.scores) > smiling(neutral.scores), i
        assert width(smile.points, DLIB68) > width(neutral.points, DLIB68), i
        assert (says(neutral, smile, DLIB68) < 1).all() and (says(smile, neutral, DLIB68) > 1).sum() >= 2, i
        said = judge_roles(smile, neutral, DLIB68)
        assert said == ["source_neutral: looks more expressive than source_expression; are the source's two photos swapped?"], i


@pytest.mark.parametrize("person", ["039", "082"])
def test_a_weak_smile_swapped_is_told_by_how_much_more_the_neutral_face_smiles(photo, person):
    """Two London smiles that the views of any expression hardly see (one of the three votes, swapped): their
    neutral face given as the expression smiles less by far more than the light alone moves the smile scores, a second
    vote; in the right order the smile votes for nothing."""
    neutral, smile = (Face.of(*photo(person, kind), DLIB68) for kind in ("neutral", "smile"))
    told = says(smile, neutral, DLIB68) > 1
    assert told[:3].sum() == 1 and told[3] and swapped(smile, neutral, DLIB68)
    assert smiling(smile.scores) - smiling(neutral.scores) > 5 * MARGINS[3] and says(neutral, smile, DLIB68)[3] < 1


@pytest.mark.parametrize("person", ["005", "173"])
def test_a_smile_the_scores_hardly_see_swapped_is_told_by_the_mouths_width(photo, person):
    """Two London smiles that the scores and the landmarks' spread hardly see (swapped, at most one of those four views
    beyond its margin, which two votes of four missed): the smile given as the neutral face has the wider mouth by more
    than a view's cap, enough with the others' say; in the right order, nothing."""
    neutral, smile = (Face.of(*photo(person, kind), DLIB68) for kind in ("neutral", "smile"))
    told = says(smile, neutral, DLIB68)
    assert (told[:4] > 1).sum() <= 1 and told[4] > CAP
    assert swapped(smile, neutral, DLIB68) and not swapped(neutral, smile, DLIB68)


def test_a_rise_is_an_expressions_whatever_it_does():
    """The rise counts the scores an expression raises against those it lowers, whatever their names: a frown and raised
    brows (a sad face) rise as a smile does, and the same motion undone falls as far."""
    from exprclone.landmarks.blendshapes import NAMES

    rest = np.zeros(52)
    for names in (("mouthSmileLeft", "mouthSmileRight"), ("mouthFrownLeft", "mouthFrownRight", "browInnerUp"), ("jawOpen",)):
        moved = rest.copy()
        moved[[NAMES.index(n) for n in names]] = 0.4
        assert rise(rest, moved) > MARGINS[0] and rise(moved, rest) == pytest.approx(-rise(rest, moved)), names
        assert from_rest(moved) > from_rest(rest), names


def test_another_light_is_no_swap(photos):
    """The smile made grey, relit by +-15% from one ear to the other, or given another white balance (the landmarks
    found afresh on it): the right order raises nothing, whatever the light; swapped, the two photos so changed are
    told."""
    detect = default_detector().detect
    for i in PEOPLE:
        neutral, smiling = photos[i, "neutral"], photos[i, "smile"]
        for name, image in changes(smiling.image, smiling.points).items():
            changed = Face.of(image, detect(image), DLIB68)
            assert judge_roles(neutral, changed, DLIB68) == [], (i, name)
            calm = changes(neutral.image, neutral.points)[name]
            assert "swapped" in judge_roles(changed, Face.of(calm, detect(calm), DLIB68), DLIB68)[0], (i, name)


def test_a_speakers_open_mouth_is_no_swap_and_its_swap_is_told():
    """A GRID speaker's most closed frame as the neutral face and its widest open one as the expression: no warning in
    that order, the swap told; though no smile (its open mouth lowers the landmarks' smile, as a sad face does)."""
    clip = need_full_data(GRID / "lbax4n.mpg")
    detect = default_detector().detect
    frames = list(read_frames(clip))
    points = np.array([detect(f) for f in frames])
    opening = np.array([measure.opening(p, DLIB68) for p in points])
    closed = Face.of(frames[k := closed_mouth_frame(points, np.ones(len(frames), bool), DLIB68)], points[k], DLIB68)
    opened = Face.of(frames[k := int(np.argmax(opening))], points[k], DLIB68)
    assert judge_roles(closed, opened, DLIB68) == []
    assert "swapped" in judge_roles(opened, closed, DLIB68)[0]


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
