"""The learnt shape of an expression (:mod:`exprclone.geometry.expression_shape`): the source's smile made as the
target's own face makes it, the rest of its motion kept where it stands out of people's own variation."""

import numpy as np

from exprclone.evaluation.scores import landmark_error
from exprclone.geometry import global_warp
from exprclone.geometry.expression_shape import SPREAD, ExpressionShape, default_model, in_pixels, normalised
from exprclone.landmarks.layout import DLIB68

MOUTH = list(DLIB68.mouth_outer + DLIB68.mouth_inner)
LOWER_LIP = [55, 56, 57, 58, 59, 65, 66, 67]


def test_no_motion_moves_nothing(points):
    model = default_model()
    assert np.allclose(model.transfer(points("126"), np.zeros((68, 2)), points("003"), DLIB68), 0)


def test_the_frame_is_the_faces_own(points):
    """Normalised coordinates are those of the face, whatever the photo's scale, turn and place; and back."""
    neutral = points("003")
    turn = np.array([[np.cos(0.3), -np.sin(0.3)], [np.sin(0.3), np.cos(0.3)]])
    moved = (2 * neutral) @ turn.T + (40, -7)
    assert np.allclose(normalised(neutral, neutral, DLIB68), normalised(moved, moved, DLIB68))
    motion = np.random.default_rng(0).normal(0, 3, (68, 2))
    assert np.allclose(in_pixels(neutral, normalised(neutral, motion, DLIB68, vectors=True), DLIB68), motion)


def test_a_target_twice_as_large_and_turned_moves_twice_as_far_turned(points):
    model = default_model()
    source, smile, target = points("126"), points("126", "smile"), points("003")
    motion = global_warp.remove_head_motion(source, smile, DLIB68) - source
    turn = np.array([[np.cos(0.2), -np.sin(0.2)], [np.sin(0.2), np.cos(0.2)]])
    plain = model.transfer(source, motion, target, DLIB68)
    scaled = model.transfer(source, motion, 2 * target @ turn.T, DLIB68)
    assert np.abs(plain).max() > 1 and np.allclose(scaled, 2 * plain @ turn.T)


def test_a_motion_far_beyond_a_smile_keeps_most_of_itself(points):
    """A lower lip dropped by half an eye distance (speech, surprise), no smile: the target's drops by most of it (the
    smile's share of the motion is the target's smile's, the rest shrunk by the people's own variation), where a model
    that kept the smile alone would drop it by a fraction."""
    model = default_model()
    source, target = points("126"), points("003")
    motion = np.zeros((68, 2))
    down = 0.5 * np.linalg.norm(source[45] - source[36])
    motion[LOWER_LIP, 1] = down
    moved = normalised(target, model.transfer(source, motion, target, DLIB68), DLIB68, vectors=True)[LOWER_LIP, 1]
    assert np.all(moved > 0.7 * 0.5) and np.all(moved < 0.5 + SPREAD * model.spread[LOWER_LIP])


def test_a_held_out_smile_is_closer_to_the_targets_own(photo, london_full):
    """Learnt from 24 other London people, 126's smile made on 003 and on 001 lies closer to their real smiles' mouths
    than 126's motion carried as it is (the global warp)."""
    people = sorted(p.name[:3] for p in (london_full / "neutral_front").glob("*_03.jpg"))
    learnt = [p for p in people if p not in ("001", "003", "126")][:24]
    model = ExpressionShape.learn([(photo(p)[1], photo(p, "smile")[1]) for p in learnt], DLIB68)
    source = photo("126")[1]
    motion = global_warp.remove_head_motion(source, photo("126", "smile")[1], DLIB68) - source
    for target in ("003", "001"):
        neutral, truth = photo(target)[1], photo(target, "smile")[1]
        learnt_smile = neutral + model.transfer(source, motion, neutral, DLIB68)
        carried = global_warp.global_landmarks(source, photo("126", "smile")[1], neutral, DLIB68)
        assert landmark_error(learnt_smile, truth, DLIB68)["mouth"] < landmark_error(carried, truth, DLIB68)["mouth"], target
