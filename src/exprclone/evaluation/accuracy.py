"""Landmark accuracy against the London Set's manual templates, per region of the 68-point layout.

Each neutral photo ``neutral_front/ID_03.jpg`` has a manual 189-point template
(``ID_03.tem``), mapped to the 68 points by :func:`exprclone.io.frl_template.frl_to_68`.
A landmarker's error on a photo is the mean distance of its points to the template's,
over the template's outer-eye-corner distance (points 36 and 45), per region
(:data:`REGIONS`). The mesh table (:data:`exprclone.landmarks.mesh_layout.MESH_TO_68`) is fitted on
the people of :func:`split`'s training part; the others are held out for its error.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import ExprCloneError
from ..io.frl_template import frl_to_68
from ..io.landmarks import read_tem
from ..landmarks.layout import DLIB68

#: the regions the error is given for, as index tuples of the 68-point layout.
REGIONS = {
    "jaw": DLIB68.jaw,
    "brows": DLIB68.brows[0] + DLIB68.brows[1],
    "nose": DLIB68.nose,
    "eyes": DLIB68.eyes[0] + DLIB68.eyes[1],
    "outer lips": DLIB68.mouth_outer,
    "inner lips": DLIB68.mouth_inner,
}
#: every this many people (sorted by id), one is held out of the mesh table's fit: the third, sixth, ...
HOLD_OUT_EVERY = 3


def templates(london: str | Path) -> dict[str, tuple[Path, np.ndarray]]:
    """Each person of ``london/neutral_front`` with a template: id -> (photo path, the template's 68 points)."""
    folder = Path(london) / "neutral_front"
    if not any(folder.glob("*_03.tem")):
        raise ExprCloneError(str(folder), "no templates (ID_03.tem) there")
    return {tem.name[:3]: (tem.with_suffix(".jpg"), frl_to_68(read_tem(tem))) for tem in sorted(folder.glob("*_03.tem"))}


def split(ids: list[str]) -> tuple[list[str], list[str]]:
    """The people the mesh table is fitted on, and those held out (every :data:`HOLD_OUT_EVERY`-th by sorted id).

    >>> split(["001", "002", "003", "004", "005", "006", "007"])
    (['001', '002', '004', '005', '007'], ['003', '006'])
    """
    ordered = sorted(ids)
    held = ordered[HOLD_OUT_EVERY - 1 :: HOLD_OUT_EVERY]
    return [i for i in ordered if i not in held], held


def point_errors(found: np.ndarray, truth: np.ndarray) -> np.ndarray:
    """Distance of each point to the truth over the truth's outer-eye-corner distance.

    Parameters
    ----------
    found, truth : ndarray of shape (..., 68, 2)

    Returns
    -------
    ndarray of shape (..., 68)
    """
    corners = np.linalg.norm(truth[..., DLIB68.eye_corners[0], :] - truth[..., DLIB68.eye_corners[1], :], axis=-1)
    return np.linalg.norm(found - truth, axis=-1) / corners[..., None]


def region_errors(errors: np.ndarray) -> dict[str, float]:
    """The mean of ``errors`` ``(F, 68)`` over all points and over each region of :data:`REGIONS`."""
    return {"all": float(errors.mean()), **{name: float(errors[:, list(points)].mean()) for name, points in REGIONS.items()}}
