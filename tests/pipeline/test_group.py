"""A photo of several faces: each found, numbered, chosen, cloned in its own region, and blended back without touching
the rest (on a group photo made of the three packaged London people)."""

import dataclasses
import warnings

import numpy as np
import pytest

import exprclone
import exprclone.expressions
from exprclone import data as samples
from exprclone.errors import ExprCloneError, ExprCloneWarning
from exprclone.evaluation.groups import make
from exprclone.landmarks.backends import default_detector
from exprclone.landmarks.layout import DLIB68
from exprclone.pipeline import group

#: the three packaged people at these face widths in a photo of this size: one behind, two in front, the largest face's
#: region over the other's face.
WIDTHS, SIZE = (110, 170, 250), (700, 800)


@pytest.fixture(scope="module")
def made():
    """The made photo, where each person is, and the faces found in it."""
    image, people = make(samples.london(), samples.PEOPLE, WIDTHS, SIZE, seed=3)
    return image, people, group.find(image, default_detector(), "group", DLIB68)


@pytest.fixture(scope="module")
def smiling(made):
    """Everyone given the built-in smile."""
    image, _, found = made
    return exprclone.expressions.clone(image, "smile", target_faces=found)


def inside(box, point):
    return box[0] <= point[0] <= box[2] and box[1] <= point[1] <= box[3]


def cores(found, shape):
    """Each face's core (the ellipse it keeps from other faces' clones) as a mask of the photo."""
    ys, xs = np.mgrid[0 : shape[0], 0 : shape[1]]
    return {f.number: group.core_radius(f.points, ys, xs) <= 1 for f in found}


def outside_regions(shape, regions):
    mask = np.ones(shape[:2], bool)
    for x0, y0, x1, y1 in regions:
        mask[y0:y1, x0:x1] = False
    return mask


def test_every_face_is_found_and_numbered_in_reading_order(made):
    _, people, found = made
    assert [f.number for f in found] == [1, 2, 3] and not any(f.problem for f in found)
    # the one behind (the narrowest, highest) first, then the front row from the left
    owners = [next(k for k, p in enumerate(people) if inside(f.box, p.landmarks[30])) for f in found]
    front = sorted((1, 2), key=lambda k: people[k].landmarks[30][0])
    assert owners == [0, *front]
    for f in found:  # the landmarks fitted where the person's own template puts them
        truth = people[owners[f.number - 1]].landmarks
        assert np.median(np.linalg.norm(f.points - truth, axis=1)) < 0.1 * people[owners[f.number - 1]].width


def test_a_portrait_gives_its_face_as_the_landmarker_detects_it():
    photo = samples.photo("003")
    (face,) = group.find(photo, default_detector(), "003", DLIB68)
    assert face.number == 1 and np.array_equal(face.points, default_detector().detect(photo))


def test_a_portrait_is_cloned_whole_as_before():
    """A photo of one face takes the path it always took: the same image, bit for bit, as with its landmarks given."""
    photo = samples.photo("003")
    found = exprclone.expressions.clone(photo, "smile")
    given = exprclone.expressions.clone(photo, "smile", target_landmarks=default_detector().detect(photo))
    assert np.array_equal(found.image, given.image) and found.face_results == ()


def test_each_face_is_cloned_in_its_region_and_the_rest_is_the_input(made, smiling):
    image, _, found = made
    results = smiling.face_results
    assert [r.number for r in results] == [1, 2, 3] and all(r.result is not None and not r.problem for r in results)
    outside = outside_regions(image.shape, [r.region for r in results])
    assert outside.any() and np.array_equal(smiling.image[outside], image[outside])
    own = cores(found, image.shape)
    for r in results:  # over its own face, the photo is the face's own clone
        x0, y0, x1, y1 = r.region
        core = own[r.number][y0:y1, x0:x1]
        assert np.abs(smiling.image[y0:y1, x0:x1][core].astype(int) - r.result.image[core]).max() <= 1
        assert np.abs(smiling.image[y0:y1, x0:x1][core].astype(int) - image[y0:y1, x0:x1][core]).max() > 40
        assert r.result.landmarks["final"].shape == (68, 2) and r.box == found[r.number - 1].box
    assert smiling.landmarks == {} and smiling.lambda_k is None


def test_the_faces_not_chosen_are_left_as_they_are(made):
    image, _, found = made
    result = exprclone.expressions.clone(image, "smile", target_faces=found, faces="3")  # its region reaches over face 2
    (cloned,) = [r for r in result.face_results if r.result is not None]
    assert cloned.number == 3 and [r.problem for r in result.face_results] == ["not chosen", "not chosen", ""]
    own = cores(found, image.shape)
    for number in (1, 2):
        assert np.array_equal(result.image[own[number]], image[own[number]])
    outside = outside_regions(image.shape, [cloned.region])
    assert np.array_equal(result.image[outside], image[outside]) and not np.array_equal(result.image, image)


def test_the_largest_face_alone(made):
    image, _, found = made
    result = exprclone.expressions.clone(image, "smile", target_faces=found, faces="largest")
    assert [r.number for r in result.face_results if r.result is not None] == [max(found, key=lambda f: f.across).number]


def test_a_face_that_cannot_be_cloned_is_left_with_a_warning_naming_it(made):
    image, _, found = made
    odd = tuple(dataclasses.replace(f, problem="too small (60 px across, at least 80)") if f.number == 1 else f for f in found)
    with pytest.warns(ExprCloneWarning, match=r"face 1: too small \(60 px across, at least 80\); left as it is"):
        result = exprclone.expressions.clone(image, "smile", target_faces=odd)
    assert [r.result is None for r in result.face_results] == [True, False, False]
    own = cores(found, image.shape)[1]
    assert np.array_equal(result.image[own], image[own])


def test_a_face_number_the_photo_has_not_is_refused(made):
    image, _, found = made
    with pytest.raises(ExprCloneError, match=r"^faces: no face 5: the photo shows 3 faces"):
        exprclone.expressions.clone(image, "smile", target_faces=found, faces="1,5")
    with pytest.raises(ExprCloneError, match=r"^faces: no face 2: the photo shows 1 face "):
        exprclone.expressions.clone(samples.photo("003"), "smile", faces=[2])


def test_overlapping_regions_share_their_weight_and_fade_at_their_edges(made):
    image, _, found = made
    regions = [group.region(f.points, image.shape) for f in found]
    weights = group.weights(found, found, regions, image.shape)
    total = np.zeros(image.shape[:2])
    for w, (x0, y0, x1, y1) in zip(weights, regions):
        total[y0:y1, x0:x1] += w
        inner = [w[0] if y0 > 0 else None, w[-1] if y1 < image.shape[0] else None, w[:, 0] if x0 > 0 else None]
        assert all(edge is None or edge.max() == 0 for edge in inner)  # 0 where the region meets the photo
    assert total.max() <= 1 + 1e-6
    overlap = [min(a[2], b[2]) > max(a[0], b[0]) and min(a[3], b[3]) > max(a[1], b[1]) for a in regions for b in regions if a < b]
    assert any(overlap)  # (the made photo's regions do overlap)
    own, covered = cores(found, image.shape), 0
    for f, w, (x0, y0, x1, y1) in zip(found, weights, regions):
        assert w[own[f.number][y0:y1, x0:x1]].min() > 0.99  # a face is its own clone's
        for other in found:
            if other.number != f.number:
                assert w[own[other.number][y0:y1, x0:x1]].max(initial=0) == 0  # and no other face's
                covered += own[other.number][y0:y1, x0:x1].sum()
    assert covered > 1000  # (a region does reach over another face)


def test_a_pixel_of_two_regions_is_the_same_from_either():
    image = np.full((40, 60, 3), 100, np.uint8)
    regions = [(0, 0, 40, 40), (20, 0, 60, 40)]
    clones = [np.full((40, 40, 3), 200, np.uint8), np.full((40, 40, 3), 0, np.uint8)]
    weights = [np.full((40, 40), 0.5, np.float32), np.full((40, 40), 0.25, np.float32)]
    out = group.blend(image, clones, regions, weights)
    assert out[0, 10, 0] == 150 and out[0, 50, 0] == 75 and out[0, 30, 0] == 125  # 100 + 0.5 * 100 - 0.25 * 100


@pytest.mark.parametrize(
    ("change", "problem"),
    [
        (lambda p: p * 0.2, "too small"),
        (lambda p: p - p.min(0) + [1.0, 300.0], "cut by the frame"),
        (lambda p: np.where((np.arange(68)[:, None] >= 27) & (np.arange(68)[:, None] <= 35), p + [70.0, 0], p), "turned too far"),
    ],
)
def test_what_keeps_a_face_from_being_cloned(points, change, problem):
    face = points("003") * 0.5 + [40.0, 0]
    moved = change(face)
    low, high = moved.min(0), moved.max(0)
    box = (low[0], low[1], high[0], high[1])
    assert group.problem_of(face, (face.min(0)[0], 0, face.max(0)[0], 1), (800, 900), DLIB68) == ""
    assert group.problem_of(moved, box, (800, 900), DLIB68).startswith(problem)


def test_the_turn_of_a_face_facing_the_camera_is_small(points):
    assert group.turn(points("003"), DLIB68) < 0.1


def test_given_global_landmarks_are_one_faces(made):
    image, _, found = made
    with warnings.catch_warnings(), pytest.raises(ExprCloneError, match="^global_landmarks: one face's"):
        exprclone.expressions.clone(image, "smile", target_faces=found, global_landmarks=found[0].points)


def test_a_face_whose_landmarks_make_no_face_is_left_with_a_warning(made):
    image, _, found = made
    line = np.c_[np.linspace(*found[0].box[::2], 68), np.full(68, found[0].points[:, 1].mean())]
    flat = (dataclasses.replace(found[0], points=line), *found[1:])
    with pytest.warns(ExprCloneWarning, match=r"^target_neutral: face 1: not a face: .*; left as it is$"):
        result = exprclone.expressions.clone(image, "smile", target_faces=flat)
    assert [r.result is None for r in result.face_results] == [True, False, False]
