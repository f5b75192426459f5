import numpy as np

from exprclone.landmarks import align
from exprclone.landmarks.layout import DLIB68


def similarity(angle, scale, shift):
    c, s = scale * np.cos(angle), scale * np.sin(angle)
    return np.array([[c, -s, shift[0]], [s, c, shift[1]]])


def test_fit_similarity_recovers_a_known_transform(pair_points):
    (landmarks, _, _), _ = pair_points
    t = similarity(0.3, 1.7, (12.0, -40.0))
    fitted = align.fit_similarity(landmarks, align.apply(t, landmarks))
    assert np.allclose(fitted, t, atol=1e-9)


def test_face_axes_follow_a_tilted_head(pair_points):
    (landmarks, _, _), _ = pair_points
    tilted = align.apply(similarity(0.4, 1.0, (0, 0)), landmarks)
    axes0, axes1 = align.face_axes(landmarks, DLIB68), align.face_axes(tilted, DLIB68)
    # face-frame coordinates of the points do not change when the head turns
    assert np.allclose(landmarks @ axes0.T - (landmarks @ axes0.T).mean(0), tilted @ axes1.T - (tilted @ axes1.T).mean(0), atol=1e-6)
    assert align.interocular(landmarks, DLIB68) > 100  # 1350-pixel photos
