"""Landmarks read from and written to files: JSON, and WebMorph/Psychomorph ``.tem`` templates."""

from __future__ import annotations

import json
import os

import numpy as np

from .errors import ExprCloneError
from .frl_template import frl_to_68
from .images import atomic_write

#: points in the Face Research Lab template
TEM_POINTS = 189


def read_tem(path: str | os.PathLike) -> np.ndarray:
    """The points of a ``.tem`` template: first line the count, then one ``x y`` line each.

    The line definitions that follow the points are ignored.

    Returns
    -------
    ndarray of shape (n, 2)
    """
    lines = _read_text(path).split("\n")
    try:
        count = int(lines[0].strip())
        points = np.array([[float(v) for v in lines[1 + k].split()[:2]] for k in range(count)])
    except (ValueError, IndexError):
        raise ExprCloneError(f"{path}: not a .tem template (a point count, then one 'x y' line per point)") from None
    if points.shape != (count, 2):
        raise ExprCloneError(f"{path}: not a .tem template (a point line lacks its y)")
    return points


def read_landmarks(path: str | os.PathLike, image_shape: tuple[int, ...], n_points: int = 68) -> np.ndarray:
    """Landmarks for a photo of shape ``image_shape`` from a ``.json`` or ``.tem`` file.

    JSON holds ``{"landmarks": [[x, y], ...]}`` (what :func:`write_landmarks` writes) or a
    plain list of ``[x, y]`` pairs; a ``.tem`` must be a 189-point Face Research Lab
    template, mapped to the 68-point layout by :func:`exprclone.frl_template.frl_to_68`.

    Returns
    -------
    ndarray of shape (n_points, 2)

    Raises
    ------
    ExprCloneError
        Unreadable file, wrong structure, wrong number of points, NaN, or points
        outside the image; the message names the file.
    """
    if str(path).lower().endswith(".tem"):
        points = read_tem(path)
        if len(points) != TEM_POINTS:
            raise ExprCloneError(f"{path}: {len(points)} template points, expected the {TEM_POINTS}-point Face Research Lab template")
        points = frl_to_68(points)
    else:
        try:
            data = json.loads(_read_text(path))
        except json.JSONDecodeError as e:
            raise ExprCloneError(f"{path}: invalid JSON ({e.msg} at line {e.lineno})") from None
        if isinstance(data, dict):
            data = data.get("landmarks")
        try:
            points = np.array(data, dtype=float)
        except (TypeError, ValueError):
            points = np.empty((0,))
        if points.ndim != 2 or points.shape[1:] != (2,):
            raise ExprCloneError(f'{path}: expected a list of [x, y] pairs (or {{"landmarks": [...]}})')
    return check_points(points, image_shape, n_points, str(path))


def check_points(points: np.ndarray, image_shape: tuple[int, ...], n_points: int, name: str) -> np.ndarray:
    """``points`` as an ``(n_points, 2)`` float array inside the image, or ExprCloneError naming ``name``."""
    points = np.asarray(points, float)
    if points.ndim != 2 or points.shape[1:] != (2,) or len(points) != n_points:
        found = len(points) if points.ndim == 2 else f"an array of shape {points.shape}"
        raise ExprCloneError(f"{name}: {found} landmarks, expected {n_points} (x, y) pairs")
    h, w = image_shape[:2]
    bad = ~np.isfinite(points).all(1) | (points[:, 0] < 0) | (points[:, 0] > w - 1) | (points[:, 1] < 0) | (points[:, 1] > h - 1)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        x, y = points[i]
        raise ExprCloneError(f"{name}: landmark {i} at ({x:g}, {y:g}) is outside the {w}x{h} image")
    return points


def write_landmarks(path: str | os.PathLike, landmarks: np.ndarray) -> None:
    """Write ``{"landmarks": [[x, y], ...]}`` atomically."""
    text = json.dumps({"landmarks": np.asarray(landmarks, float).round(3).tolist()}).encode()
    atomic_write(path, lambda f: f.write(text))


def _read_text(path: str | os.PathLike) -> str:
    try:
        with open(path, encoding="utf-8") as f:
            return f.read()
    except FileNotFoundError:
        raise ExprCloneError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise ExprCloneError(f"{path}: is a directory") from None
    except (OSError, UnicodeDecodeError) as e:
        raise ExprCloneError(f"{path}: cannot be read ({e})") from None
