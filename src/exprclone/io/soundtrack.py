"""A video's sound carried into another video: re-encoded as AAC, in step with the frames written there
(:func:`exprclone.io.video.write_video`'s ``audio_from``)."""

from __future__ import annotations

from fractions import Fraction

import av
import numpy as np

from ..errors import ExprCloneError
from .images import PathLike

AUDIO_BIT_RATE = 128_000
"""AAC bit rate, in bits per second."""

_AAC = av.Codec("aac", "w")


class Soundtrack:
    """The sound of a video, re-encoded as AAC into an output in step with the frames written there.

    Sample ``n`` of the output is the source's sound at ``n / rate`` seconds after the start of the
    source's video stream (silence before the source's sound starts).

    Parameters
    ----------
    path : str or os.PathLike
        The source, for error messages.
    source : av.container.InputContainer
        The source opened, with an audio stream.
    output : av.container.OutputContainer
        Where to add the AAC stream and write its packets.
    """

    def __init__(self, path: PathLike, source: av.container.InputContainer, output: av.container.OutputContainer) -> None:
        audio = source.streams.audio[0]
        rate = audio.codec_context.sample_rate
        self.rate = rate if rate in (_AAC.audio_rates or ()) else 48_000
        self.layout = "mono" if audio.codec_context.channels == 1 else "stereo"
        self.stream = output.add_stream("aac", rate=self.rate, layout=self.layout)
        self.stream.bit_rate = AUDIO_BIT_RATE
        self.output = output
        self.path = path
        video = source.streams.video[0]
        self.start = Fraction(video.start_time or 0) * time_base(video.time_base, path)
        self.decoded = source.decode(audio)
        self.resampler = av.AudioResampler(format="fltp", layout=self.layout, rate=self.rate)
        self.fifo = av.AudioFifo()
        self.to_skip: int | None = None  # samples before the video's start, once the first is decoded
        self.written = 0

    def write_until(self, seconds: Fraction) -> None:
        """Encode the sound up to ``seconds`` into the video (less if the source's sound ends first)."""
        end = round(seconds * self.rate)
        while self.written + self.fifo.samples < end and self._decode_more():
            pass
        samples = min(end - self.written, self.fifo.samples)
        if samples > 0:
            frame = self.fifo.read(samples)  # PyAV re-cuts it into the encoder's frame size
            if frame is None:  # not reached: the FIFO holds at least ``samples``
                return
            frame.pts, frame.time_base = self.written, Fraction(1, self.rate)
            self.output.mux(self.stream.encode(frame))
            self.written += samples

    def finish(self) -> None:
        """Flush the encoder."""
        self.output.mux(self.stream.encode())

    def _decode_more(self) -> bool:
        """Move the next decoded frame of sound into the FIFO, aligned to the video; False at the end."""
        try:
            decoded = next(self.decoded, None)
        except av.FFmpegError as exc:
            raise ExprCloneError(self.path, f"audio data is corrupt ({exc.strerror})") from exc
        if self.to_skip is None and decoded is not None and decoded.pts is not None:
            lead = round((decoded.pts * time_base(decoded.time_base, self.path) - self.start) * self.rate)
            if lead > 0:
                silence = av.AudioFrame.from_ndarray(
                    np.zeros((self.stream.codec_context.channels, lead), np.float32), format="fltp", layout=self.layout
                )
                silence.sample_rate = self.rate
                self.fifo.write(silence)
            self.to_skip = max(0, -lead)
        for frame in self.resampler.resample(decoded):
            frame.pts = None  # the FIFO would insist on gapless timestamps from 0
            self.fifo.write(frame)
            if self.to_skip:
                skipped = min(self.to_skip, self.fifo.samples)
                self.fifo.read(skipped)
                self.to_skip -= skipped
        return decoded is not None


def time_base(time_base: Fraction | None, path: PathLike) -> Fraction:
    """A stream's (or a frame's) time base: seconds per tick of its timestamps; FFmpeg gives every stream one."""
    if time_base is None:
        raise ExprCloneError(path, "a stream has no time base")
    return time_base
