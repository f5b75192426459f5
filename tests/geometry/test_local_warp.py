import numpy as np
import pytest

from exprclone.geometry import global_warp, local_warp
from exprclone.landmarks import align
from exprclone.landmarks.layout import DLIB68


def ratio(points, axes):
    p = points @ axes.T
    size = p.max(0) - p.min(0)
    return size[1] / size[0]


@pytest.mark.parametrize("angle", [0.0, 0.35])
def test_each_organ_takes_the_source_height_to_width_ratio(pair_points, angle):
    (sn, se, tn), _ = pair_points
    rot = np.array([[np.cos(angle), -np.sin(angle), 0], [np.sin(angle), np.cos(angle), 0]])
    tn = align.apply(rot, tn)  # a tilted target head
    gl = global_warp.global_landmarks(sn, se, tn, DLIB68)
    lo = local_warp.local_landmarks(gl, se, DLIB68)
    ax_t, ax_s = align.face_axes(gl, DLIB68), align.face_axes(se, DLIB68)
    for name, idx in DLIB68.organs.items():
        idx = list(idx)
        assert ratio(lo[idx], ax_t) == pytest.approx(ratio(se[idx], ax_s), rel=1e-6), name
        assert ratio(gl[idx], ax_t) != pytest.approx(ratio(se[idx], ax_s), rel=1e-3), name
        # the box keeps its centre and width (Eq. 1 scales by W_t / W_s)
        box = lambda p: (p.min(0) + p.max(0)) / 2  # noqa: E731
        assert np.allclose(box(lo[idx] @ ax_t.T), box(gl[idx] @ ax_t.T))


def test_points_outside_the_organs_stay(pair_points):
    (sn, se, tn), _ = pair_points
    gl = global_warp.global_landmarks(sn, se, tn, DLIB68)
    lo = local_warp.local_landmarks(gl, se, DLIB68)
    organ_points = sorted(set().union(*DLIB68.organs.values()))
    others = [i for i in range(68) if i not in organ_points]
    assert others == list(DLIB68.jaw)
    assert np.array_equal(lo[others], gl[others])
    assert not np.allclose(lo[organ_points], gl[organ_points])
