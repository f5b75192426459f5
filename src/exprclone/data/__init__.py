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
    """The folder of the samples (inside the installed package)."""
    return Path(str(resources.files(__name__)))


def london() -> Path:
    """The samples as a London-Set folder: ``neutral_front/ID_03.jpg``, ``smiling_front/ID_08.jpg``, ``neutral_front/ID_03.tem``."""
    return folder() / "london"


def path(face_id: str, kind: str = "neutral") -> Path:
    """One of the London photos: ``kind`` is ``neutral`` or ``smile``."""
    if face_id not in PEOPLE or kind not in ("neutral", "smile"):
        raise ExprCloneError("sample", f"no {face_id} {kind}: the samples are {', '.join(PEOPLE)}, neutral or smile")
    return london() / ("neutral_front" if kind == "neutral" else "smiling_front") / f"{face_id}_{'03' if kind == 'neutral' else '08'}.jpg"


def template(face_id: str) -> Path:
    """The London Set's manual 189-point template of a neutral photo (``.tem``, read by :func:`exprclone.io.landmarks.read_landmarks`)."""
    return path(face_id).with_suffix(".tem")


def clip() -> Path:
    """A GRID clip with its sound (speaker 1, "lay blue at x four now"; 75 frames, 360x288, 25 fps)."""
    return folder() / "grid" / "lbax4n.mp4"


def photo(face_id: str, kind: str = "neutral") -> np.ndarray:
    """One of the London photos, loaded: ``(1350, 1350, 3)`` uint8 RGB."""
    from ..io.images import load_image

    return load_image(path(face_id, kind))


def credits() -> str:
    """Where the samples come from, and their licence."""
    return (folder() / "CREDITS.md").read_text()
