"""Sample data shipped with the package, so that every example runs anywhere (as ``skimage.data``).

Three people of the Face Research Lab London Set (001, 003 and 126; neutral and smiling
photos, and the set's landmark templates of the neutral photos) and one GRID clip with
its sound; their credits and licence (CC BY 4.0) are in ``CREDITS.md`` beside this file
(:func:`credits`). Functions return file paths, and :func:`photo` the loaded image.

>>> path("126", "smile").name
'126_08.jpg'
>>> sorted(p.name for p in (london() / "neutral_front").glob("*.jpg"))
['001_03.jpg', '003_03.jpg', '126_03.jpg']
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import ExprCloneError

if TYPE_CHECKING:
    import numpy as np

#: the London Set's people shipped, each with a neutral and a smiling photo.
PEOPLE = ("001", "003", "126")
#: the demo's source (its smile shows teeth) and target.
SOURCE, TARGET = "126", "003"


def folder() -> Path:
    """The folder of the samples (inside the installed package).

    Returns
    -------
    pathlib.Path

    Examples
    --------
    >>> (folder() / "CREDITS.md").exists()
    True
    """
    return Path(str(resources.files(__name__)))


def london() -> Path:
    """The samples as a London-Set folder, as ``exprclone evaluate --data`` reads one.

    Returns
    -------
    pathlib.Path
        Holding ``neutral_front/ID_03.jpg``, ``smiling_front/ID_08.jpg`` and ``neutral_front/ID_03.tem``.

    Examples
    --------
    >>> sorted(p.name for p in (london() / "smiling_front").iterdir())
    ['001_08.jpg', '003_08.jpg', '126_08.jpg']
    """
    return folder() / "london"


def path(face_id: str, kind: str = "neutral") -> Path:
    """The file of one of the London photos.

    Parameters
    ----------
    face_id : str
        One of :data:`PEOPLE`.
    kind : str
        ``"neutral"`` or ``"smile"``.

    Returns
    -------
    pathlib.Path
        A 1350x1350 JPEG.

    Raises
    ------
    ExprCloneError
        About ``sample``, for a person or kind not shipped.

    Examples
    --------
    >>> path("003").name, path("003", "smile").name
    ('003_03.jpg', '003_08.jpg')
    >>> path("002")
    Traceback (most recent call last):
    ...
    exprclone.errors.ExprCloneError: sample: no 002 neutral: the samples are 001, 003, 126, neutral or smile
    """
    if face_id not in PEOPLE or kind not in ("neutral", "smile"):
        raise ExprCloneError("sample", f"no {face_id} {kind}: the samples are {', '.join(PEOPLE)}, neutral or smile")
    return london() / ("neutral_front" if kind == "neutral" else "smiling_front") / f"{face_id}_{'03' if kind == 'neutral' else '08'}.jpg"


def template(face_id: str) -> Path:
    """The London Set's manual 189-point landmark template of a neutral photo.

    Parameters
    ----------
    face_id : str
        One of :data:`PEOPLE`.

    Returns
    -------
    pathlib.Path
        A ``.tem`` file, read by :func:`exprclone.io.landmarks.read_landmarks` as the 68-point layout.

    Raises
    ------
    ExprCloneError
        About ``sample``, for a person not shipped.

    Examples
    --------
    >>> from exprclone.io.landmarks import read_landmarks
    >>> read_landmarks(template("003"), (1350, 1350, 3)).shape
    (68, 2)
    """
    return path(face_id).with_suffix(".tem")


def clip() -> Path:
    """A GRID clip with its sound: speaker 1 says "lay blue at x four now".

    Returns
    -------
    pathlib.Path
        An MP4 (H.264 and AAC) of 75 frames, 360x288, 25 fps.

    Examples
    --------
    >>> from exprclone.io.video import probe
    >>> info = probe(clip())
    >>> (info.width, info.height), float(info.fps)
    ((360, 288), 25.0)
    """
    return folder() / "grid" / "lbax4n.mp4"


def photo(face_id: str, kind: str = "neutral") -> np.ndarray:
    """One of the London photos, loaded.

    Parameters
    ----------
    face_id, kind
        As for :func:`path`.

    Returns
    -------
    ndarray of shape (1350, 1350, 3), uint8 RGB

    Raises
    ------
    ExprCloneError
        As for :func:`path`.

    Examples
    --------
    >>> image = photo("126", "smile")
    >>> image.shape, image.dtype.name
    ((1350, 1350, 3), 'uint8')
    """
    from ..io.images import load_image  # (numpy and Pillow when a photo is read: naming the samples needs neither)

    return load_image(path(face_id, kind))


def credits() -> str:
    """Where the samples come from, and their licence.

    Returns
    -------
    str
        The text of ``CREDITS.md`` (Markdown).

    Examples
    --------
    >>> "CC BY 4.0" in credits() and "DeBruine" in credits()
    True
    """
    return (folder() / "CREDITS.md").read_text()
