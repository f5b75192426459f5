"""The expression editor on real photos: its landmarks are GI, each control raises the blendshape score it names, the
smile alone brings shading, and no value changes nothing."""

import numpy as np
import pytest

import exprclone
from exprclone import data as samples
from exprclone.drive.framing import resize_portrait
from exprclone.errors import ExprCloneError, NoFaceError
from exprclone.expressions import editor as editing
from exprclone.expressions.controls import CONTROLS
from exprclone.landmarks import lips
from exprclone.landmarks.blendshapes import Blendshapes, indices
from exprclone.landmarks.layout import DLIB68


@pytest.fixture(scope="module")
def editor(photo):
    image, points = photo("003")
    return editing.Editor.of(editing.request(image, points))


def test_no_value_leaves_the_photo_as_it_is(editor, photo):
    image, _ = photo("003")
    still = editor.render({})
    assert np.abs(still.image.astype(int) - image).max() <= 1
    assert np.array_equal(editor.render({"smile": 0.0, "frown": 0.0}).image, still.image)


def test_the_final_landmarks_are_the_edited_ones(editor):
    """The edit is GI given (Fig. 21) and lambda_k 0: the final landmarks are the edited ones (the inner lips made
    valid, as every clone makes them)."""
    values = {"smile": 0.7, "brows_down": 0.4, "wink_right": 1.0}
    result = editor.render(values)
    edited = editor.landmarks(values)
    assert result.method == "e+md" and result.lambda_k == 0.0
    assert np.array_equal(result.landmarks["global"], edited)
    assert np.abs(result.landmarks["final"] - lips.uncross(edited, DLIB68)).max() < 1e-6


def test_each_control_raises_the_score_it_names(photo):
    """On the sample people, the blendshape model reads each control's named scores higher at 1 than at 0 on average,
    and the smile, the mouth's opening, the frown and the blink higher at 1 than at 0 on each of them. (The issue's
    measure, the rise with the value on held-out people, is tools/judge_editor.py's: a control may not rise on a
    person or two, as the pucker does not on 126, puckered already, and one eye's wink on 126's narrow eye.)"""
    judge, rises = Blendshapes(), []
    for person in samples.PEOPLE:
        editor = editing.Editor.of(editing.request(*photo(person)))
        still = judge.scores(editor.render({}).image)
        rises.append(
            [judge.scores(editor.render({c.name: 1.0}).image)[indices(c.scores)].mean() - still[indices(c.scores)].mean() for c in CONTROLS]
        )
    names = [c.name for c in CONTROLS]
    assert np.all(np.mean(rises, axis=0) > 0), dict(zip(names, np.mean(rises, axis=0)))
    each = [names.index(n) for n in ("smile", "mouth_open", "frown", "eyes_closed")]
    assert np.all(np.array(rises)[:, each] > 0), rises


def test_the_smile_alone_brings_its_shading(editor):
    """The smile's shading (its ERI) comes with its value: without it the smile's image is its motion alone, and any
    other control comes without shading."""
    plain = editing.Editor(editor.cloner.changed(strength_shading=0.0), editor.expression)
    shaded, unshaded = (e.render({"smile": 1.0}) for e in (editor, plain))
    assert np.array_equal(shaded.landmarks["final"], unshaded.landmarks["final"])
    assert np.abs(shaded.image.astype(int) - unshaded.image).mean() > 0.05
    assert np.array_equal(editor.render({"brows_up": 1.0}).image, plain.render({"brows_up": 1.0}).image)


def test_the_values_add_up(editor):
    one, other = editor.landmarks({"smile": 0.5}), editor.landmarks({"brows_up": 0.8})
    both = editor.landmarks({"smile": 0.5, "brows_up": 0.8})
    assert np.allclose(both - editor.neutral, (one - editor.neutral) + (other - editor.neutral))


def test_a_smaller_photo_is_edited_alike(photo, editor):
    """The same values on the photo at 512 pixels (its preview) move its landmarks as far, in its scale."""
    image, points = photo("003")
    small, scaled = resize_portrait(image, points, 512)
    preview = editing.Editor.of(editing.request(small, scaled))
    values = {"mouth_open": 1.0, "brows_up": 0.5}
    scale = 512 / 1350
    assert np.allclose((preview.landmarks(values) - preview.neutral), (editor.landmarks(values) - editor.neutral) * scale, atol=1e-6)


def test_the_api_edits_as_the_editor_does():
    image = samples.photo("001")
    result = exprclone.edit(image, {"pucker": 0.6}, eyes_closed=0.3)
    again = editing.Editor.of(editing.request(image)).render({"pucker": 0.6, "eyes_closed": 0.3})
    assert np.array_equal(result.image, again.image) and result.image.shape == image.shape
    assert result.options.strength_shading == 1.0


def test_bad_values_and_photos_say_what_is_wrong():
    image = samples.photo("001")
    with pytest.raises(ExprCloneError) as e:
        exprclone.edit(image, grin=0.5)
    assert e.value.subject == "grin" and "smile, mouth_open" in e.value.problem
    with pytest.raises(ExprCloneError) as e:
        exprclone.edit(image, smile=1.5)
    assert e.value.subject == "smile"
    with pytest.raises(NoFaceError) as e:
        exprclone.edit(np.full((300, 300, 3), 128, np.uint8), smile=0.5)
    assert e.value.subject == "target_neutral"
    with pytest.raises(ExprCloneError) as e:
        exprclone.edit(image, landmarks=np.zeros((5, 2)), smile=0.5)
    assert e.value.subject == "target_neutral"
