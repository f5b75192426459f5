"""A study folder: what ``exprclone study make`` writes, ``study serve`` shows and ``study results`` reads.

::

    DIR/
      study.json        the public part: each set's three photos and its results, by id
      images/ID.png     every photo and result, under a random id
      key.json          which result is which method, and where each set came from
      ratings/PID.json  one participant's ratings (written by ``study serve``)

The page's server reads only ``study.json`` and the images it lists, and writes only
``ratings/``: it never opens ``key.json``, which ``study results`` alone reads. An id is
16 random hex digits (:func:`new_id`, from :mod:`secrets`), so nothing of a method's name
can be read back from it, and ``study.json`` lists a set's results sorted by id, not in
the methods' order.
"""

from __future__ import annotations

import json
import re
import secrets
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import ExprCloneError
from ..io.documents import parse_json
from ..io.images import atomic_write
from ..roles import ROLES

#: the files and folders of a study.
STUDY, KEY, IMAGES, RATINGS = "study.json", "key.json", "images", "ratings"
#: the version of the layout, written in ``study.json`` and ``key.json``.
FORMAT = 1
#: an image's id.
ID = re.compile(r"[0-9a-f]{16}")
#: the suffix of every image of a study.
SUFFIX = ".png"


def new_id(taken: set[str]) -> str:
    """A random id (:data:`ID`) not in ``taken``, which it joins."""
    while (found := secrets.token_hex(8)) in taken:
        pass
    taken.add(found)
    return found


@dataclass(frozen=True)
class Set:
    """One set of a study as a participant sees it: ``photos``, each role's image id (roles of :mod:`exprclone.roles`);
    ``items``, its results' ids."""

    photos: dict[str, str]
    items: tuple[str, ...]


@dataclass(frozen=True)
class Study:
    """The public part of a study folder (``study.json``): its sets, in the order they are shown."""

    folder: Path
    sets: tuple[Set, ...]

    def image(self, image_id: str) -> Path:
        """The file of an image, by id."""
        return self.folder / IMAGES / f"{image_id}{SUFFIX}"

    def images(self) -> set[str]:
        """The ids of every image the page may show."""
        return {i for s in self.sets for i in (*s.photos.values(), *s.items)}

    def public(self) -> dict[str, Any]:
        """What ``study.json`` holds."""
        return {"format": FORMAT, "sets": [{"photos": s.photos, "items": sorted(s.items)} for s in self.sets]}


def read_json(path: Path, what: str) -> dict[str, Any]:
    """A JSON object from a file of a study, or ExprCloneError about ``path`` saying it is not ``what``."""
    try:
        data = parse_json(path.read_text(encoding="utf-8"), str(path))
    except FileNotFoundError:
        raise ExprCloneError(str(path.parent), f"not a study folder (no {path.name}): make one with exprclone study make") from None
    except OSError as e:
        raise ExprCloneError(str(path), f"cannot be read ({e.strerror})") from None
    except UnicodeDecodeError as e:
        raise ExprCloneError(str(path), f"not {what} ({e})") from None
    except ExprCloneError as e:
        raise ExprCloneError(str(path), f"not {what} ({e.problem})") from None
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise ExprCloneError(str(path), f"not {what} of format {FORMAT}")
    return data


def write_json(path: Path, data: dict[str, Any]) -> None:
    """A JSON file written atomically (whole or not at all)."""
    atomic_write(path, lambda f: f.write(json.dumps(data, indent=1).encode()))


def read_study(folder: str | Path) -> Study:
    """The study in ``folder`` (its ``study.json``), checked: ids well formed, each image there.

    Raises
    ------
    ExprCloneError
        About the folder or its ``study.json``.
    """
    folder = Path(folder)
    path = folder / STUDY
    data = read_json(path, "a study's study.json")
    try:
        sets = tuple(Set({role: s["photos"][role] for role in ROLES}, tuple(s["items"])) for s in data["sets"])
    except (KeyError, TypeError) as e:
        raise ExprCloneError(str(path), f"not a study's study.json (no {e})") from None
    study = Study(folder, sets)
    ids = [i for s in sets for i in (*s.photos.values(), *s.items)]
    if not sets or not all(isinstance(i, str) and ID.fullmatch(i) for i in ids):
        raise ExprCloneError(str(path), "not a study's study.json (no sets, or an id that is not 16 hex digits)")
    missing = next((i for i in ids if not study.image(i).is_file()), None)
    if missing is not None:
        raise ExprCloneError(str(study.image(missing)), "missing: the study folder is not whole")
    return study


@dataclass(frozen=True)
class Key:
    """The private part of a study (``key.json``): the methods, each set's name, and which result is which method.

    Attributes
    ----------
    methods : tuple of str
        In the order of the paper's Fig. 11.
    names : tuple of str
        Each set's name (the manifest's ``set`` column, or its row number).
    items : dict of str to (int, str)
        Each result's id to its set (an index into ``names``) and its method.
    """

    methods: tuple[str, ...]
    names: tuple[str, ...]
    items: dict[str, tuple[int, str]]


def read_key(folder: str | Path) -> Key:
    """The key of the study in ``folder``, or ExprCloneError about it."""
    path = Path(folder) / KEY
    data = read_json(path, "a study's key.json")
    try:
        methods, names = tuple(data["methods"]), tuple(str(s["name"]) for s in data["sets"])
        items = {i: (k, str(m)) for k, s in enumerate(data["sets"]) for i, m in s["items"].items()}
    except (KeyError, TypeError, AttributeError) as e:
        raise ExprCloneError(str(path), f"not a study's key.json ({e})") from None
    return Key(methods, names, items)
