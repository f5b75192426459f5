"""``exprclone study make``: a study folder (:mod:`.folder`) from a manifest of photo triples.

The manifest is a batch manifest (:mod:`exprclone.batch.manifest`) without its ``output``
column: ``source_neutral,source_expression,target_neutral``, paths relative to the
manifest's folder, with two optional columns: ``set``, the set's name in the results (the
paper's "Fig. 11"; its row number otherwise), and ``lambda``, the set's own lambda_k.

Each distinct photo is copied into the study as a PNG under a random id, made at most
``size`` pixels on its longest side, and each set is cloned from those copies by every
method, as a batch job (:func:`exprclone.batch.job.run`: each photo detected once, each
pair of faces prepared once, on local processes or a Dask cluster), each result under a
random id. The page thus shows exactly the pixels the methods were given, and a set's results
are files of one size (:func:`pad_alike`): how well a method's image compresses says nothing.

The folder is built beside its destination under a hidden name and renamed into place
once whole: a failure (a photo without a face, Ctrl-C) leaves nothing behind. An existing
study is replaced only when asked (``overwrite``), a folder that is not a study never.
"""

from __future__ import annotations

import datetime
import os
import secrets
import shutil
import zlib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import cv2

from .. import __version__
from ..batch import job
from ..batch.manifest import Row, photos_of, read_records
from ..batch.rows import Outcome
from ..errors import ExprCloneError
from ..io.images import load_image, save_image
from ..io.progress import Progress, Quiet
from ..methods import lookup
from ..options import Options
from ..roles import ROLES
from .folder import FORMAT, IMAGES, KEY, STUDY, SUFFIX, Set, Study, new_id, write_json

#: a PNG chunk's bytes beside its data (length, type, CRC), and the IEND chunk's, which ends every PNG file.
PAD_CHUNK, IEND = 12, 12
#: the smallest ``size`` allowed, in pixels (the face detector needs a face about 80 pixels wide).
MIN_SIZE = 128


@dataclass(frozen=True)
class Triple:
    """One set as the manifest gives it: its name, its three photos (in :data:`exprclone.roles.ROLES`' order), the
    texts of its own options (its ``lambda`` column, when not empty)."""

    name: str
    photos: tuple[str, str, str]
    cells: tuple[tuple[str, str], ...] = ()


def read_sets(path: str) -> list[Triple]:
    """The sets of a study's manifest (see the module's notes), or ExprCloneError about ``path``."""
    records = read_records(path, ROLES)
    sets = [
        Triple(r.get("set") or str(k), photos_of(r, path), (("lambda", r["lambda"]),) if r.get("lambda") else ())
        for k, r in enumerate(records, 1)
    ]
    if not sets:
        raise ExprCloneError(path, "no rows: a study needs at least one set")
    first: dict[str, int] = {}
    for k, triple in enumerate(sets, 1):
        try:
            Options.from_text(dict(triple.cells))
        except ExprCloneError as e:
            raise ExprCloneError(path, f"row {k}: {e}") from None
        if triple.name in first:
            raise ExprCloneError(path, f"rows {first[triple.name]} and {k} both name the set {triple.name!r}")
        first[triple.name] = k
    return sets


def check_destination(folder: Path, overwrite: bool) -> None:
    """ExprCloneError unless a study can be written at ``folder``: new, empty, or a study to replace with ``overwrite``."""
    if folder.is_dir():
        is_study = (folder / STUDY).is_file()
        if is_study and not overwrite:
            raise ExprCloneError(str(folder), "a study is there already; --overwrite replaces it (and its ratings)")
        if not is_study and any(folder.iterdir()):
            raise ExprCloneError(str(folder), "exists and is not a study folder; choose another")
    elif folder.exists():
        raise ExprCloneError(str(folder), "exists and is not a folder")
    elif not folder.parent.is_dir():
        raise ExprCloneError(str(folder), f"its folder {folder.parent} does not exist")
    if not os.access(folder.parent, os.W_OK | os.X_OK):
        raise ExprCloneError(str(folder), f"its folder {folder.parent} is not writable")


def make(
    manifest: str,
    folder: str | Path,
    methods: tuple[str, ...],
    options: Options,
    backend: job.Local | job.Dask,
    *,
    max_size: int | None = None,
    overwrite: bool = False,
    progress: Progress = Quiet,
) -> None:
    """Make the study of ``manifest``'s sets, cloned by ``methods``, in ``folder`` (see the module's notes).

    Parameters
    ----------
    manifest : str
        The manifest CSV.
    folder : str or Path
        Where the study goes.
    methods : tuple of str
        Names of :data:`exprclone.methods.METHODS`.
    options : Options
        The clone options (its ``method`` unused: every set is cloned by each of ``methods``).
    backend : exprclone.batch.job.Local or exprclone.batch.job.Dask
        Where the clones run.
    max_size : int, optional
        The photos' longest side at most, in pixels (not enlarged); as they are by default.
    overwrite : bool
        Replace a study already at ``folder``.
    progress : callable
        ``progress(total, what)``, as :func:`exprclone.batch.job.run` takes it.
    """
    methods = tuple(m.name for m in lookup(methods))
    if not methods:
        raise ExprCloneError("methods", "a study needs one method at least")
    if max_size is not None and max_size < MIN_SIZE:
        raise ExprCloneError("--max-size", f"expected at least {MIN_SIZE} pixels, got {max_size}")
    sets, folder = read_sets(manifest), Path(folder).resolve()
    check_destination(folder, overwrite)
    built = folder.with_name(f".{folder.name}.partial-{secrets.token_hex(4)}")
    try:
        (built / IMAGES).mkdir(parents=True)  # with the umask's permissions (a temporary folder's would be 0700)
        taken: set[str] = set()
        copies = copy_photos(manifest, sets, built, max_size, taken)
        rows, items = plan(sets, methods, copies, built, taken)
        outcomes: dict[int, Outcome] = {}
        job.run(rows, options, backend, outcomes, progress=progress)
        check_outcomes(manifest, sets, rows, outcomes, {str(built / IMAGES / f"{i}{SUFFIX}"): p for p, i in copies.items()})
        for ids in items:  # a result's file size would hint at its method
            pad_alike([built / IMAGES / f"{i}{SUFFIX}" for i in ids])
        public = Study(built, tuple(Set(dict(zip(ROLES, (copies[p] for p in s.photos))), tuple(i)) for s, i in zip(sets, items)))
        write_json(built / STUDY, public.public())
        write_json(built / KEY, key(manifest, sets, methods, items, options, max_size))
        install(built, folder)
    except OSError as e:
        raise ExprCloneError(str(folder), f"cannot be written ({e.strerror or e})") from None
    finally:
        shutil.rmtree(built, ignore_errors=True)


def copy_photos(manifest: str, sets: list[Triple], built: Path, size: int | None, taken: set[str]) -> dict[str, str]:
    """Each photo copied into the study as PNG under a new id (at most ``size`` pixels on its longest side); path to id.

    A photo that cannot be read stops the study: ExprCloneError about ``manifest`` naming the first set that has it.
    """
    copies: dict[str, str] = {}
    for triple in sets:
        for path in (p for p in triple.photos if p not in copies):
            try:
                image = load_image(path)
            except ExprCloneError as e:
                raise ExprCloneError(manifest, f"set {triple.name!r}: {e}") from None
            height, width = image.shape[:2]
            scale = 1.0 if size is None else min(1.0, size / max(height, width))
            if scale < 1:
                image = cv2.resize(image, (round(width * scale), round(height * scale)), interpolation=cv2.INTER_AREA)
            copies[path] = new_id(taken)
            save_image(built / IMAGES / f"{copies[path]}{SUFFIX}", image)
    return copies


def plan(
    sets: list[Triple], methods: tuple[str, ...], copies: dict[str, str], built: Path, taken: set[str]
) -> tuple[list[Row], list[dict[str, str]]]:
    """The batch rows (each set by each method, from the copies, to a new id) and each set's results (id to method)."""
    rows: list[Row] = []
    items: list[dict[str, str]] = []
    for triple in sets:
        ids = {new_id(taken): method for method in methods}
        items.append(ids)
        source_neutral, source_expression, target_neutral = (str(built / IMAGES / f"{copies[p]}{SUFFIX}") for p in triple.photos)
        for result, method in ids.items():
            output = str(built / IMAGES / f"{result}{SUFFIX}")
            cells = (("method", method), *triple.cells)
            rows.append(Row(len(rows) + 1, source_neutral, source_expression, target_neutral, output, cells))
    return rows, items


def check_outcomes(manifest: str, sets: list[Triple], rows: list[Row], outcomes: dict[int, Outcome], originals: dict[str, str]) -> None:
    """ExprCloneError for the first row that failed, naming its set and method, and its copies by the photos they came from."""
    failed = next((o for o in (outcomes[r.number] for r in rows) if o.status != "done"), None)
    if failed is None:
        return
    error = failed.error
    for copy, original in originals.items():
        error = error.replace(copy, original)
    name = sets[(failed.number - 1) * len(sets) // len(rows)].name
    raise ExprCloneError(manifest, f"set {name!r}, method {dict(rows[failed.number - 1].cells)['method']}: {error}")


def key(
    manifest: str, sets: list[Triple], methods: tuple[str, ...], items: list[dict[str, str]], options: Options, max_size: int | None
) -> dict[str, Any]:
    """What ``key.json`` holds: which result is which method, where each set came from, how the clones were made."""
    settings = {
        "lambda": options.lambda_k,
        "mouth": options.mouth,
        "landmarker": options.landmarker,
        "size": max_size,
        **changed(options),
    }
    sets_ = [
        {"name": s.name, "photos": dict(zip(ROLES, s.photos)), "lambda": dict(s.cells).get("lambda"), "items": i}
        for s, i in zip(sets, items)
    ]
    made = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
    return {
        "format": FORMAT,
        "manifest": str(Path(manifest).resolve()),
        "made": made,
        "exprclone": __version__,
        "methods": methods,
        "options": settings,
        "sets": sets_,
    }


def changed(options: Options) -> dict[str, Any]:
    """The options of a study's clones shown apart from its key's own (lambda, mouth, landmarker) that differ from the
    defaults (the ones given on the command line), as JSON values.

    >>> changed(Options()), changed(Options(strength=0.5, retarget=False))
    ({}, {'strength': 0.5, 'retarget': False})
    """
    default, shown = Options(), ("global_warp", "image_warp", "strength", "only", "retarget")
    return {name: getattr(options, name) for name in shown if getattr(options, name) != getattr(default, name)}


def pad_alike(paths: list[Path]) -> None:
    """PNG files made the same length: each gets a private ancillary chunk (``paDd``, which decoders skip) of zeros
    before its end, up to the longest's length and the chunk's own 12 bytes."""
    contents = [p.read_bytes() for p in paths]
    longest = max(len(c) for c in contents) + PAD_CHUNK
    for path, content in zip(paths, contents):
        data = bytes(longest - len(content) - PAD_CHUNK)
        chunk = len(data).to_bytes(4, "big") + b"paDd" + data + zlib.crc32(b"paDd" + data).to_bytes(4, "big")
        path.write_bytes(content[:-IEND] + chunk + content[-IEND:])


def install(built: Path, folder: Path) -> None:
    """Rename the whole study into place, replacing the folder there (empty, or a study being overwritten)."""
    if not folder.exists():
        os.rename(built, folder)
        return
    old = folder.with_name(f".{folder.name}.old-{secrets.token_hex(4)}")
    os.rename(folder, old)
    os.rename(built, folder)
    shutil.rmtree(old, ignore_errors=True)
