"""Driving a portrait from the GRID clips: smoothing, mouth motion, head motion, the command."""

import os
import subprocess
import sys

import numpy as np
import pytest
from conftest import GRID_CLIPS, command, need_full_data, neutral_path
from serving import interruptible

from exprclone import data as samples
from exprclone import drive
from exprclone.drive import driver, tracking
from exprclone.drive.framing import resize_portrait
from exprclone.io.images import load_image
from exprclone.io.video import probe, read_frames
from exprclone.landmarks import backends
from exprclone.landmarks.layout import DLIB68
from exprclone.mouth import measure
from exprclone.pipeline import clone

pytestmark = pytest.mark.slow  # servers, browsers, clusters or videos: pytest -m 'not slow' leaves these out

PORTRAIT = neutral_path("003")


run = command  # in this process


MOUTH = DLIB68.mouth_outer + DLIB68.mouth_inner


def opening(points):
    """The mouth opening (inner-lip area over squared width) of each frame: (T, 68, 2) -> (T,)."""
    return np.array([measure.opening(p, DLIB68) for p in points])


def prepare(portrait, clip, **options) -> drive.Recording:
    """The portrait prepared to be driven by a clip file."""
    return drive.prepare(portrait, None, lambda: read_frames(clip), float(probe(clip).fps), **options)


@pytest.fixture(scope="module")
def portrait(london):
    return resize_portrait(load_image(PORTRAIT), None, 256)[0]


@pytest.fixture(scope="module")
def driven(portrait, grid_clip):
    """The portrait driven by a clip with smoothing (as shipped) and without."""
    out = {}
    for smooth in (True, False):
        recording = prepare(portrait, grid_clip, smooth=smooth)
        out[smooth] = recording, list(recording.frames(read_frames(grid_clip)))
    return out


def raw_landmarks(clip):
    """The driver's landmarks as the detector finds them afresh on every frame (None: no face)."""
    detector = backends.default_detector()
    return [detector.fit(f, b[0]) if (b := detector.faces(f)) else None for f in read_frames(clip)]


def test_output_is_smoother_than_the_raw_detections(driven):
    """The issue's check, first half: less jitter in the output's mouth than with the raw per-frame fits."""
    final = {s: np.array([f.result.landmarks["final"] for f in frames]) for s, (_, frames) in driven.items()}
    assert tracking.jitter(final[True], MOUTH) < 0.7 * tracking.jitter(final[False], MOUTH)


def test_output_mouth_follows_the_driver_on_every_clip(portrait):
    """The issue's check, second half: the mouth opening over time, driver against output.

    The driver's opening comes from the detector run afresh on every frame (independent of
    the tracker); the neutral face is the frame with the most closed mouth. Median over the
    eleven clips above 0.9 (the noisiest, a moustached speaker, is about 0.8).
    """
    correlations = []
    for clip in map(need_full_data, GRID_CLIPS):
        raw = raw_landmarks(clip)
        seen = [i for i, p in enumerate(raw) if p is not None]
        recording = prepare(portrait, clip, neutral_frame="closed")
        final = np.array([f.result.landmarks["final"] for f in recording.frames(read_frames(clip))])
        correlations.append(np.corrcoef(opening(np.array([raw[i] for i in seen])), opening(final[seen]))[0, 1])
    assert np.median(correlations) > 0.9, correlations


def test_every_frame_is_rendered_at_the_portrait_size_with_one_lambda(driven, portrait):
    recording, frames = driven[True]
    assert [f.index for f in frames] == list(range(75))
    assert all(f.image.shape == portrait.shape for f in frames)
    # the neutral face is by default the frame whose mouth is most closed
    assert recording.neutral_index == driver.closed_mouth_frame(recording.points, recording.track.found, DLIB68)
    assert len(recording.lambda_frames) == driver.LAMBDA_FRAMES
    assert min(np.diff(sorted(recording.lambda_frames))) >= 12  # half a second apart at 25 fps
    assert {f.result.lambda_k for f in frames} == {recording.driver.lambda_k}
    assert frames[recording.neutral_index].result.mouth_mask is None  # the neutral frame is the neutral face


def test_head_motion_is_carried_as_the_same_rotation_and_scale(driven):
    """The source's head similarity, moved into the portrait's frame, keeps its angle and scale."""
    driver = driven[True][0].driver
    s_neu = driver.cloner.faces.s_neu
    angle, scale = np.deg2rad(6), 1.05
    turn = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]]) * scale
    moved = (s_neu - s_neu.mean(0)) @ turn.T + s_neu.mean(0) + (3, -2)
    t = driver._head_motion(moved)
    assert np.isclose(np.hypot(t[0, 0], t[1, 0]), scale)
    assert np.isclose(np.arctan2(t[1, 0], t[0, 0]), angle)
    assert np.allclose(driver._head_motion(s_neu), [[1, 0, 0], [0, 1, 0]], atol=1e-9)


def test_neutral_photo_of_the_source(portrait, grid_clip):
    """The source's neutral face may be a photo instead of a frame: that photo, as a frame, changes nothing."""
    frame = next(f for i, f in enumerate(read_frames(grid_clip)) if i == 3)
    recording = prepare(portrait, grid_clip, source_neutral=(frame, None), method="global")
    assert recording.neutral_index is None and recording.driver.lambda_k is None
    photo_points = backends.default_detector().detect(frame)
    same = recording.driver.render(frame, photo_points).image
    assert np.abs(same.astype(int) - portrait).max() <= 1
    moved = [f.image for f in recording.frames(read_frames(grid_clip))]
    assert max(np.abs(m.astype(int) - portrait).mean() for m in moved) > 1.0


def test_frames_rendered_at_once_are_those_rendered_one_by_one(driven, grid_clip):
    """The driver's threads give every frame, in order, as it renders alone."""
    recording, frames = driven[True]
    alone = [recording.driver.render(f, p, i) for i, (f, p) in enumerate(zip(read_frames(grid_clip), recording.points))]
    assert [f.index for f in frames] == list(range(len(alone))) and len(alone) == 75
    assert all(np.array_equal(a.image, b.image) for a, b in zip(alone, frames))


def test_frames_from_a_stream_that_cannot_be_read_twice(driven, grid_clip):
    """A live source (a webcam, a socket) is read once: the driver renders any iterator of frames with their landmarks."""
    recording, frames = driven[True]
    tracker = tracking.Tracker(backends.default_detector())
    stream = ((frame, tracker.update(frame)) for frame in read_frames(grid_clip))  # one pass, landmarks as they come
    live = [recording.driver.render(frame, points, i) for i, (frame, points) in enumerate(stream) if points is not None]
    assert len(live) == 75 and all(f.image.shape == frames[0].image.shape for f in live)
    raw = driven[False][1]  # the same frames, rendered from the recording's raw fits
    assert np.array_equal(live[40].result.landmarks["source_expression"], raw[40].result.landmarks["source_expression"])


@pytest.mark.parametrize("clip", [samples.clip(), *GRID_CLIPS], ids=lambda c: c.name)
def test_command_drives_a_portrait_with_every_clip(clip, tmp_path):
    """The packaged clip, and every clip of the full set."""
    need_full_data(clip)
    out = tmp_path / "out.mp4"
    p = run("video", PORTRAIT, clip, "-o", out, "--size", 160, "--side-by-side")
    assert p.returncode == 0, p.stderr
    info = probe(out)
    assert (info.frames, info.fps, info.height, info.has_audio) == (75, 25, 160, True)
    assert info.width == 160 + 200  # the 360x288 driving frame scaled to 160 high, then the portrait
    assert "a face on every frame" in p.stdout
    assert os.listdir(tmp_path) == ["out.mp4"]


@pytest.mark.parametrize(
    "args, message",
    [
        (["missing.mp4"], "missing.mp4: no such file"),
        ([PORTRAIT], "not a video"),
        (["{clip}", "--neutral-frame", "500"], "no frame 500"),
        (["{clip}", "--size", "4"], "--size"),
        (["{clip}", "--size", "100000"], "--size: must be from 16 to 4096 pixels"),  # was OpenCV's allocation traceback
    ],
)
def test_bad_input_is_one_line_and_no_output(args, message, grid_clip, tmp_path):
    out = tmp_path / "out.mp4"
    args = [str(a).format(clip=grid_clip) for a in args]
    p = run("video", PORTRAIT, *args, "-o", out)
    assert p.returncode == 2 and message in p.stderr and len(p.stderr.strip().splitlines()) == 1, p.stderr
    assert os.listdir(tmp_path) == []


def test_output_over_the_driving_video_is_refused(grid_clip, tmp_path):
    copy = tmp_path / "clip.mp4"
    copy.write_bytes(grid_clip.read_bytes())
    p = run("video", PORTRAIT, copy, "-o", copy)
    assert p.returncode == 2 and "overwrite" in p.stderr
    assert copy.read_bytes() == grid_clip.read_bytes()


def test_a_run_failing_half_way_leaves_no_file(portrait, grid_clip, tmp_path, monkeypatch):
    from exprclone import cli
    from exprclone.errors import ExprCloneError

    render = clone.Cloner.clone_methods
    calls = []

    def failing(self, *args, **kwargs):
        calls.append(1)
        if len(calls) > 20:
            raise ExprCloneError("frame", "simulated failure")
        return render(self, *args, **kwargs)

    monkeypatch.setattr(clone.Cloner, "clone_methods", failing)
    out = tmp_path / "out.mp4"
    assert cli.main(["video", str(PORTRAIT), str(grid_clip), "-o", str(out), "--size", "128", "--method", "global"]) == 2
    assert len(calls) > 20 and os.listdir(tmp_path) == []


def test_an_interrupted_run_says_so_and_leaves_no_file(grid_clip, tmp_path):
    """Ctrl-C half way: one line, exit 130, nothing at the output path.

    The clip is played four times over (300 frames, several seconds of rendering) and Ctrl-C comes once the first progress
    line shows frames being written, so that it falls inside the run even on a fast machine (on the 75-frame clip a
    fast machine could finish before the test's signal arrived)."""
    import signal

    from exprclone.io.video import write_video

    frames = list(read_frames(grid_clip))
    long_clip = tmp_path / "long.mp4"
    write_video(long_clip, frames * 4, probe(grid_clip).fps)
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    p = subprocess.Popen(
        [sys.executable, "-m", "exprclone", "video", str(PORTRAIT), str(long_clip), "-o", str(out_dir / "out.mp4"), "--size", "256"],
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=interruptible,
    )
    first = p.stderr.readline()  # the progress bar's first line: frames are being rendered and encoded
    assert "/300 frames" in first, first
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=60)
    assert p.returncode == 130 and err.strip().endswith("exprclone: interrupted; no output written"), first + err
    assert os.listdir(out_dir) == []


def test_a_recording_is_read_once_to_track_and_once_to_fetch(portrait, grid_clip):
    passes = []

    def open_frames():
        passes.append(1)
        return read_frames(grid_clip)

    recording = drive.prepare(portrait, None, open_frames, 25.0, neutral_frame="closed")
    assert len(passes) == 2 and recording.lambda_frames  # the neutral frame and the lambda_k frames in one pass


def test_strength_and_the_other_options_drive_every_frame(portrait, grid_clip):
    """Strength 0 holds the portrait still through the whole performance; the options reach the cloner."""
    asked = dict(strength=0, global_warp="rbf", image_warp="tps", only=("mouth",), retarget=False)
    recording = prepare(portrait, grid_clip, neutral_frame="closed", **asked)
    options = recording.driver.cloner.options
    assert {k: getattr(options, k) for k in asked} == dict(asked, strength=0.0)
    frames = list(recording.frames(read_frames(grid_clip)))
    assert len(frames) == 75 and max(np.abs(f.image.astype(int) - portrait).max() for f in frames) <= 1


def test_the_command_takes_strength(grid_clip, tmp_path):
    out = tmp_path / "weak.mp4"
    options = ("--strength", "0.5", "--global-warp", "rbf", "--only", "mouth", "--no-retarget")
    p = run("video", PORTRAIT, grid_clip, "-o", out, "--size", 96, *options)
    assert p.returncode == 0, p.stderr
    assert probe(out).frames == 75
    p = run("video", PORTRAIT, grid_clip, "-o", tmp_path / "bad.mp4", "--strength", "5")
    assert p.returncode == 2 and "--strength" in p.stderr and not (tmp_path / "bad.mp4").exists()


def test_the_mouth_at_strength_zero_is_the_portraits_own_in_every_frame(portrait, grid_clip, driven):
    """``strength_mouth=0`` holds the portrait's mouth through a performance that moves it: its landmarks exactly, its
    pixels within one level (the shading's weight is interpolated from a grid, small but not 0 inside the lips); the rest
    of the face is still driven."""
    import cv2

    recording = prepare(portrait, grid_clip, strength_mouth=0)
    neutral = recording.driver.cloner.faces.t_neu
    mask = np.zeros(portrait.shape[:2], np.uint8)
    cv2.fillConvexPoly(mask, cv2.convexHull(np.round(neutral[list(MOUTH)]).astype(np.int32)), 1)
    held = list(recording.frames(read_frames(grid_clip)))
    moving = driven[True][1]
    assert max(np.abs(f.image.astype(int) - portrait)[mask > 0].max() for f in moving) > 30  # the mouth that is held back
    assert all(np.array_equal(f.result.landmarks["final"][list(MOUTH)], neutral[list(MOUTH)]) for f in held)
    assert max(np.abs(f.image.astype(int) - portrait)[mask > 0].max() for f in held) <= 1
    assert max(np.abs(f.image.astype(int) - portrait)[mask == 0].max() for f in held) > 10  # the rest still moves
