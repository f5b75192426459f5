"""Landmarks read from and written to files: JSON, and WebMorph/Psychomorph ``.tem`` templates."""

from __future__ import annotations

import json
import os
import re

import numpy as np

from ..errors import ExprCloneError, quoted
from ..landmarks.layout import DLIB68
from ..pipeline.checks import check_face, check_finite, check_points
from .documents import parse_json
from .frl_template import frl_to_68
from .images import atomic_write, check_file

#: points in the Face Research Lab template
TEM_POINTS = 189
#: the largest landmark file read, in characters (a 189-point template with its line definitions is about 10 000).
MAX_CHARS = 1_000_000
#: the deepest nesting of brackets a JSON landmark file may have (``{"landmarks": [[x, y], ...]}`` has 3).
MAX_DEPTH = 8


def read_tem(path: str | os.PathLike[str]) -> np.ndarray:
    """The points of a 189-point Face Research Lab ``.tem`` template.

    The file holds the point count on its first line, then one ``x y`` line per point (tab
    or space separated, pixels); the line definitions that follow are ignored.

    Parameters
    ----------
    path : str or os.PathLike
        The ``.tem`` file.

    Returns
    -------
    ndarray of shape (189, 2), float64
        Points (x, y) in template order; points 0 and 1 are the pupils.

    Raises
    ------
    ExprCloneError
        Missing or unreadable file, a malformed count or point line, a count other than
        189, or a NaN or infinite coordinate; the message names the file.
    """
    return parse_tem(_read_text(path), str(path))


def parse_tem(text: str, name: str) -> np.ndarray:
    """The points of a ``.tem`` template's text (see :func:`read_tem`); errors are about ``name``."""
    lines = text.splitlines()
    header = lines[0].strip() if lines else ""
    if not re.fullmatch(r"[0-9]{1,6}", header):
        raise ExprCloneError(name, f"not a .tem template (the first line must be the point count, got {quoted(header)})")
    count = int(header)
    if count != TEM_POINTS:
        raise ExprCloneError(name, f"{count} template points, expected the {TEM_POINTS}-point Face Research Lab template")
    if len(lines) <= count:
        raise ExprCloneError(name, f"not a .tem template (found {len(lines) - 1} point lines, expected {count})")
    points = np.empty((count, 2))
    for k in range(count):
        fields = lines[1 + k].split()
        try:
            if len(fields) != 2:
                raise ValueError
            points[k] = [float(fields[0]), float(fields[1])]
        except ValueError:
            raise ExprCloneError(name, f"not a .tem template (line {k + 2} should be 'x y', got {quoted(lines[1 + k])})") from None
    check_finite(points, name)
    return points


def read_landmarks(path: str | os.PathLike[str], image_shape: tuple[int, ...], n_points: int = 68) -> np.ndarray:
    """Landmarks for a photo of shape ``image_shape`` from a ``.json`` or ``.tem`` file.

    JSON holds ``{"landmarks": [[x, y], ...]}`` (what :func:`write_landmarks` writes) or a
    plain list of ``[x, y]`` pairs. A ``.tem`` must be a 189-point Face Research Lab
    template; it is mapped to the 68-point layout by :func:`exprclone.io.frl_template.frl_to_68`.

    Parameters
    ----------
    path : str or os.PathLike
        The landmark file; its extension (``.json`` or ``.tem``) selects the format.
    image_shape : tuple of int
        Shape ``(H, W, ...)`` of the photo the landmarks belong to.
    n_points : int
        Number of landmarks expected.

    Returns
    -------
    ndarray of shape (n_points, 2), float64
        Landmarks (x, y) in pixels.

    Raises
    ------
    ExprCloneError
        Missing or unreadable file, unknown extension, invalid JSON, wrong structure, wrong
        number of points, NaN or infinite values, or points outside the image; the message
        names the file.
    """
    return parse_landmarks(_read_text(path), os.path.splitext(path)[1], image_shape, n_points, str(path))


def parse_landmarks(text: str, extension: str, image_shape: tuple[int, ...], n_points: int = 68, name: str = "landmarks") -> np.ndarray:
    """Landmarks from a landmark file's text, as :func:`read_landmarks`; ``extension`` (``.json`` or ``.tem``) names its format."""
    extension = extension.lower()
    if len(text) > MAX_CHARS:
        raise ExprCloneError(name, f"too large for a landmark file ({len(text)} characters; at most {MAX_CHARS})")
    if extension == ".tem":
        points = frl_to_68(parse_tem(text, name))
    elif extension == ".json":
        points = _parse_json_points(text, name)
    else:
        raise ExprCloneError(name, f"unknown landmark file type {extension!r} (use .json or .tem)")
    points = check_points(points, image_shape, n_points, name)
    return check_face(points, DLIB68, name) if n_points == DLIB68.n_points else points


def write_landmarks(path: str | os.PathLike[str], landmarks: np.ndarray) -> None:
    """Write landmarks as JSON ``{"landmarks": [[x, y], ...]}``, atomically.

    Coordinates are written at full float64 precision, so :func:`read_landmarks` gives
    back exactly the same values.

    Parameters
    ----------
    path : str or os.PathLike
        The ``.json`` file to write; it is replaced only once the new content is complete.
    landmarks : array_like of shape (N, 2)
        Landmarks (x, y) in pixels, all finite.

    Raises
    ------
    ExprCloneError
        If ``landmarks`` is not an (N, 2) array of finite numbers.
    ExprCloneError
        If the file cannot be written.
    """
    landmarks = np.asarray(landmarks, dtype=np.float64)
    if landmarks.ndim != 2 or landmarks.shape[1] != 2 or not np.isfinite(landmarks).all():
        raise ExprCloneError("landmarks", f"expected finite landmarks of shape (N, 2), got shape {landmarks.shape}")
    text = json.dumps({"landmarks": landmarks.tolist()}).encode()
    atomic_write(path, lambda f: f.write(text))


def _parse_json_points(text: str, name: str) -> np.ndarray:
    """The ``[x, y]`` pairs of a JSON landmark file's text, as an (N, 2) array (count not checked).

    Nesting deeper than :data:`MAX_DEPTH` is refused before parsing; numbers are read as floats (an
    integer of any length too: a huge one becomes infinite, and :func:`check_points` refuses it, as it
    refuses the NaN and Infinity that Python writes).
    """
    data = parse_json(text, name, MAX_DEPTH, parse_int=float)
    if isinstance(data, dict):
        data = data.get("landmarks")
    if not isinstance(data, list) or not all(isinstance(p, list) and len(p) == 2 and all(map(_is_number, p)) for p in data):
        raise ExprCloneError(name, 'expected a list of [x, y] pairs or {"landmarks": [[x, y], ...]}')
    return np.array(data, dtype=np.float64).reshape(-1, 2)


def _is_number(value: object) -> bool:
    """Whether a decoded JSON value is a number (JSON's true and false are not)."""
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _read_text(path: str | os.PathLike[str]) -> str:
    """The file's text, or ExprCloneError naming the file."""
    check_file(path)
    try:
        with open(path, encoding="utf-8-sig") as f:
            return f.read(MAX_CHARS + 1)
    except FileNotFoundError:
        raise ExprCloneError(path, "no such file") from None
    except OSError as e:
        raise ExprCloneError(path, f"cannot be read ({e.strerror})") from None
    except UnicodeDecodeError:
        raise ExprCloneError(path, "not a text file (not UTF-8)") from None
