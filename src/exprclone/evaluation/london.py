"""The London Set (Face Research Lab, DeBruine and Jones 2017) as scored pairs: each person's neutral photo and real smile.

The folder holds ``neutral_front/ID_03.jpg`` and ``smiling_front/ID_08.jpg`` for each
person; a clone of A's smile onto B can be scored against B's own smile.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import ExprCloneError


@dataclass(frozen=True)
class Dataset:
    """The photos of a London-Set-like folder: ``neutral_front/ID_03.jpg`` and ``smiling_front/ID_08.jpg``."""

    root: Path
    ids: tuple[str, ...]

    @classmethod
    def open(cls, root: str | os.PathLike[str]) -> "Dataset":
        root = Path(root)
        ids = tuple(
            sorted(
                p.name[:3] for p in (root / "neutral_front").glob("*_03.jpg") if (root / "smiling_front" / f"{p.name[:3]}_08.jpg").is_file()
            )
        )
        if len(ids) < 2:
            raise ExprCloneError(root, "needs neutral_front/ID_03.jpg and smiling_front/ID_08.jpg for at least two people")
        return cls(root, ids)

    def path(self, face_id: str, smiling: bool) -> str:
        return str(self.root / ("smiling_front" if smiling else "neutral_front") / f"{face_id}_{'08' if smiling else '03'}.jpg")

    def pairs(self, n: int, seed: int) -> list[tuple[str, str]]:
        """``n`` ordered pairs of different people drawn with a fixed seed (0: all of them)."""
        every = [(a, b) for a in self.ids for b in self.ids if a != b]
        if n <= 0 or n >= len(every):
            return every
        pick = np.random.default_rng(seed).choice(len(every), n, replace=False)
        return [every[i] for i in sorted(pick)]
