"""Shared fixtures: the real sample photos and clips of ../shared/data, and the photos' landmarks.

The data folder is taken from EXPRCLONE_DATA, else ../shared/data beside the checkout. The
tests of pure geometry need no photo: they use the landmarks of a few photos, shipped in
``tests/data/landmarks.json``.
"""

import json
import os
from pathlib import Path

import numpy as np
import pytest

from exprclone.io.images import load_image
from exprclone.pipeline import default_detector

DATA = Path(os.environ.get("EXPRCLONE_DATA", Path(__file__).resolve().parents[2] / "shared" / "data"))
LONDON = DATA / "london"
GRID = DATA / "grid"
SHIPPED = json.loads((Path(__file__).parent / "data" / "landmarks.json").read_text())


def neutral_path(face_id: str) -> Path:
    return LONDON / "neutral_front" / f"{face_id}_03.jpg"


def smile_path(face_id: str) -> Path:
    return LONDON / "smiling_front" / f"{face_id}_08.jpg"


@pytest.fixture(scope="session")
def london() -> Path:
    if not LONDON.is_dir():
        pytest.fail(f"sample data not found at {LONDON}: set EXPRCLONE_DATA to the shared data folder")
    return LONDON


@pytest.fixture(scope="session")
def grid_clip() -> Path:
    """A GRID clip: 360x288, 25 fps, 75 frames, with sound (mp2)."""
    clip = GRID / "bbaf2n.mpg"
    if not clip.is_file():
        pytest.fail(f"sample clip not found at {clip}: set EXPRCLONE_DATA to the shared data folder")
    return clip


@pytest.fixture(scope="session")
def photo(london):
    """Load a photo and its detected landmarks once per session: photo(face_id, 'neutral'|'smile')."""
    cache: dict = {}

    def get(face_id: str, kind: str = "neutral") -> tuple[np.ndarray, np.ndarray]:
        if (face_id, kind) not in cache:
            path = neutral_path(face_id) if kind == "neutral" else smile_path(face_id)
            image = load_image(path)
            cache[face_id, kind] = (image, default_detector().detect(image, str(path)))
        return cache[face_id, kind]

    return get


@pytest.fixture(scope="session")
def pair(photo):
    """A real cross-person triple: source 001 (neutral, smile) onto target 003."""
    (sn, sn_lm), (se, se_lm), (tn, tn_lm) = photo("001"), photo("001", "smile"), photo("003")
    return (sn, se, tn), (sn_lm, se_lm, tn_lm)


@pytest.fixture(scope="session")
def points():
    """Shipped landmarks of a London photo (no photo, no dlib): points(face_id, 'neutral'|'smile') -> (68, 2) float."""
    return lambda face_id, kind="neutral": np.array(SHIPPED["faces"][f"{face_id}_{kind}"], float)


@pytest.fixture(scope="session")
def pair_points(points):
    """The landmarks of :func:`pair`'s photos (source 001 neutral and smile, target 003), and the photos' shape."""
    return (points("001"), points("001", "smile"), points("003")), tuple(SHIPPED["shape"])
