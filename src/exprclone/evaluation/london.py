"""The people whose photos score the clones: each person's neutral photo and real expression, in a folder.

Two layouts of the folder are read:

- the London Set's (Face Research Lab, DeBruine and Jones 2017): ``neutral_front/ID_03.jpg``
  and ``smiling_front/ID_08.jpg`` for each person, as it is downloaded;
- one's own: ``neutral/NAME.EXT`` and ``expression/NAME.EXT``, one person's two photos under one
  name (any image extension: ``neutral/anna.jpg`` and ``expression/anna.png``), every person
  showing the same kind of expression.

A clone of A's expression onto B is scored against B's own expression.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import ExprCloneError
from ..io.images import PHOTO_SUFFIXES

#: the London Set's folders and file name endings, neutral then smiling.
LONDON = (("neutral_front", "_03"), ("smiling_front", "_08"))
#: one's own folders, neutral then expression.
OWN = ("neutral", "expression")


@dataclass(frozen=True, eq=False)
class Dataset:
    """The people of a folder in either layout (the module's notes): their ids, and each one's two photos."""

    root: Path
    photos: dict[str, tuple[str, str]]

    @property
    def ids(self) -> tuple[str, ...]:
        """The people, sorted."""
        return tuple(sorted(self.photos))

    @classmethod
    def open(cls, root: str | os.PathLike[str]) -> Dataset:
        """The people of ``root`` who have both photos; ExprCloneError if fewer than two have."""
        root = Path(root)
        london = {p.name[:3]: p for p in (root / LONDON[0][0]).glob(f"*{LONDON[0][1]}.jpg")}
        photos = {
            face_id: (str(neutral), str(smiling))
            for face_id, neutral in london.items()
            if (smiling := root / LONDON[1][0] / f"{face_id}{LONDON[1][1]}.jpg").is_file()
        }
        if not photos:
            found = [{p.stem: p for p in sorted((root / folder).glob("*")) if p.suffix.lower() in PHOTO_SUFFIXES} for folder in OWN]
            photos = {name: (str(found[0][name]), str(found[1][name])) for name in found[0] if name in found[1]}
        if len(photos) < 2:
            raise ExprCloneError(
                root,
                "needs two photos for at least two people: neutral/NAME.jpg and expression/NAME.jpg (one name a person),"
                " or the London Set's neutral_front/ID_03.jpg and smiling_front/ID_08.jpg",
            )
        return cls(root, photos)

    def path(self, face_id: str, smiling: bool) -> str:
        """The person's photo: their expression if ``smiling``, else their neutral face."""
        return self.photos[face_id][int(smiling)]

    def folds(self, k: int, seed: int) -> tuple[tuple[str, ...], ...]:
        """The people dealt into ``k`` folds of (nearly) equal size, in an order drawn with a fixed seed.

        >>> Dataset(Path("."), {str(i): ("", "") for i in range(7)}).folds(3, 0)
        (('2', '6', '1'), ('4', '5'), ('3', '0'))
        """
        order = [self.ids[i] for i in np.random.default_rng(seed).permutation(len(self.ids))]
        return tuple(tuple(order[f::k]) for f in range(k))

    def pairs(self, n: int, seed: int, folds: tuple[tuple[str, ...], ...] | None = None) -> list[tuple[str, str]]:
        """``n`` ordered pairs of different people drawn with a fixed seed (0: all of them); within ``folds`` if given
        (both people of a pair in one fold)."""
        together = {p: f for f in folds or (self.ids,) for p in f}
        every = [(a, b) for a in self.ids for b in self.ids if a != b and together[a] == together[b]]
        if n <= 0 or n >= len(every):
            return every
        pick = np.random.default_rng(seed).choice(len(every), n, replace=False)
        return [every[i] for i in sorted(pick)]
