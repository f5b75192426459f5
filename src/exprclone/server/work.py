"""The server's CPU work, run in worker processes that load the models once: the server's own, or a Dask cluster's
(``serve --scheduler``, :mod:`exprclone.server.runtime.cluster`).

Each function takes small, picklable arguments (the uploaded bytes and the options) and
returns encoded results, so that only files cross between the web process and its
workers. A driving video is a file in a job's folder for the server's own workers, and
its bytes for a cluster's (:func:`probe_sent`, :func:`video_sent`), whose workers cannot
read the web process's files. A worker remembers the landmarks of the photos it has
seen, by the SHA-256 of their bytes and the landmarker: a portrait sent again with
another expression is not detected again.
"""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
import warnings
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np

from .. import drive
from ..drive import Recording
from ..drive.framing import resize_portrait, side_by_side
from ..errors import ExprCloneError, naming
from ..evaluation.figures import draw, figure_request
from ..expressions.editor import Editor
from ..geometry.eigenface import default_eigenfaces
from ..io import video as video_io
from ..io.images import atomic_write, encode_image
from ..io.inputs import Seen, Source, gather, placed
from ..io.record import json_number, result_record
from ..io.video import Limits, probe, read_frames
from ..landmarks.backends import default_detector
from ..options import Driving, Framing, Options
from ..pipeline import request as door
from ..pipeline.cloner import Prepared
from ..pipeline.group import Group, choose
from ..pipeline.request import Request
from ..roles import SOURCE_EXPRESSION, SOURCE_NEUTRAL, TARGET_NEUTRAL

#: frames between two updates of a video job's progress file.
PROGRESS_EVERY = 5

#: what a worker remembers of the photos it has seen (:class:`exprclone.io.inputs.Seen`): their landmarks, by their bytes.
_seen = Seen()


@dataclass(frozen=True)
class CloneRequest:
    """What ``POST /api/clone`` and ``/api/compare`` ask: three photos (or with a built-in ``expression``, the
    target's alone: the others None), optional landmark files, the options.

    ``options`` are checked but for the given GI, which comes as a file (``global_landmarks``);
    ``figure`` is the compare sheet's, ``given`` the options the form gave (Fig. 19 shows the
    RBF transfer unless a global warp was given); ``max_faces`` the most faces of the target photo it may clone
    (:func:`check_faces`).
    """

    photos: tuple[Source | None, Source | None, Source]
    landmarks: tuple[Source | None, Source | None, Source | None]
    options: Options
    max_pixels: int | None
    global_landmarks: Source | None
    figure: str
    given: frozenset[str]
    expression: str | None
    max_faces: int | None = None


@dataclass(frozen=True)
class VideoRequest:
    """What ``POST /api/video`` asks: a portrait, how to clone each frame (:class:`~exprclone.options.Options`), drive
    the portrait (:class:`~exprclone.options.Driving`) and frame the output (:class:`~exprclone.options.Framing`), and
    the bounds on its driving video's frames."""

    portrait: Source
    options: Options
    driving: Driving
    framing: Framing
    limits: Limits


@dataclass(frozen=True)
class Clip:
    """A job's driving video where its worker reads it, its frame rate (:func:`probe_video`), and where the MP4 goes."""

    video: str
    fps: Fraction
    output: str


#: how a video job's worker reports its progress: ``report(done, total)`` frames.
Report = Callable[[int, int], None]


@dataclass(frozen=True)
class ProgressFile:
    """A job's progress in a file the web process reads: ``{"done", "total"}`` frames (the server's own video pool)."""

    path: str

    def __call__(self, done: int, total: int) -> None:
        report = json.dumps({"done": done, "total": total}).encode()
        atomic_write(self.path, lambda out: out.write(report))


def load_models() -> None:
    """A worker's initializer: load the default landmarker and the eigenface basis now, not on its first request."""
    default_detector()._load()
    default_eigenfaces()
    warnings.simplefilter("ignore")  # an odd photo's conversion is not the API's business


def ready() -> int:
    """A task that returns at once: sent to every worker at start-up, so that all exist and have loaded."""
    return os.getpid()


def faces(upload: Source, max_pixels: int | None, landmarker: str) -> dict[str, Any]:
    """``POST /api/faces``: every face of a photo in reading order, ``{"width", "height", "faces": [{"number", "box",
    "problem"}, ...]}`` (``box`` as ``[left, top, right, bottom]``; ``problem`` empty for a face that can be cloned)."""
    photo = placed(upload, Options(landmarker=landmarker), _seen, max_pixels, every=True)
    assert photo.found is not None
    listed = [{"number": f.number, "box": [round(v, 1) for v in f.box], "problem": f.problem} for f in photo.found]
    return {"width": photo.image.shape[1], "height": photo.image.shape[0], "faces": listed}


def landmarks(upload: Source, max_pixels: int | None, landmarker: str) -> dict[str, Any]:
    """``POST /api/landmarks``: the landmarks of a photo placed by ``landmarker``, and its size, ``{"width", "height", "landmarks"}``."""
    photo = placed(upload, Options(landmarker=landmarker), _seen, max_pixels)
    assert photo.points is not None
    return {"width": photo.image.shape[1], "height": photo.image.shape[0], "landmarks": np.round(photo.points, 2).tolist()}


def _request(request: CloneRequest) -> Request:
    """The request's photos decoded (a built-in expression's loaded), their landmark files read, and the clone's options
    (the given GI read from its file): :func:`exprclone.io.inputs.gather`; the landmarks of photos sent without a file
    placed by the request's landmarker, or remembered from the last time they were sent; no more faces to clone than
    it may (:func:`check_faces`)."""
    asked = gather(
        request.photos,
        request.landmarks,
        request.options,
        expression=request.expression,
        global_landmarks=request.global_landmarks,
        max_pixels=request.max_pixels,
        seen=_seen,
    )
    check_faces(asked, request.max_faces)
    return asked


def check_faces(asked: Request, max_faces: int | None) -> None:
    """ExprCloneError about ``faces`` when ``asked`` would clone more than ``max_faces`` faces of its target photo (each
    face's clone takes the time and memory of a portrait's)."""
    found = asked.target.found
    if max_faces is None or asked.target.points is not None or not found:
        return
    chosen = len(choose(found, asked.options.faces))
    if chosen > max_faces:
        advice = "choose some by number (faces=1,3: POST /api/faces lists them)"
        raise ExprCloneError("faces", f"{chosen} faces of {TARGET_NEUTRAL} chosen; this server clones at most {max_faces}: {advice}")


def inputs_of(request: CloneRequest) -> dict[str, str]:
    """What each photo of the request was, for its record: the form field it came in, or the built-in expression."""
    parts = {SOURCE_NEUTRAL: "neutral", SOURCE_EXPRESSION: "expression", TARGET_NEUTRAL: ""}
    return {role: p.name if p is not None else f"expression {request.expression} ({parts[role]})" for role, p in zip(parts, request.photos)}


def clone(request: CloneRequest, extension: str = ".png") -> tuple[bytes, dict[str, Any]]:
    """``POST /api/clone``: the result encoded as a file of ``extension`` (PNG by default), and its JSON record
    (:func:`exprclone.io.record.result_record`)."""
    asked = _request(request)
    result = door.prepare(asked).render()[asked.options.method]
    record = result_record(replace(result, landmarker=_placed(request, asked.options)), inputs_of(request))
    return encode_image(result.image, extension), record


def _placed(request: CloneRequest, options: Options) -> str | None:
    """Which landmarker placed landmarks of the request's photos: its options', unless every photo sent came with its own."""
    sent = [given for photo, given in zip(request.photos, request.landmarks) if photo is not None]
    return str(options.landmarker) if any(given is None for given in sent) else None


def prepare_edit(request: CloneRequest, preview: int) -> tuple[Prepared | Group, Prepared | Group, dict[str, str], str | None]:
    """``POST /api/edits``: the clone prepared at the target photo's size and at ``preview`` pixels (its longest side),
    the second with the first's landmarks (scaled) and lambda_k, so that both show the same clone; what the photos were
    and which landmarker placed landmarks, for the records (:mod:`exprclone.server.edits`). A photo of several faces
    has no smaller preview (its small faces would be too small in it): both are the one at its size."""
    asked = _request(request)
    full = door.prepare(asked)
    options, target = asked.options, asked.target
    placed = _placed(request, options)
    if isinstance(full, Group) or preview >= max(target.image.shape[:2]):
        return full, full, inputs_of(request), placed
    lambda_k = full.lambda_k
    own = target.points if target.points is not None else target.found[0].points if target.found else None
    image, points = resize_portrait(target.image, own, preview)
    ratio = np.array(image.shape[1::-1]) / target.image.shape[1::-1]
    given = None if options.global_landmarks is None else options.global_landmarks * ratio
    small = replace(options, lambda_k=options.lambda_k if lambda_k is None else lambda_k, global_landmarks=given)
    smaller = door.photo(image, points, TARGET_NEUTRAL, options.landmarks_layout)
    shown = door.prepare(replace(asked, target=smaller, options=small, check_roles=False))  # (the full one's roles)
    return full, replace(shown, warnings=full.warnings), inputs_of(request), placed


def prepare_editor(request: CloneRequest, preview: int) -> tuple[Editor, Editor]:
    """``POST /api/editor``: the photo's expression editor (:class:`exprclone.expressions.editor.Editor`, the request's
    source the built-in expression it names), at the photo's size and at ``preview`` pixels (its longest side, with
    the first's landmarks scaled), so that both show the same edit."""
    asked = gather(request.photos, request.landmarks, request.options, expression=request.expression, max_pixels=request.max_pixels)
    full = Editor.of(asked)
    image = asked.target.image
    if preview >= max(image.shape[:2]):
        return full, full
    small, points = resize_portrait(image, full.neutral, preview)
    smaller = door.photo(small, points, TARGET_NEUTRAL, asked.options.landmarks_layout)
    return full, Editor.of(replace(asked, target=smaller))


def compare(request: CloneRequest, extension: str = ".png") -> bytes:
    """``POST /api/compare``: the sheet of Figs. 11-13 (by the paper's stages, and this project's default with
    ``retarget``), or of Figs. 16-17 or 19-21, encoded as a file of ``extension`` (as ``exprclone compare --figure`` draws
    them)."""
    asked = _request(request)
    runs = figure_request(request.figure, asked.options, "global_warp" in request.given)
    results = [door.prepare(replace(asked, options=run.options), run.methods).render() for run in runs]
    return encode_image(draw(request.figure, results, [p.image for p in asked.photos]), extension)


def probe_video(path: str, limits: Limits) -> Fraction:
    """A driving video checked before its job starts, in a worker (inside the server's bounds on work): a video, its
    frames within ``limits`` as its headers give them (:func:`exprclone.io.video.probe`); its frame rate."""
    with naming({path: "driving_video"}):
        return probe(path, limits).fps


def video(request: VideoRequest, clip: Clip, report: Report) -> dict[str, Any]:
    """``POST /api/video``: the portrait driven by the clip, written to ``clip.output``, its progress reported.

    Returns
    -------
    dict
        ``frames`` written, the ``lambda_k`` used, the ``neutral_frame`` and the ``frames_without_face``.
    """
    with naming({clip.video: "driving_video", clip.output: "result"}):
        portrait, _ = resize_portrait(request.portrait.image(request.limits.max_pixels), None, request.framing.size)
        recording = drive.prepare(
            portrait, None, lambda: opened(request, clip), float(clip.fps), options=request.options, driving=request.driving
        )
        frames = _reporting(recording, opened(request, clip), request, report)
        written = video_io.write_video(clip.output, frames, clip.fps, audio_from=clip.video)
    return {
        "frames": written,
        "lambda_k": json_number(recording.driver.lambda_k),
        "neutral_frame": recording.neutral_index,
        "frames_without_face": int((~recording.track.found).sum()),
    }


def opened(request: VideoRequest, clip: Clip) -> Iterator[np.ndarray]:
    """A new pass over a job's driving video, within its limits."""
    return read_frames(clip.video, request.limits)


def _reporting(recording: Recording, frames: Iterator[np.ndarray], request: VideoRequest, report: Report) -> Iterator[np.ndarray]:
    """The rendered frames, the progress reported every :data:`PROGRESS_EVERY` of them."""
    total = len(recording.points)
    for done, f in enumerate(recording.frames(frames), 1):
        if done % PROGRESS_EVERY == 0 or done == total:
            report(done, total)
        yield side_by_side(f.driving, f.image) if request.framing.side_by_side else f.image


@contextlib.contextmanager
def _received(content: bytes) -> Iterator[Path]:
    """``content`` saved in a folder of this worker's own, as ``driving``: a driving video sent as bytes (a worker on a
    cluster cannot read the web process's files); the folder is removed after."""
    with tempfile.TemporaryDirectory(prefix="exprclone-job-") as folder:
        path = Path(folder) / "driving"
        path.write_bytes(content)
        yield path


def probe_sent(content: bytes, limits: Limits) -> Fraction:
    """:func:`probe_video` of a driving video sent as bytes (on a Dask cluster)."""
    with _received(content) as path:
        return probe_video(str(path), limits)


def video_sent(request: VideoRequest, content: bytes, fps: Fraction, report: Report) -> tuple[dict[str, Any], bytes]:
    """:func:`video` of a driving video sent as bytes (on a Dask cluster): what it returns, and the MP4's bytes."""
    with _received(content) as path:
        clip = Clip(str(path), fps, str(path.with_name("result.mp4")))
        info = video(request, clip, report)
        return info, Path(clip.output).read_bytes()
