"""Video files in and out, at the edge of the package.

A video is read as a stream of frames in exprclone's image convention: numpy arrays of shape
(H, W, 3), dtype uint8, RGB order. :func:`probe` reports what a file holds, :func:`read_frames`
decodes it frame by frame, and :func:`write_video` encodes frames as they come (from a lazy
generator, so a long video never sits in memory) into an H.264 file, optionally with the sound of
another video, atomically, so no half-written output ever exists. FFmpeg does the work, through
PyAV.

Colour: a decoded frame is converted to RGB by the YUV matrix and range its tags name (BT.601 and
limited range if untagged, as FFmpeg assumes); written frames are converted by BT.709, limited
range, and tagged so, which players honour.

Orientation: a phone stores a video filmed upright as its sensor sees it, turned a quarter, with a
display matrix that players turn it back by; each frame is read turned as players show it (its
rotation by quarter turns; a matrix's mirroring, rare, is not undone). :func:`probe` gives the
size as stored.
"""

from __future__ import annotations

import contextlib
import itertools
import math
import os
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from fractions import Fraction
from typing import IO, Any

import av
import numpy as np
from av.video.reformatter import ColorRange, Colorspace

from ..errors import ExprCloneError
from .images import PathLike, atomic_write, check_file, check_output_path, check_size
from .soundtrack import Soundtrack

CRF = 18
"""x264 constant rate factor: 18 is close to visually lossless; each +6 halves the size."""

PRESET = "veryfast"
"""x264 speed preset."""

_MUXERS: dict[str, tuple[str, dict[str, str]]] = {
    ".mp4": ("mp4", {"movflags": "+faststart"}),  # index first, so that a browser can start playing at once
    ".mov": ("mov", {"movflags": "+faststart"}),
    ".mkv": ("matroska", {}),
}
#: file extensions a video can be written as.
EXTENSIONS = tuple(_MUXERS)
_STILL_IMAGE_FORMATS = ("image2", "image2pipe")  # FFmpeg also reads photos, as one-frame videos
# The colour tags (FFmpeg's AVCOL_* codes) written: BT.709 matrix, primaries and transfer, limited
# range, as we convert RGB to YUV; players then convert back as we converted.
_COLOR_TAGS = {"colorspace": 1, "color_primaries": 1, "color_trc": 1, "color_range": ColorRange.MPEG}
# The YUV -> RGB matrix for each colorspace tag (AVCOL_SPC_*) a decoded frame may carry; any other
# (unspecified; BT.2020, which is HDR and would need tone mapping anyway) gets swscale's default,
# BT.601. PyAV before 18 ignores the tags unless told.
_MATRICES = {1: Colorspace.ITU709, 4: Colorspace.FCC, 5: Colorspace.ITU601, 6: Colorspace.SMPTE170M, 7: Colorspace.SMPTE240M}


#: the streams of a file whose probe is bounded (:attr:`Limits.max_pixels`): more than any video a user sends has.
PROBED_STREAMS = 16
#: the highest frame rate a bounded video's length is counted at (:attr:`Limits.max_seconds`): headers may claim any.
MAX_FPS = 60.0


@dataclass(frozen=True)
class Limits:
    """Bounds on a video from outside (a server's upload): its frames' pixels, and how long it runs.

    Attributes
    ----------
    max_pixels : int or None
        The most pixels a frame may have, as photos' are bounded (:func:`exprclone.io.images.check_size`).
    max_seconds : float or None
        The longest it may run: its headers' duration, and the frames decoded at its frame rate (at most
        :data:`MAX_FPS`, whatever the headers say).
    """

    max_pixels: int | None = None
    max_seconds: float | None = None

    def max_frames(self, fps: Fraction) -> int | None:
        """The most frames a video of ``fps`` may have."""
        return None if self.max_seconds is None else math.ceil(self.max_seconds * min(float(fps), MAX_FPS))

    def decoder(self) -> dict[str, str]:
        """FFmpeg's decoder options that refuse a frame over :attr:`max_pixels` before allocating it."""
        return {"max_pixels": str(self.max_pixels)}

    def check_frame(self, path: PathLike, count: int, width: int, height: int, fps: Fraction) -> None:
        """ExprCloneError about ``path`` if its ``count``-th frame (from 1), of ``width`` by ``height``, is over a limit."""
        most = self.max_frames(fps)
        if most is not None and count > most:
            raise ExprCloneError(path, f"is too long (more than {self.max_seconds:g} s: {most} frames)")
        if self.max_pixels is not None:
            check_size(width, height, f"{os.fspath(path)} (frame {count - 1})", self.max_pixels)


@dataclass(frozen=True)
class VideoInfo:
    """What :func:`probe` found in a video file.

    Attributes
    ----------
    path : str
        The file.
    width, height : int
        Frame size in pixels, as stored (:func:`read_frames` turns a phone's frames upright: see the module's notes).
    fps : fractions.Fraction
        Frame rate of the video stream (its average rate, else FFmpeg's guess, else its base rate).
    frames : int
        Number of frames: as the container records it, else estimated from the duration and
        ``fps``; 0 if unknown.
    has_audio : bool
        Whether the file has an audio stream.
    """

    path: str
    width: int
    height: int
    fps: Fraction
    frames: int
    has_audio: bool


def probe(path: PathLike, limits: Limits | None = None) -> VideoInfo:
    """Describe the video in ``path`` without decoding it.

    Parameters
    ----------
    path : str or os.PathLike
        A video file in any format FFmpeg reads.
    limits : Limits, optional
        Refuse, from its headers, frames larger than ``limits.max_pixels`` (FFmpeg's probe
        decodes no frame larger either) and a video longer than ``limits.max_seconds``.

    Returns
    -------
    VideoInfo
        Size, frame rate, frame count and whether there is sound.

    Raises
    ------
    ExprCloneError
        If the file is missing or unreadable, not a video, has no video stream or no frame rate.

    Examples
    --------
    >>> probe("missing.mp4")
    Traceback (most recent call last):
    ...
    exprclone.errors.ExprCloneError: missing.mp4: no such file
    """
    with _open_input(path, limits) as container:
        stream = container.streams.video[0]
        fps = _frame_rate(path, stream)
        info = VideoInfo(
            path=os.fspath(path),
            width=stream.codec_context.width,
            height=stream.codec_context.height,
            fps=fps,
            frames=stream.frames or _estimated_frames(container, stream, fps),
            has_audio=bool(container.streams.audio),
        )
    most = None if limits is None else limits.max_frames(fps)
    if limits is not None and most is not None and info.frames > most:
        raise ExprCloneError(path, f"is too long ({info.frames} frames; at most {limits.max_seconds:g} s: {most} frames)")
    return info


def read_frames(path: PathLike, limits: Limits | None = None) -> Iterator[np.ndarray]:
    """Decode every frame of the video in ``path``, in order.

    The file is opened (and checked) at the call; the frames are decoded one at a time as the
    iterator is consumed.

    Parameters
    ----------
    path : str or os.PathLike
        A video file in any format FFmpeg reads.
    limits : Limits, optional
        As for :func:`probe`, and checked on every frame as it is decoded: the decoder refuses a
        frame larger than ``limits.max_pixels`` before it holds its pixels (a later frame may be
        larger than the first), and the frames stop with an error past ``limits.max_seconds``.

    Returns
    -------
    iterator of numpy.ndarray
        Each frame as a C-contiguous array of shape (H, W, 3), dtype uint8, RGB order, upright as a player shows it
        (see the module's notes).

    Raises
    ------
    ExprCloneError
        At the call, as :func:`probe`; while iterating, if the video data cannot be decoded.
    """
    container = _open_input(path, limits)
    return _decode(path, container, limits)


def write_video(
    path: PathLike,
    frames: Iterable[np.ndarray],
    fps: Fraction,
    audio_from: PathLike | None = None,
    *,
    inputs: Iterable[PathLike] = (),
) -> int:
    """Encode frames as an H.264 video, with the sound of another video if asked, atomically.

    The frames are consumed one at a time (``frames`` may be a slow, lazy generator) and encoded
    with libx264 (yuv420p, ``CRF``, ``PRESET``, tagged BT.709). yuv420p needs an even width and
    height: an odd one is padded by one row or column repeating the last. If ``audio_from`` has
    sound, it is re-encoded as AAC (mono or stereo), cut or padded with silence at the start so
    that it keeps its timing relative to that video's first frame, and cut to the duration of the
    new video, so that frames taken from ``audio_from`` play in sync with their sound.

    The file is written through :func:`~exprclone.io.images.atomic_write`: if ``frames`` raises (or
    the user interrupts), or encoding fails, nothing is left at ``path`` and no temporary file
    stays behind.

    Parameters
    ----------
    path : str or os.PathLike
        The output file: .mp4, .mov or .mkv.
    frames : iterable of numpy.ndarray
        uint8 arrays of shape (H, W, 3), RGB order, all of one size.
    fps : fractions.Fraction
        Frame rate of the output, such as ``probe(source).fps``.
    audio_from : str or os.PathLike, optional
        A video whose sound to carry over; if it has none, the output is silent.
    inputs : iterable of str or os.PathLike
        Input files that the output must not overwrite (``audio_from`` is always one).

    Returns
    -------
    int
        The number of frames written.

    Raises
    ------
    ExprCloneError
        If :func:`~exprclone.io.images.check_output_path` rejects ``path`` (checked before any frame
        is asked for), ``audio_from`` is not a readable video, ``frames`` is empty, or the file
        cannot be written; also if ``fps`` is not positive, or a frame is not a uint8
        (H, W, 3) array of the first frame's size.
    """
    sources = [*inputs, audio_from] if audio_from is not None else list(inputs)
    check_output_path(path, sources, extensions=_MUXERS)
    fps = Fraction(fps)
    if fps <= 0:
        raise ExprCloneError("fps", f"must be positive, got {fps}")
    sound = audio_from is not None and probe(audio_from).has_audio
    iterator = iter(frames)
    first = next(iterator, None)
    if first is None:
        raise ExprCloneError(path, "no frames to write")
    shape = _check_frame(first)
    muxer, options = _MUXERS[os.path.splitext(path)[1].lower()]
    count = 0

    def write(file: IO[bytes]) -> None:
        nonlocal count
        checked = _checked(itertools.chain([first], iterator), shape)
        try:
            with av.open(file, "w", format=muxer, options=options) as output:
                count = _encode(output, shape, checked, fps, audio_from if sound else None)
        except av.FFmpegError as exc:
            raise ExprCloneError(path, f"cannot be written ({exc})") from exc

    try:
        atomic_write(path, write)
    except _FrameError as carrier:
        error = carrier.error
    else:
        return count
    raise error  # outside the except clause, so that it comes out as it was raised


class _FrameError(Exception):
    """Carries an error raised by the frames, or by checking one, through ``atomic_write``.

    ``atomic_write`` removes its temporary file on any error, and would report a ValueError (an ExprCloneError too) or
    OSError as "cannot be written"; :func:`write_video` re-raises the carried error instead.
    """

    def __init__(self, error: Exception) -> None:
        super().__init__(error)
        self.error = error


def _checked(frames: Iterator[np.ndarray], shape: tuple[int, ...]) -> Iterator[np.ndarray]:
    """Check that each of ``frames`` has ``shape``; an error raised in ``frames`` or by the check comes out as a :class:`_FrameError`."""
    try:
        for frame in frames:
            _check_frame(frame, shape)
            yield frame
    except Exception as exc:
        raise _FrameError(exc) from exc


def _check_frame(frame: object, shape: tuple[int, ...] | None = None) -> tuple[int, ...]:
    """Raise ExprCloneError unless ``frame`` is a uint8 (H, W, 3) array (of ``shape`` if given); return its shape."""
    if not isinstance(frame, np.ndarray) or frame.dtype != np.uint8 or frame.ndim != 3 or frame.shape[2] != 3:
        described = f"{frame.dtype} array of shape {frame.shape}" if isinstance(frame, np.ndarray) else type(frame).__name__
        raise ExprCloneError("frame", f"expected a uint8 (H, W, 3) frame, got {described}")
    if shape is not None and frame.shape != shape:
        raise ExprCloneError("frame", f"all frames must have one size: expected {shape}, got {frame.shape}")
    return frame.shape


def _encode(
    output: av.container.OutputContainer, shape: tuple[int, ...], frames: Iterator[np.ndarray], fps: Fraction, audio_from: PathLike | None
) -> int:
    """Encode ``frames`` of ``shape`` (and the sound of ``audio_from``) into ``output``; return the frame count."""
    with contextlib.ExitStack() as stack:
        video = output.add_stream("libx264", rate=fps, options={"crf": str(CRF), "preset": PRESET})
        video.height, video.width = shape[0] + shape[0] % 2, shape[1] + shape[1] % 2
        video.pix_fmt = "yuv420p"
        for tag, value in _COLOR_TAGS.items():
            setattr(video.codec_context, tag, value)
        sound = Soundtrack(audio_from, stack.enter_context(_open_input(audio_from)), output) if audio_from is not None else None
        count = 0
        for frame in frames:
            picture = av.VideoFrame.from_ndarray(_even(frame), format="rgb24")
            picture = picture.reformat(format="yuv420p", dst_colorspace=Colorspace.ITU709, dst_color_range=ColorRange.MPEG)
            picture.pts = count
            output.mux(video.encode(picture))
            count += 1
            if sound is not None:
                sound.write_until(count / fps)
        output.mux(video.encode())
        if sound is not None:
            sound.finish()
    return count


def _even(frame: np.ndarray) -> np.ndarray:
    """Pad an odd height or width by one row or column repeating the last; (H, W, 3) -> (H', W', 3), C-contiguous."""
    height, width = frame.shape[:2]
    if height % 2 or width % 2:
        return np.pad(frame, ((0, height % 2), (0, width % 2), (0, 0)), mode="edge")
    return np.ascontiguousarray(frame)


def _open_input(path: PathLike, limits: Limits | None = None) -> av.container.InputContainer:
    """Open ``path`` for reading and check that it is a video with a video stream (of frames within ``limits``, read
    from its headers)."""
    check_file(path)
    # each stream's decoder options (PyAV's stubs say strings: typed Any here)
    bounded: dict[str, Any] = {} if limits is None or limits.max_pixels is None else {"stream_options": [limits.decoder()] * PROBED_STREAMS}
    try:
        try:
            container = av.open(os.fspath(path), **bounded)
        except ValueError:  # a format that lists its streams only by probing them (MPEG-PS) takes no options per stream:
            container = av.open(os.fspath(path))  # its frames' size is checked from the probed headers, below
    except FileNotFoundError as exc:
        raise ExprCloneError(path, "no such file") from exc
    except PermissionError as exc:
        raise ExprCloneError(path, "cannot be read (permission denied)") from exc
    except av.FFmpegError as exc:
        raise ExprCloneError(path, f"not a video, or damaged ({exc.strerror})") from exc
    if container.format.name in _STILL_IMAGE_FORMATS or container.format.name.endswith("_pipe"):
        container.close()
        raise ExprCloneError(path, "is a still image, not a video")
    if not container.streams.video:
        container.close()
        raise ExprCloneError(path, "has no video stream")
    if limits is not None and limits.max_pixels is not None:
        context = container.streams.video[0].codec_context
        try:
            if not context.width * context.height:
                raise ExprCloneError(
                    path, f"its frames are larger than {limits.max_pixels / 1e6:g} megapixels, or of no size its headers tell"
                )
            check_size(context.width, context.height, os.fspath(path), limits.max_pixels)
        except ExprCloneError:
            container.close()
            raise
    return container


def _decode(path: PathLike, container: av.container.InputContainer, limits: Limits | None = None) -> Iterator[np.ndarray]:
    """The frames of the first video stream of ``container`` as (H, W, 3) uint8 RGB arrays, within ``limits``; closes it
    at the end."""
    with container:
        stream = container.streams.video[0]
        stream.thread_type = "AUTO"
        if limits is not None and limits.max_pixels is not None:
            stream.codec_context.options = limits.decoder()  # FFmpeg refuses a larger frame before it allocates it
        fps = _frame_rate(path, stream)
        try:
            for count, frame in enumerate(container.decode(stream), 1):
                if limits is not None:
                    limits.check_frame(path, count, frame.width, frame.height, fps)
                matrix = _MATRICES.get(frame.colorspace, Colorspace.DEFAULT)
                # (PyAV 14 skips the conversion details when source and destination colorspace are equal.)
                rgb = frame.to_ndarray(
                    format="rgb24", src_colorspace=matrix, dst_colorspace=Colorspace.DEFAULT, src_color_range=frame.color_range
                )
                # to_ndarray returns a view of FFmpeg's row-padded buffer: give a C-contiguous copy of its own, upright
                yield np.ascontiguousarray(np.rot90(rgb, quarter_turns(frame.rotation)))
        except av.FFmpegError as exc:
            too_large = limits is not None and limits.max_pixels is not None
            raise ExprCloneError(
                path,
                f"video data is corrupt, or a frame is over its limit ({exc.strerror})"
                if too_large
                else f"video data is corrupt ({exc.strerror})",
            ) from exc


def quarter_turns(rotation: float) -> int:
    """How many counter-clockwise quarter turns (``np.rot90``'s ``k``) show a frame upright whose display matrix turns it
    by ``rotation`` degrees counter-clockwise (PyAV's ``VideoFrame.rotation``); 0 for an angle between quarters.

    >>> quarter_turns(0), quarter_turns(90), quarter_turns(-90), quarter_turns(180), quarter_turns(30)
    (0, 1, 3, 2, 0)
    """
    return int(rotation // 90 % 4) if rotation % 90 == 0 else 0


def _frame_rate(path: PathLike, stream: av.video.stream.VideoStream) -> Fraction:
    """The frame rate of ``stream``: average, else guessed, else base rate."""
    fps = stream.average_rate or stream.guessed_rate or stream.base_rate
    if not fps:
        raise ExprCloneError(path, "video has no frame rate")
    return Fraction(fps)


def _estimated_frames(container: av.container.InputContainer, stream: av.video.stream.VideoStream, fps: Fraction) -> int:
    """Frame count from the duration of ``stream`` (else of ``container``) times ``fps``, rounded; 0 if unknown."""
    if stream.duration is not None and stream.time_base is not None:
        seconds = stream.duration * stream.time_base
    elif container.duration is not None:
        seconds = Fraction(container.duration, av.time_base)
    else:
        return 0
    return math.floor(seconds * fps + Fraction(1, 2))
