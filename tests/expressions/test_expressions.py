"""The built-in expressions shipped in the package: what they are, how they load, and one photo cloned with them."""

import json

import numpy as np
import pytest
from conftest import LONDON, need_full_data

import exprclone
from exprclone import data as samples
from exprclone import expressions
from exprclone.errors import ExprCloneError
from exprclone.evaluation.judge import SMILING, SmileJudge
from exprclone.evaluation.scores import TEETH_SHOWN, teeth
from exprclone.expressions.files import write
from exprclone.landmarks import align
from exprclone.landmarks.blendshapes import Blendshapes, indices
from exprclone.landmarks.layout import DLIB68
from exprclone.mouth.camera import blur_sigma


def test_the_names_hold_the_prototypes_the_sample_smiles_and_the_edited_expressions():
    assert expressions.names() == ("angry", "sad", "smile", "smile-001", "smile-003", "smile-126", "smile-gentle", "surprise")


@pytest.mark.parametrize(
    "name, scores",
    [
        ("surprise", ("browInnerUp", "jawOpen")),
        ("sad", ("mouthFrownLeft", "mouthFrownRight")),
        ("angry", ("browDownLeft", "browDownRight")),
    ],
)
def test_the_edited_expressions_show_their_motions_on_the_gentle_prototypes_neutral_face(name, scores):
    """Made by the expression editor on the gentle prototype's neutral composite (its photo shared): the blendshape model
    reads each one's motions (the raised brows and dropped jaw of surprise, the corners down of sadness, the brows
    drawn down of anger) well above the neutral face's."""
    e, gentle = expressions.load(name), expressions.load("smile-gentle")
    assert e.files[0] == gentle.files[0] and np.array_equal(e.neutral.points, gentle.neutral.points)
    judge = Blendshapes()
    rise = judge.scores(e.expression.image)[indices(scores)] - judge.scores(e.neutral.image)[indices(scores)]
    assert np.all(rise > 0.1), dict(zip(scores, rise))


@pytest.mark.parametrize("name", expressions.names())
def test_each_loads_as_a_source_pair(name):
    e = expressions.load(name)
    assert e.name == name and e.description and e.people
    for face in (e.neutral, e.expression):
        assert face.image.dtype == np.uint8 and face.image.ndim == 3 and not face.image.flags.writeable
        assert face.points.shape == (68, 2)


def test_the_sample_smiles_are_the_shipped_photos():
    e = expressions.load("smile-126")
    assert e.people == ("126",) and e.files == (str(samples.path("126").resolve()), str(samples.path("126", "smile").resolve()))
    assert np.array_equal(e.expression.image, samples.photo("126", "smile"))


def test_an_unknown_name_lists_the_names():
    with pytest.raises(
        ExprCloneError, match=r"^expression: unknown expression 'grin'; the built-in expressions are: angry, sad, smile, smile-001"
    ):
        expressions.load("grin")


def test_the_prototype_smiles_wider_than_its_neutral_face_and_holds_its_head_still():
    e = expressions.load("smile")
    n, s = e.neutral.points, e.expression.points
    widening = np.linalg.norm(s[54] - s[48]) / np.linalg.norm(n[54] - n[48]) - 1
    assert widening > 0.15  # the London Set's median smile widens the mouth by 15%
    head = align.fit_rigid(s, n, DLIB68)  # one frame for both: the head does not move between them
    assert np.abs(head[:, :2] - np.eye(2)).max() < 0.01 and np.abs(head[:, 2]).max() < 0.01 * align.interocular(n, DLIB68)


def test_the_prototype_shows_real_teeth_as_sharp_as_a_real_smiles():
    """The composite's own averaged teeth were too soft (tools/build_expressions.py): a real smile's interior is pasted."""
    e = expressions.load("smile").expression
    mouth = align.box(e.points[list(DLIB68.mouth_inner)], e.image.shape)
    assert teeth(e.image, e.points, DLIB68) >= TEETH_SHOWN
    # blur between the inner lips, in outer-eye-corner distances: the London Set's 36 smiles that show teeth
    # 0.0025-0.0039, the composite's own averaged interior 0.0081 (tools/build_expressions.py); the bound is their
    # geometric mean
    assert blur_sigma(e.image[mouth]) / align.interocular(e.points, DLIB68) < np.sqrt(0.0039 * 0.0081)


def test_the_python_api_is_clone_with_the_pair(photo):
    target, points = photo("003")
    smile = expressions.load("smile")
    result = expressions.clone(target, "smile", strength=0.5, target_landmarks=points)
    pair = (smile.neutral.points, smile.expression.points, points)
    same = exprclone.clone(smile.neutral.image, smile.expression.image, target, landmarks=pair, strength=0.5)
    assert np.array_equal(result.image, same.image) and result.options.strength == 0.5


@pytest.mark.parametrize("name", ["surprise", "sad", "angry"])
def test_a_built_in_pair_is_not_judged_as_if_given(name, recwarn):
    # the editor's surprise, its brows raised, looked like another person than its neutral face to the role check,
    # and every clone with it was warned that the source's two photos should show one person
    expressions.clone(samples.photo("003"), name)
    assert not [str(w.message) for w in recwarn if issubclass(w.category, exprclone.ExprCloneWarning)]


def test_strength_zero_leaves_the_target_and_regions_keep_the_rest(photo):
    target, points = photo("001")
    unchanged = expressions.clone(target, "smile", strength=0, target_landmarks=points).image
    assert np.abs(unchanged.astype(int) - target).max() <= 1
    mouth_only = expressions.clone(target, "smile", method="global", only=("mouth",), target_landmarks=points)
    eyes = list(DLIB68.eyes[0] + DLIB68.eyes[1] + DLIB68.brows[0] + DLIB68.brows[1])
    final = mouth_only.landmarks["final"]
    assert np.abs(final[eyes] - points[eyes]).max() < 1e-6 and np.abs(final[48:] - points[48:]).max() > 5


def test_an_expression_file_round_trips(tmp_path):
    e = expressions.load("smile-003")
    path = write(e, tmp_path)
    again = expressions.load(str(path))
    assert again.people == e.people and np.abs(again.expression.points - e.expression.points).max() <= 0.005
    assert json.loads(path.read_text())["expression"]["image"] == "smile-003-expression.jpg"


def test_a_broken_expression_file_is_one_error(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{"name": "x"}')
    with pytest.raises(ExprCloneError, match="not an expression file"):
        expressions.load(str(bad))


def test_the_prototype_reads_as_a_smile_to_a_judge_that_never_saw_its_people():
    need_full_data(LONDON / "neutral_front")
    from conftest import neutral_path, smile_path

    from exprclone.io.images import load_image
    from exprclone.landmarks.backends import default_detector

    e = expressions.load("smile")
    others = sorted({p.name[:3] for p in (LONDON / "neutral_front").glob("*_03.jpg")} - set(e.people))[:12]
    assert len(others) == 12
    faces = [[default_detector().detect(load_image(path(p)), p) for p in others] for path in (neutral_path, smile_path)]
    judge = SmileJudge.train(*faces)
    assert judge(e.expression.points) >= SMILING > judge(e.neutral.points)


def test_the_gentle_prototype_smiles_less_than_the_open_one():
    def widening(e):
        n, s = e.neutral.points, e.expression.points
        return np.linalg.norm(s[54] - s[48]) / np.linalg.norm(n[54] - n[48]) - 1

    gentle, smile = expressions.load("smile-gentle"), expressions.load("smile")
    assert 0 < widening(gentle) < widening(smile) and len(gentle.people) > len(smile.people)


def test_a_video_frame_it_has_never_seen_gets_the_smile():
    """A GRID frame (360x288, another camera and light): the mouth widens by the prototype's share, the eyes stay."""
    from exprclone.io.video import read_frames

    frame = next(iter(read_frames(samples.clip())))
    result = expressions.clone(frame, "smile")
    before, after = result.landmarks["target_neutral"], result.landmarks["final"]
    assert result.image.shape == frame.shape and not np.array_equal(result.image, frame)
    smile = expressions.load("smile")
    width = lambda p: np.linalg.norm(p[54] - p[48]) / align.interocular(p, DLIB68)  # noqa: E731
    prototype = width(smile.expression.points) / width(smile.neutral.points)
    assert 1 + 0.5 * (prototype - 1) < width(after) / width(before) < 1 + 1.5 * (prototype - 1)
