"""A built-in expression on disk: one JSON file naming its two photos, with their landmarks.

::

    {"name": "smile", "description": "...", "people": ["001", "002", ...],
     "neutral": {"image": "smile-neutral.jpg", "landmarks": [[x, y], ...]},
     "expression": {"image": "smile.jpg", "landmarks": [[x, y], ...]}}

Image paths are relative to the JSON file's folder. ``people`` are the London Set people
the expression was made from: a clone scored against one of them is not held out
(:mod:`exprclone.evaluation.expression`).
"""

from __future__ import annotations

import functools
import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any

import numpy as np
from PIL import Image

from ..errors import ExprCloneError
from ..io.documents import parse_json
from ..io.images import atomic_write, load_image
from ..landmarks.layout import DLIB68
from ..pipeline.checks import check_points
from .composite import Face

#: the JPEG quality of a composite written by :func:`write`: 90 keeps the teeth's edges (95 doubles the size).
QUALITY = 90
#: the roles of a built-in expression's two photos, as its JSON file names them.
PARTS = ("neutral", "expression")


@dataclass(frozen=True)
class Expression:
    """A source pair shipped ready to clone: a neutral face and the expression, each a photo with its landmarks.

    Attributes
    ----------
    name : str
    description : str
        One line: what it is and where it comes from.
    people : tuple of str
        The London Set people it was made from.
    neutral, expression : Face
        The two photos (uint8 RGB, read-only) and their 68 landmarks.
    files : tuple of two str
        Where the two photos were read from (empty for an expression made in memory).
    """

    name: str
    description: str
    people: tuple[str, ...]
    neutral: Face
    expression: Face
    files: tuple[str, str] = ("", "")


def read(path: str | os.PathLike[str]) -> Expression:
    """The expression a JSON file describes, its photos loaded (read-only) and its landmarks checked.

    Raises
    ------
    ExprCloneError
        About the file: unreadable, not such a JSON document, a photo missing or
        unreadable, landmarks of the wrong count or outside their photo.
    """
    path = Path(path)
    try:
        document = parse_json(path.read_text(), str(path))
        parts = [(document[part]["image"], document[part]["landmarks"]) for part in PARTS]
        name, description, people = str(document["name"]), str(document.get("description", "")), tuple(document.get("people", ()))
    except OSError as e:
        raise ExprCloneError(path, f"cannot read the expression file: {e.strerror or e}") from None
    except ExprCloneError:
        raise
    except (ValueError, KeyError, TypeError) as e:
        raise ExprCloneError(
            path, f"not an expression file (JSON with name, neutral and expression, each an image and landmarks): {e}"
        ) from None
    faces, files = [], tuple(str((path.parent / image_name).resolve()) for image_name, _ in parts)
    for part, file, (_, points) in zip(PARTS, files, parts):
        image = load_image(file)
        image.flags.writeable = False
        faces.append(Face(image, check_points(points, image.shape, DLIB68.n_points, f"{path} ({part} landmarks)")))
    return Expression(name, description, people, faces[0], faces[1], (files[0], files[1]))


def _jpeg(image: np.ndarray, out: IO[bytes]) -> None:
    """The image as a JPEG of :data:`QUALITY`, to ``out``."""
    Image.fromarray(image).save(out, format="JPEG", quality=QUALITY)


def write(expression: Expression, folder: str | os.PathLike[str], images: dict[str, str] | None = None) -> Path:
    """Write ``folder/NAME.json`` and, for each part not named in ``images``, its photo as ``NAME-PART.jpg`` (JPEG at :data:`QUALITY`).

    Parameters
    ----------
    expression : Expression
    folder : str or os.PathLike
    images : dict of str to str, optional
        Photos already on disk, by part (``neutral``, ``expression``), relative to ``folder``:
        written as they are named, not again.

    Returns
    -------
    Path
        The JSON file.
    """
    folder, images = Path(folder), dict(images or {})
    for part, face in zip(PARTS, (expression.neutral, expression.expression)):
        if part not in images:
            images[part] = f"{expression.name}-{part}.jpg"
            atomic_write(folder / images[part], functools.partial(_jpeg, face.image))
    document: dict[str, Any] = {"name": expression.name, "description": expression.description, "people": list(expression.people)}
    for part, face in zip(PARTS, (expression.neutral, expression.expression)):
        document[part] = {"image": images[part], "landmarks": np.round(np.asarray(face.points, float), 2).tolist()}
    out = folder / f"{expression.name}.json"
    text = json.dumps(document, indent=1).encode()
    atomic_write(out, lambda f: f.write(text))
    return out
