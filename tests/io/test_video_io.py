"""Tests for exprclone.io.video: probing and decoding videos, encoding frames (with sound) atomically."""

from fractions import Fraction
from pathlib import Path

import av
import cv2
import numpy as np
import pytest
from conftest import neutral_path

from exprclone.errors import ExprCloneError
from exprclone.io.video import probe, read_frames, write_video


@pytest.fixture(scope="module")
def clip_frames(grid_clip: Path) -> list[np.ndarray]:
    """Every frame of the GRID clip, decoded once."""
    return list(read_frames(grid_clip))


def stream_seconds(path: Path, kind: str) -> float:
    """Duration of the first ``kind`` ('video' or 'audio') stream of ``path``, in seconds."""
    with av.open(str(path)) as container:
        stream = getattr(container.streams, kind)[0]
        return float(stream.duration * stream.time_base)


def decoded_sound(path: Path) -> np.ndarray:
    """The first channel of the sound of ``path`` as floats in [-1, 1], shape (samples,)."""
    with av.open(str(path)) as container:
        sound = np.concatenate([frame.to_ndarray()[0] for frame in container.decode(audio=0)])
    return sound / 32768 if sound.dtype == np.int16 else sound


def mean_abs_difference(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a.astype(np.int16) - b).mean())


@pytest.mark.parametrize("which", ["grid_clip", "grid_mpg"])
def test_probe_describes_grid_clip(which, request):
    """The packaged clip (MP4, which records its frame count) and the corpus's own (MPEG-PS, which does not)."""
    clip = request.getfixturevalue(which)
    info = probe(clip)
    assert (info.path, info.width, info.height) == (str(clip), 360, 288)
    assert info.fps == 25 and isinstance(info.fps, Fraction)
    assert info.frames == 75  # from MPEG-PS: estimated from the duration
    assert info.has_audio


def test_read_frames_yields_every_frame_as_contiguous_rgb(grid_clip, clip_frames):
    assert len(clip_frames) == 75
    for frame in clip_frames:
        assert frame.shape == (288, 360, 3) and frame.dtype == np.uint8 and frame.flags.c_contiguous
    # OpenCV decodes through FFmpeg too, in BGR order: the same pixels, channels reversed.
    capture = cv2.VideoCapture(str(grid_clip))
    for frame in clip_frames:
        ok, bgr = capture.read()
        assert ok and mean_abs_difference(frame, bgr[..., ::-1]) < 0.5
    assert not capture.read()[0]
    capture.release()


def lossless_clip(path: Path, frames: list[np.ndarray], rotation: int = 0) -> None:
    """``frames`` in an H.264 file without loss (4:4:4, qp 0), stored turned clockwise by ``rotation`` degrees with a
    display matrix that turns them back, as a phone stores a video filmed upright."""
    stored = [np.ascontiguousarray(np.rot90(f, -rotation // 90)) for f in frames]
    with av.open(str(path), "w") as container:
        stream = container.add_stream("libx264", rate=25, options={"qp": "0"})
        stream.height, stream.width = stored[0].shape[:2]
        stream.pix_fmt = "yuv444p"
        if rotation:
            stream.set_display_rotation(rotation)
        for frame in stored:
            container.mux(stream.encode(av.VideoFrame.from_ndarray(frame, format="rgb24")))
        container.mux(stream.encode())


@pytest.mark.parametrize("rotation", [90, -90, 180])
def test_a_phones_turned_video_is_read_upright(clip_frames, tmp_path, rotation):
    """A phone's video, stored turned with a display matrix, is read as a player shows it: the frames of the same video
    stored upright, pixel for pixel. Before, its frames came turned, and ``exprclone video`` found no face in any."""
    lossless_clip(tmp_path / "upright.mp4", clip_frames[:8])
    lossless_clip(tmp_path / "turned.mp4", clip_frames[:8], rotation)
    upright, turned = list(read_frames(tmp_path / "upright.mp4")), list(read_frames(tmp_path / "turned.mp4"))
    assert len(turned) == 8 and all(f.shape == (288, 360, 3) and f.flags.c_contiguous for f in turned)
    assert all(np.array_equal(a, b) for a, b in zip(turned, upright))
    assert mean_abs_difference(upright[0], clip_frames[0]) < 1.0  # (lossless but for the colour conversion's rounding)


def test_round_trip_keeps_frames_rate_and_sound(grid_clip, clip_frames, tmp_path):
    out = tmp_path / "copy.mp4"
    assert write_video(out, iter(clip_frames), probe(grid_clip).fps, audio_from=grid_clip) == 75
    info = probe(out)
    assert (info.width, info.height, info.fps, info.frames, info.has_audio) == (360, 288, 25, 75, True)
    copies = list(read_frames(out))
    assert len(copies) == 75
    # Measured 2.0 levels per frame at CRF 18; swapping R and B gives 80, reading BT.709 as BT.601 5.7.
    differences = [mean_abs_difference(frame, copy) for frame, copy in zip(clip_frames, copies)]
    assert max(differences) < 4
    # The clip's sound (2.98 s; the 75 frames last 3 s) is carried over whole, in step.
    with av.open(str(out)) as container:
        assert [stream.start_time for stream in container.streams] == [0, 0]
    original, copy = decoded_sound(grid_clip), decoded_sound(out)
    assert stream_seconds(out, "audio") == pytest.approx(len(original) / 44100, abs=0.005)
    overlap = min(len(original), len(copy))
    assert np.corrcoef(original[:overlap], copy[:overlap])[0, 1] > 0.99


def test_frames_keep_their_order_and_colours(tmp_path):
    """A red square moving 8 pixels a frame: a dropped, repeated or reordered frame, or swapped channels, show."""
    frames = []
    for index in range(8):
        frame = np.full((64, 64, 3), 40, np.uint8)
        frame[24:40, 8 * index : 8 * index + 8] = (220, 30, 30)
        frames.append(frame)
    out = tmp_path / "square.mkv"
    assert write_video(out, (frame for frame in frames), Fraction(30000, 1001)) == 8
    assert probe(out).fps == Fraction(30000, 1001)
    copies = list(read_frames(out))
    assert len(copies) == 8
    for index, copy in enumerate(copies):
        redness = copy[..., 0].astype(int) - copy[..., 2]
        assert np.argmax(redness[32]) // 8 == index
        assert mean_abs_difference(copy, frames[index]) < 4


def test_odd_size_is_padded_by_repeating_the_edge(clip_frames, tmp_path):
    frames = [frame[:101, :77] for frame in clip_frames[:3]]
    out = tmp_path / "odd.mp4"
    write_video(out, frames, 25)
    copy = next(read_frames(out))
    assert copy.shape == (102, 78, 3)
    assert mean_abs_difference(copy[:101, :77], frames[0]) < 4
    assert mean_abs_difference(copy[101, :77], frames[0][100]) < 4  # last row repeated
    assert mean_abs_difference(copy[:101, 77], frames[0][:, 76]) < 4  # last column repeated


def test_sound_is_cut_to_the_video(grid_clip, clip_frames, tmp_path):
    out = tmp_path / "short.mov"
    write_video(out, clip_frames[:10], 25, audio_from=grid_clip)
    assert stream_seconds(out, "video") == pytest.approx(0.4)
    assert stream_seconds(out, "audio") == pytest.approx(0.4, abs=0.001)


def make_beeping_clip(path: Path, video_start: float, sound_start: float, beep_at: float = 0.3) -> None:
    """A 0.6 s mkv clip whose video and sound streams start at the given times (seconds); the sound
    is silent until ``beep_at``, then a 440 Hz tone. 64x64 gray frames at 25 fps, 44.1 kHz mono sound."""
    rate = 44100
    with av.open(str(path), "w") as container:
        video = container.add_stream("libx264", rate=25)
        video.width = video.height = 64
        video.pix_fmt = "yuv420p"
        audio = container.add_stream("pcm_s16le", rate=rate, layout="mono")
        first = round(sound_start * rate)
        seconds = np.arange(first, round((video_start + 0.7) * rate)) / rate
        tone = np.where(seconds >= beep_at, 0.5 * np.sin(2 * np.pi * 440 * seconds), 0)
        sound = av.AudioFrame.from_ndarray((tone * 32767).astype(np.int16)[None], format="s16", layout="mono")
        sound.sample_rate, sound.pts, sound.time_base = rate, first, Fraction(1, rate)
        container.mux(audio.encode(sound))
        container.mux(audio.encode())
        for index in range(15):
            picture = av.VideoFrame.from_ndarray(np.full((64, 64, 3), 10 * index, np.uint8))
            picture.pts, picture.time_base = round(video_start * 25) + index, Fraction(1, 25)
            container.mux(video.encode(picture))
        container.mux(video.encode())


@pytest.mark.parametrize(("video_start", "sound_start"), [(0.0, 0.1), (0.2, 0.0)])
def test_sound_keeps_its_timing_against_the_first_frame(tmp_path, video_start, sound_start):
    """Sound that starts after the video is delayed by silence; sound from before the video is cut."""
    source, out = tmp_path / "source.mkv", tmp_path / "out.mp4"
    make_beeping_clip(source, video_start, sound_start)
    write_video(out, read_frames(source), 25, audio_from=source)
    sound = decoded_sound(out)
    assert np.argmax(np.abs(sound) > 0.25) / 44100 == pytest.approx(0.3 - video_start, abs=0.005)
    assert stream_seconds(out, "audio") == pytest.approx(0.6, abs=0.001)


@pytest.mark.parametrize("error", [RuntimeError("renderer failed"), ValueError("bad landmarks"), KeyboardInterrupt()])
def test_failing_frames_leave_no_file(clip_frames, tmp_path, error, grid_clip):
    out = tmp_path / "out.mp4"
    out.write_bytes(b"earlier result")

    def frames():
        yield from clip_frames[:5]
        raise error

    with pytest.raises(type(error)) as raised:
        write_video(out, frames(), 25, audio_from=grid_clip)
    assert raised.value is error
    assert [p.name for p in tmp_path.iterdir()] == ["out.mp4"]
    assert out.read_bytes() == b"earlier result"


@pytest.mark.parametrize(
    "bad",
    [lambda frame: frame[:-2], lambda frame: frame.astype(np.float32), lambda frame: frame[..., 0]],
    ids=["other-size", "float", "gray"],
)
def test_bad_frame_raises_value_error_and_leaves_no_file(clip_frames, tmp_path, bad):
    with pytest.raises(ValueError, match="frame"):
        write_video(tmp_path / "out.mp4", [*clip_frames[:2], bad(clip_frames[2])], 25)
    assert list(tmp_path.iterdir()) == []


def test_no_frames_is_an_error(tmp_path):
    with pytest.raises(ExprCloneError, match="no frames"):
        write_video(tmp_path / "out.mp4", iter([]), 25)
    assert list(tmp_path.iterdir()) == []


def unreadable_inputs(tmp_path: Path) -> dict[str, Path]:
    text = tmp_path / "notes.txt"
    text.write_text("not a video\n")
    fake = tmp_path / "fake.mp4"
    fake.write_bytes(b"\x00\x00\x00\x18ftypmp42" + bytes(100))
    return {"missing": tmp_path / "missing.mp4", "text": text, "fake": fake, "photo": neutral_path("001"), "folder": tmp_path}


@pytest.mark.parametrize("kind", ["missing", "text", "fake", "photo", "folder"])
@pytest.mark.parametrize("read", [probe, read_frames])
def test_unreadable_input_is_an_error_naming_the_file(tmp_path, kind, read):
    path = unreadable_inputs(tmp_path)[kind]
    with pytest.raises(ExprCloneError) as raised:
        read(path)  # read_frames checks the file at the call, before iterating
    assert str(path) in str(raised.value) and "\n" not in str(raised.value)


def test_damaged_video_is_an_error_naming_the_file(clip_frames, tmp_path):
    whole, damaged = tmp_path / "whole.mp4", tmp_path / "damaged.mp4"
    write_video(whole, clip_frames[:10], 25)
    data = whole.read_bytes()
    damaged.write_bytes(data[: len(data) * 2 // 5])  # the index (written first) promises frames that are gone
    assert probe(damaged).frames == 10
    with pytest.raises(ExprCloneError, match="corrupt") as raised:
        list(read_frames(damaged))
    assert str(damaged) in str(raised.value)


def test_bad_output_path_fails_before_any_frame(clip_frames, tmp_path):
    source = tmp_path / "source.mp4"
    write_video(source, clip_frames[:2], 25)
    before = source.read_bytes()
    asked = []

    def frames():
        asked.append(True)
        yield clip_frames[0]

    for path, keywords, message in [
        (source, {"audio_from": source}, "overwrite"),
        (source, {"inputs": [source]}, "overwrite"),
        (tmp_path / "out.avi", {}, "format"),
        (tmp_path / "missing" / "out.mp4", {}, "does not exist"),
    ]:
        with pytest.raises(ExprCloneError, match=message):
            write_video(path, frames(), 25, **keywords)
    with pytest.raises(ExprCloneError, match="no such file"):
        write_video(tmp_path / "out.mp4", frames(), 25, audio_from=tmp_path / "missing.mpg")
    assert not asked
    assert source.read_bytes() == before


def test_an_mpeg_program_stream_is_read_within_a_servers_limits(tmp_path):
    """MPEG-PS (.mpg, .vob) lists its streams only by probing them, and FFmpeg takes no decoder options per stream
    for it: a server's upload of one was an internal error. It opens, and its frames' size is still checked."""
    from exprclone.io.video import Limits

    path = tmp_path / "clip.mpg"
    with av.open(str(path), "w", format="mpeg") as container:
        stream = container.add_stream("mpeg1video", rate=25)
        stream.width, stream.height, stream.pix_fmt = 64, 48, "yuv420p"
        for k in range(10):
            frame = av.VideoFrame.from_ndarray(np.full((48, 64, 3), 20 * k, np.uint8), format="rgb24")
            container.mux(stream.encode(frame))
        container.mux(stream.encode(None))
    info = probe(path, Limits(max_pixels=25_000_000, max_seconds=120))
    assert (info.width, info.height) == (64, 48)
    assert len(list(read_frames(path, limits=Limits(max_pixels=25_000_000, max_seconds=120)))) == 10
    with pytest.raises(ExprCloneError, match="too large"):
        probe(path, Limits(max_pixels=1000, max_seconds=120))
