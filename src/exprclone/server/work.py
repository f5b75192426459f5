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
import hashlib
import json
import os
import tempfile
import warnings
from collections import OrderedDict
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace
from fractions import Fraction
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np

from ..errors import naming
from ..io.record import json_number
from ..io.video import Limits
from ..options import Driving, Framing, Options
from ..roles import SOURCE_EXPRESSION, SOURCE_NEUTRAL, TARGET_NEUTRAL

if TYPE_CHECKING:
    from ..drive import Recording
    from ..pipeline.cloner import Prepared
    from ..pipeline.group import Found, Group

#: photos whose landmarks a worker remembers.
LANDMARK_CACHE = 256
#: frames between two updates of a video job's progress file.
PROGRESS_EVERY = 5

T = TypeVar("T")

#: what a worker remembers of the photos it has seen, by their bytes' SHA-256, the landmarker and what was found.
_seen: OrderedDict[tuple[str, str, str], Any] = OrderedDict()


@dataclass(frozen=True)
class Upload:
    """An uploaded file: the form field it came in (which names it in errors), its content, and for a
    landmark file the extension the client gave it (the only part of a client's file name that is used)."""

    field: str
    content: bytes
    extension: str = ""


@dataclass(frozen=True)
class CloneRequest:
    """What ``POST /api/clone`` and ``/api/compare`` ask: three photos (or with a built-in ``expression``, the
    target's alone: the others None), optional landmark files, the options.

    ``options`` are checked but for the given GI, which comes as a file (``global_landmarks``);
    ``figure`` is the compare sheet's, ``given`` the options the form gave (Fig. 19 shows the
    RBF transfer unless a global warp was given).
    """

    photos: tuple[Upload | None, Upload | None, Upload]
    landmarks: tuple[Upload | None, Upload | None, Upload | None]
    options: Options
    max_pixels: int | None
    global_landmarks: Upload | None
    figure: str
    given: frozenset[str]
    expression: str | None


@dataclass(frozen=True)
class VideoRequest:
    """What ``POST /api/video`` asks: a portrait, how to clone each frame (:class:`~exprclone.options.Options`), drive
    the portrait (:class:`~exprclone.options.Driving`) and frame the output (:class:`~exprclone.options.Framing`), and
    the bounds on its driving video's frames."""

    portrait: Upload
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
        from ..io.images import atomic_write

        report = json.dumps({"done": done, "total": total}).encode()
        atomic_write(self.path, lambda out: out.write(report))


def load_models() -> None:
    """A worker's initializer: load the default landmarker and the eigenface basis now, not on its first request."""
    from ..geometry.eigenface import default_eigenfaces
    from ..landmarks.backends import default_detector

    default_detector()._load()
    default_eigenfaces()
    warnings.simplefilter("ignore")  # an odd photo's conversion is not the API's business


def ready() -> int:
    """A task that returns at once: sent to every worker at start-up, so that all exist and have loaded."""
    return os.getpid()


def _image(upload: Upload, max_pixels: int | None) -> np.ndarray:
    from ..io.images import load_image

    return load_image(upload.content, name=upload.field, max_pixels=max_pixels)


def _remembered(upload: Upload, landmarker: str, kind: str, find: Callable[[], T]) -> T:
    """What ``find`` finds of an uploaded photo by ``landmarker`` (its ``kind``: one face's landmarks, or every face):
    remembered by the photo's bytes, or found (and remembered)."""
    key = (hashlib.sha256(upload.content).hexdigest(), landmarker, kind)
    if key in _seen:
        _seen.move_to_end(key)
    else:
        _seen[key] = find()
        if len(_seen) > LANDMARK_CACHE:
            _seen.popitem(last=False)
    found: T = _seen[key]
    return found


def _detected(upload: Upload, image: np.ndarray, landmarker: str) -> np.ndarray:
    """The landmarks of the face of an uploaded photo placed by ``landmarker`` (its largest: :meth:`detect`)."""
    from ..landmarks.backends import shared

    return _remembered(upload, landmarker, "face", lambda: shared(landmarker).detect(image, upload.field))


def _found(upload: Upload, image: np.ndarray, landmarker: str) -> tuple[Found, ...]:
    """Every face of an uploaded photo, its landmarks placed by ``landmarker`` (:func:`exprclone.pipeline.group.find`)."""
    from ..landmarks.backends import shared
    from ..landmarks.layout import DLIB68
    from ..pipeline import group

    return _remembered(upload, landmarker, "faces", lambda: group.find(image, shared(landmarker), upload.field, DLIB68))


def faces(upload: Upload, max_pixels: int | None, landmarker: str) -> dict[str, Any]:
    """``POST /api/faces``: every face of a photo in reading order, ``{"width", "height", "faces": [{"number", "box",
    "problem"}, ...]}`` (``box`` as ``[left, top, right, bottom]``; ``problem`` empty for a face that can be cloned)."""
    image = _image(upload, max_pixels)
    found = _found(upload, image, landmarker)
    listed = [{"number": f.number, "box": [round(v, 1) for v in f.box], "problem": f.problem} for f in found]
    return {"width": image.shape[1], "height": image.shape[0], "faces": listed}


def landmarks(upload: Upload, max_pixels: int | None, landmarker: str) -> dict[str, Any]:
    """``POST /api/landmarks``: the landmarks of a photo placed by ``landmarker``, and its size, ``{"width", "height", "landmarks"}``."""
    image = _image(upload, max_pixels)
    points = _detected(upload, image, landmarker)
    return {"width": image.shape[1], "height": image.shape[0], "landmarks": np.round(points, 2).tolist()}


def _landmark_file(upload: Upload, shape: tuple[int, ...]) -> np.ndarray:
    """The landmarks of an uploaded landmark file, for a photo of ``shape``."""
    from ..io.landmarks import parse_landmarks

    return parse_landmarks(upload.content.decode("utf-8-sig", errors="replace"), upload.extension, shape, name=upload.field)


@dataclass(frozen=True)
class Inputs:
    """A request's photos decoded, their landmarks (the target's None when its faces are found instead), the clone's
    options (the given GI read from its file) and the target photo's faces (None with its landmark file)."""

    images: tuple[np.ndarray, np.ndarray, np.ndarray]
    points: tuple[np.ndarray, np.ndarray, np.ndarray | None]
    options: Options
    faces: tuple[Found, ...] | None


def _inputs(request: CloneRequest) -> Inputs:
    """The three photos decoded (a built-in expression's loaded, :func:`exprclone.expressions.load`), their landmarks
    (the expression's, from the landmark file given, else placed by the request's landmarker: every face of the
    target's), and the clone's options."""
    landmarker = str(request.options.landmarker)
    sent = [(photo, given) for photo, given in zip(request.photos, request.landmarks) if photo is not None]
    sources = [_face(photo, given, request.max_pixels, landmarker) for photo, given in sent[:-1]]
    if request.expression is not None:
        from ..expressions import load

        chosen = load(request.expression)
        sources = [(chosen.neutral.image, chosen.neutral.points), (chosen.expression.image, chosen.expression.points)]
    (sn, sn_points), (se, se_points) = sources
    photo, given = sent[-1]
    tn = _image(photo, request.max_pixels)
    found = _found(photo, tn, landmarker) if given is None else None
    tn_points = None if given is None else _landmark_file(given, tn.shape)
    options = request.options
    if request.global_landmarks is not None:
        options = replace(options, global_landmarks=_landmark_file(request.global_landmarks, tn.shape))
    return Inputs((sn, se, tn), (sn_points, se_points, tn_points), options, found)


def _face(photo: Upload, given: Upload | None, max_pixels: int | None, landmarker: str) -> tuple[np.ndarray, np.ndarray]:
    """An uploaded photo decoded, and its landmarks: from the landmark file given, else placed by ``landmarker`` (or remembered)."""
    image = _image(photo, max_pixels)
    return image, _detected(photo, image, landmarker) if given is None else _landmark_file(given, image.shape)


def inputs_of(request: CloneRequest) -> dict[str, str]:
    """What each photo of the request was, for its record: the form field it came in, or the built-in expression."""
    parts = {SOURCE_NEUTRAL: "neutral", SOURCE_EXPRESSION: "expression", TARGET_NEUTRAL: ""}
    return {
        role: p.field if p is not None else f"expression {request.expression} ({parts[role]})" for role, p in zip(parts, request.photos)
    }


def clone(request: CloneRequest, extension: str = ".png") -> tuple[bytes, dict[str, Any]]:
    """``POST /api/clone``: the result encoded as a file of ``extension`` (PNG by default), and its JSON record
    (:func:`exprclone.io.record.result_record`)."""
    from ..io.images import encode_image
    from ..io.record import result_record
    from ..pipeline.clone import clone as clone_photos

    asked = _inputs(request)
    result = clone_photos(*asked.images, landmarks=asked.points, options=asked.options, target_faces=asked.faces)
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
    from ..drive.framing import resize_portrait
    from ..pipeline.clone import prepare
    from ..pipeline.group import Group

    asked = _inputs(request)
    images, points, options = asked.images, asked.points, asked.options
    full = prepare(*images, landmarks=points, options=options, target_faces=asked.faces)
    placed = _placed(request, options)
    if isinstance(full, Group) or preview >= max(images[2].shape[:2]):
        return full, full, inputs_of(request), placed
    lambda_k = full.lambda_k
    own = points[2] if points[2] is not None else asked.faces[0].points if asked.faces else None
    target, target_points = resize_portrait(images[2], own, preview)
    ratio = np.array(target.shape[1::-1]) / images[2].shape[1::-1]
    given = None if options.global_landmarks is None else options.global_landmarks * ratio
    small = replace(options, lambda_k=options.lambda_k if lambda_k is None else lambda_k, global_landmarks=given)
    shown = prepare(images[0], images[1], target, landmarks=(points[0], points[1], target_points), options=small)
    return full, shown, inputs_of(request), placed


def compare(request: CloneRequest, extension: str = ".png") -> bytes:
    """``POST /api/compare``: the sheet of Figs. 11-13, or of Figs. 19-21, encoded as a file of ``extension`` (as
    ``exprclone compare --figure`` draws them)."""
    from ..evaluation.figures import draw, figure_request
    from ..io.images import encode_image
    from ..pipeline.clone import clone_methods

    asked = _inputs(request)
    methods, options = figure_request(request.figure, asked.options, "global_warp" in request.given)
    results = clone_methods(*asked.images, methods, landmarks=asked.points, options=options, target_faces=asked.faces)
    return encode_image(draw(request.figure, results, asked.images), extension)


def probe_video(path: str, limits: Limits) -> Fraction:
    """A driving video checked before its job starts, in a worker (inside the server's bounds on work): a video, its
    frames within ``limits`` as its headers give them (:func:`exprclone.io.video.probe`); its frame rate."""
    from ..io.video import probe

    with naming({path: "driving_video"}):
        return probe(path, limits).fps


def video(request: VideoRequest, clip: Clip, report: Report) -> dict[str, Any]:
    """``POST /api/video``: the portrait driven by the clip, written to ``clip.output``, its progress reported.

    Returns
    -------
    dict
        ``frames`` written, the ``lambda_k`` used, the ``neutral_frame`` and the ``frames_without_face``.
    """
    from .. import drive
    from ..drive.framing import resize_portrait
    from ..io import video as video_io

    with naming({clip.video: "driving_video", clip.output: "result"}):
        portrait, _ = resize_portrait(_image(request.portrait, request.limits.max_pixels), None, request.framing.size)
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
    from ..io.video import read_frames

    return read_frames(clip.video, request.limits)


def _reporting(recording: Recording, frames: Iterator[np.ndarray], request: VideoRequest, report: Report) -> Iterator[np.ndarray]:
    """The rendered frames, the progress reported every :data:`PROGRESS_EVERY` of them."""
    from ..drive.framing import side_by_side

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
