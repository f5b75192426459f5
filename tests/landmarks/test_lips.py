import cv2
import numpy as np
import pytest

from exprclone.landmarks import align, lips
from exprclone.landmarks.layout import DLIB68
from exprclone.mouth.measure import mouth_width

INNER, OUTER = list(DLIB68.mouth_inner), list(DLIB68.mouth_outer)


def farthest_outside(landmarks):
    """How far (pixels) the inner-lip polygon reaches outside the outer lips, by OpenCV.

    Every vertex and points every quarter pixel along every edge are tested; 0 when all
    are inside or on the edge.
    """
    contour = landmarks[OUTER].astype(np.float32).reshape(-1, 1, 2)
    ring = landmarks[INNER]
    worst = 0.0
    for a, b in zip(ring, np.roll(ring, -1, axis=0)):
        for t in np.linspace(0, 1, int(4 * np.linalg.norm(b - a)) + 2):
            p = a + t * (b - a)
            worst = min(worst, cv2.pointPolygonTest(contour, (float(p[0]), float(p[1])), True))
    return -worst


def self_intersecting(polygon):
    """Whether two non-adjacent edges of a closed polygon cross."""
    n = len(polygon)

    def side(o, p, q):
        return (p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0])

    for i in range(n):
        for j in range(i + 2, n - (i == 0)):
            a, b, c, d = polygon[i], polygon[(i + 1) % n], polygon[j], polygon[(j + 1) % n]
            if side(a, b, c) * side(a, b, d) < 0 and side(c, d, a) * side(c, d, b) < 0:
                return True
    return False


def test_crossed_inner_lips_close_and_open_ones_stay(pair_points):
    (_, se, tn), _ = pair_points
    crossed = tn.copy()
    crossed[[61, 62, 63], 1] += 3
    crossed[[67, 66, 65], 1] -= 3
    fixed = lips.uncross(crossed, DLIB68)
    for upper, lower in DLIB68.lip_pairs:
        assert fixed[upper, 1] <= fixed[lower, 1] + 1e-9
    others = [i for i in range(68) if i not in (61, 62, 63, 65, 66, 67)]
    assert np.array_equal(fixed[others], crossed[others])
    opened = tn.copy()
    opened[[61, 62, 63], 1] -= 5
    assert np.array_equal(lips.uncross(opened, DLIB68), opened)


def test_inner_lips_above_or_below_the_outer_lips_move_onto_them(pair_points):
    (_, se, tn), _ = pair_points
    wild = tn.copy()
    wild[62, 1] = tn[51, 1] - 6  # upper inner lip above the upper outer lip
    wild[66, 1] = tn[57, 1] + 4  # lower inner lip below the lower outer lip
    fixed = lips.uncross(wild, DLIB68)
    depth = fixed @ align.face_axes(fixed, DLIB68)[1]  # how far down the face, as uncross measures it
    for top, upper, lower, bottom in DLIB68.lip_columns:
        assert depth[top] <= depth[upper] + 1e-9 <= depth[lower] + 2e-9 <= depth[bottom] + 3e-9
    assert depth[62] == pytest.approx(depth[51], abs=0.05) and depth[66] == pytest.approx(depth[57], abs=0.05)
    assert farthest_outside(fixed) < 1e-3
    assert np.array_equal(lips.uncross(se, DLIB68)[48:60], se[48:60])  # the outer lips never move


@pytest.mark.parametrize("face", [("001", "neutral"), ("001", "smile"), ("003", "neutral"), ("126", "neutral"), ("126", "smile")])
def test_real_inner_lips_end_inside_and_fitted_ones_inside_stay(points, face):
    landmarks = points(*face)
    assert farthest_outside(lips.uncross(landmarks, DLIB68)) < 1e-3
    # the fitter put these inside already: pulling in leaves them exactly as they were
    assert farthest_outside(landmarks) < 1e-3
    assert np.array_equal(lips.inside_outer_lips(landmarks, DLIB68), landmarks)


def test_inner_mouth_corners_outside_are_pulled_just_onto_the_outer_corners(pair_points):
    (_, _, tn), _ = pair_points
    right = (tn[54] - tn[48]) / np.linalg.norm(tn[54] - tn[48])
    wild = tn.copy()
    wild[60] = tn[48] - 0.1 * mouth_width(tn, DLIB68) * right
    wild[64] = tn[54] + 0.1 * mouth_width(tn, DLIB68) * right
    fixed = lips.inside_outer_lips(wild, DLIB68)
    assert farthest_outside(fixed) < 1e-3
    contour = tn[OUTER].astype(np.float32).reshape(-1, 1, 2)
    for i in (60, 64):  # on the outer lips' edge: moved no further than needed
        assert abs(cv2.pointPolygonTest(contour, tuple(map(float, fixed[i])), True)) < 0.01
    others = [i for i in range(68) if i not in (60, 64)]
    assert np.array_equal(fixed[others], wild[others])


def test_inflated_inner_lips_come_back_inside_without_crossing(pair_points):
    (_, se, tn), _ = pair_points
    for landmarks in (se, tn):
        centre = landmarks[OUTER].mean(0)
        wild = landmarks.copy()
        wild[INNER] = centre + 1.6 * (landmarks[INNER] - centre)  # every inner point outside
        assert farthest_outside(wild) > 1
        fixed = lips.uncross(wild, DLIB68)
        assert farthest_outside(fixed) < 1e-3 and not self_intersecting(fixed[INNER])
        assert np.array_equal(np.delete(fixed, INNER, axis=0), np.delete(wild, INNER, axis=0))


def test_randomly_thrown_inner_lips_always_end_inside(pair_points):
    (_, se, tn), _ = pair_points
    rng = np.random.default_rng(7)
    for k in range(40):
        wild = (se, tn)[k % 2].copy()
        wild[INNER] += rng.normal(0, 0.15 * mouth_width(wild, DLIB68), (len(INNER), 2))
        fixed = lips.uncross(wild, DLIB68)
        assert farthest_outside(fixed) < 1e-3, k
        assert np.array_equal(np.delete(fixed, INNER, axis=0), np.delete(wild, INNER, axis=0))


def test_the_quick_inside_test_never_says_inside_wrongly(pair_points):
    """clearly_inside is sufficient: whenever it says inside, the exact test agrees; on real lips it decides."""
    landmarks, _ = pair_points
    rng = np.random.default_rng(1)
    inner, outer = list(DLIB68.mouth_inner), list(DLIB68.mouth_outer)
    said_inside = 0
    for lm in landmarks:
        ring, polygon = lm[inner], lm[outer]
        assert lips.clearly_inside(ring, polygon)  # real fitted lips: no exact check needed
        width = mouth_width(lm, DLIB68)
        for _ in range(200):
            thrown = ring + rng.normal(0, 0.05 * width, ring.shape)
            exact = all(lips.segment_inside(thrown[k], thrown[(k + 1) % len(ring)], polygon) for k in range(len(ring)))
            if lips.clearly_inside(thrown, polygon):
                said_inside += 1
                assert exact
    assert 50 < said_inside < 550  # the random rings test both answers


def test_inside_counts_every_edge_and_vertex_and_nothing_beyond():
    """The even-odd rule alone calls points on a polygon's right and top edges outside; within TOLERANCE they are in."""
    square = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]])
    along = np.linspace(0.0, 10.0, 41)
    on = np.concatenate([np.c_[along, 0 * along], np.c_[10 + 0 * along, along], np.c_[along, 10 + 0 * along], np.c_[0 * along, along]])
    assert lips.inside(on, square).all()
    assert lips.inside(np.array([[5.0, 5.0], [10.0, 5.0 + 1e-9]]), square).all()  # inside; on the right edge within tolerance
    outward = np.repeat([[0.0, -1.0], [1.0, 0.0], [0.0, 1.0], [-1.0, 0.0]], len(along), axis=0)  # each edge's outward normal
    assert not lips.inside(on + 1e-4 * outward, square).any()
