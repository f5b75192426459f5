"""Shared fixtures: the samples shipped in the package, the full data sets, and landmarks.

Most tests run on the samples that ship inside the package (:mod:`exprclone.data`: three
London people and a GRID clip), so that ``pytest`` passes in a fresh clone with nothing
beside it. Tests that need the full sets (the 72 London people, the 11 GRID clips) find
them in ``$EXPRCLONE_DATA``, else ``../shared/data`` beside the checkout, and skip with the
reason when they are absent; so do the browser tests without Debian's Chromium. With
``EXPRCLONE_REQUIRE_ALL=1`` (as CI sets) they fail instead. The tests of pure geometry need no photo: they use the landmarks of a few
photos, shipped in ``tests/data/landmarks.json``.
"""

import contextlib
import io
import json
import os
import re
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from exprclone import data as samples
from exprclone.io.images import load_image
from exprclone.landmarks.backends import default_detector

DATA = Path(os.environ.get("EXPRCLONE_DATA", Path(__file__).resolve().parents[2] / "shared" / "data"))
LONDON = DATA / "london"
GRID = DATA / "grid"
REQUIRE_ALL = os.environ.get("EXPRCLONE_REQUIRE_ALL") == "1"
SHIPPED = json.loads((Path(__file__).parent / "data" / "landmarks.json").read_text())


@dataclass(frozen=True)
class Completed:
    """What a command did: its exit status and what it printed (as :class:`subprocess.CompletedProcess` has them)."""

    returncode: int
    stdout: str
    stderr: str


def command(*args: object, cwd: Path | str | None = None) -> Completed:
    """``exprclone ARGS`` run in this process (:func:`exprclone.cli.main.main`), in ``cwd`` if given: its exit status and
    what it printed. Each warning is shown as a fresh process would show it."""
    from exprclone.cli.main import main

    out, err, here = io.StringIO(), io.StringIO(), os.getcwd()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), warnings.catch_warnings():
        warnings.simplefilter("always")
        try:
            os.chdir(cwd or here)
            code = main([str(a) for a in args])
        except SystemExit as e:  # argparse's usage errors, and a command's own exit status
            code = e.code if isinstance(e.code, int) else 0 if e.code is None else 1
        finally:
            os.chdir(here)
    return Completed(code, out.getvalue(), err.getvalue())


def need(path: Path, reason: str) -> Path:
    """``path``, which the test needs from outside the repository; skipped without it (failed under EXPRCLONE_REQUIRE_ALL=1)."""
    if not path.exists():
        (pytest.fail if REQUIRE_ALL else pytest.skip)(f"{reason}: {path} not found")
    return path


def need_full_data(path: Path) -> Path:
    """``path`` in the full data sets (see :func:`need`)."""
    return need(path, "needs the full data sets (set EXPRCLONE_DATA to the folder holding london/ and grid/)")


def neutral_path(face_id: str) -> Path:
    """A neutral London photo: the packaged sample when it ships, else the full set's."""
    return samples.path(face_id) if face_id in samples.PEOPLE else LONDON / "neutral_front" / f"{face_id}_03.jpg"


def smile_path(face_id: str) -> Path:
    """A smiling London photo: the packaged sample when it ships, else the full set's."""
    return samples.path(face_id, "smile") if face_id in samples.PEOPLE else LONDON / "smiling_front" / f"{face_id}_08.jpg"


#: the full set's GRID clips, or one placeholder whose test skips (fails under EXPRCLONE_REQUIRE_ALL=1).
GRID_CLIPS = sorted(GRID.glob("*.mpg")) or [GRID / "(no clips)"]


@pytest.fixture(scope="session")
def london() -> Path:
    """The packaged samples as a London-Set folder (three people)."""
    return samples.london()


@pytest.fixture(scope="session")
def london_full() -> Path:
    """The full London Set (72 people)."""
    return need_full_data(LONDON / "neutral_front").parent


@pytest.fixture(scope="session")
def grid_clip() -> Path:
    """The packaged GRID clip: 360x288, 25 fps, 75 frames, with sound (H.264 and AAC)."""
    return samples.clip()


@pytest.fixture(scope="session")
def grid_mpg() -> Path:
    """A GRID clip as the corpus ships it: MPEG-1 with MP2 sound, 360x288, 25 fps, 75 frames."""
    return need_full_data(GRID / "bbaf2n.mpg")


@pytest.fixture(scope="session")
def photo():
    """A London photo and its detected landmarks, loaded once per session: photo(face_id, 'neutral'|'smile').

    The packaged samples (001, 003, 126) always; the others, and with ``original=True``
    the full set's own (finer) JPEG of a packaged person, need the full set.
    """
    cache: dict = {}

    def get(face_id: str, kind: str = "neutral", original: bool = False) -> tuple[np.ndarray, np.ndarray]:
        if (face_id, kind, original) not in cache:
            path = neutral_path(face_id) if kind == "neutral" else smile_path(face_id)
            if original:
                path = LONDON / path.parent.name / path.name
            image = load_image(need_full_data(path))
            cache[face_id, kind, original] = (image, default_detector().detect(image, str(path)))
        return cache[face_id, kind, original]

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


@pytest.fixture(scope="session")
def made_study(tmp_path_factory) -> Path:
    """A study made once by ``exprclone study make`` (tests/studies.py: two sets of the samples, three methods); copy it to change it."""
    from studies import make

    folder = tmp_path_factory.mktemp("made")
    p = make(folder)
    assert p.returncode == 0, p.stderr
    return folder / "study"


@pytest.fixture()
def study_folder(made_study, tmp_path) -> Path:
    """A copy of :func:`made_study` of this test's own."""
    import shutil

    return Path(shutil.copytree(made_study, tmp_path / "study"))


#: the paper's words and symbols, which a page for a person keeps under its "Advanced" fold (the options of
#: :data:`exprclone.options.ADVANCED`): acronyms as written, words in any case.
PAPER_ACRONYMS = ("DB", "ERI", "GI", "LI", "RBF", "TPS", "VTC", "E+MD")
PAPER_WORDS = (
    "λ",
    "lambda",
    "global warp",
    "image warp",
    "elastic",
    "similarity",
    "piecewise",
    "affine",
    "thin-plate",
    "eigenface",
    "jacobian",
    "landmark",
    "muscle",
    "Fig.",
    "Eq.",
    "dlib",
    "MediaPipe",
)


def paper_terms(text: str) -> list[str]:
    """The paper's words and symbols (:data:`PAPER_ACRONYMS`, :data:`PAPER_WORDS`) that ``text`` uses."""
    found = [a for a in PAPER_ACRONYMS if re.search(rf"(?<![\w+]){re.escape(a)}(?![\w+])", text)]
    return found + [w for w in PAPER_WORDS if w.lower() in text.lower()]
