import numpy as np
import pytest

from exprclone.drive import tracking
from exprclone.errors import ExprCloneError
from exprclone.io.video import read_frames
from exprclone.landmarks.backends import default_detector
from exprclone.landmarks.layout import DLIB68
from exprclone.mouth import measure


@pytest.fixture(scope="module")
def frames(grid_clip):
    return list(read_frames(grid_clip))


@pytest.fixture(scope="module")
def detected(frames):
    """The reference: the detector run afresh on every frame."""
    detector = default_detector()
    return np.array([detector.fit(f, detector.faces(f)[0]) for f in frames])


def test_tracking_follows_the_detections_with_few_detector_runs(frames, detected):
    track = tracking.track(frames, default_detector())
    assert track.found.all() and track.missing == 0
    iod = np.linalg.norm(detected[:, 45] - detected[:, 36], axis=1)
    error = np.linalg.norm(track.points - detected, axis=2).mean(1) / iod
    assert np.median(error) < 0.02 and error.max() < 0.05
    assert track.detections <= 2  # one to start; the face is never lost in this clip
    assert track.checks <= len(frames) // tracking.CHECK_EVERY


def test_frames_without_a_face_are_counted_and_hold_the_last_landmarks(frames):
    blank = np.full_like(frames[0], 128)
    video = frames[:30] + [blank] * 10 + frames[40:]
    track = tracking.track(video, default_detector())
    assert not track.found[30:40].any()
    assert track.found[:25].all() and track.found[45:].all()  # seen again once it is back
    last = int(np.flatnonzero(track.found[:30])[-1])
    assert all(np.array_equal(track.points[i], track.points[last]) for i in range(last, 40))


def test_a_video_without_a_face_is_an_error(frames):
    with pytest.raises(ExprCloneError, match="clip.mpg: no face found in any of its 5 frames"):
        tracking.track([np.zeros_like(frames[0])] * 5, default_detector(), "clip.mpg")


def test_smoothing_removes_jitter_but_keeps_the_mouth_motion(detected):
    """Jitter (the second difference over time) drops; the mouth opening still follows."""
    smoothed = tracking.smooth(detected, 25)

    lips = DLIB68.mouth_outer + DLIB68.mouth_inner
    assert tracking.jitter(smoothed, lips) < 0.7 * tracking.jitter(detected, lips)
    a, b = (np.array([measure.opening(p, DLIB68) for p in points]) for points in (smoothed, detected))
    assert np.corrcoef(a, b)[0, 1] > 0.9
    lags = range(-3, 4)
    shifted = [np.corrcoef(a[3 + lag : len(a) - 3 + lag], b[3:-3])[0, 1] for lag in lags]
    assert lags[int(np.argmax(shifted))] == 0  # no lag
