"""The full data sets' folder, as the tools, the benchmarks and ``exprclone evaluate`` take it (``--data``).

The London Set's 72 people and the GRID clips do not ship (the samples inside the package
are three people and one clip): they are found where the tests find them, in
``$EXPRCLONE_DATA``, else in ``../shared/data`` beside a checkout of the repository, whatever
folder a tool is run from; a ``--data`` that is not a folder is a one-line error before any work.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

#: where the data sets are when neither ``--data`` nor ``$EXPRCLONE_DATA`` says: beside the checkout (this file is
#: ``src/exprclone/data/sets.py`` in it).
BESIDE = Path(__file__).resolve().parents[4] / "shared" / "data"


def default(*parts: str) -> Path:
    """The data folder (or ``parts`` inside it, such as ``"london"``) when ``--data`` is not given."""
    return Path(os.environ.get("EXPRCLONE_DATA", BESIDE)).joinpath(*parts)


def folder(text: str) -> Path:
    """``--data``'s type: the path, when it is a folder."""
    if not Path(text).is_dir():
        raise argparse.ArgumentTypeError(f"{text}: no such folder (give --data, or set $EXPRCLONE_DATA)")
    return Path(text)


def add_argument(parser: argparse.ArgumentParser, *parts: str, holds: str = "") -> None:
    """Add ``--data`` to ``parser``: a folder, by default :func:`default` of ``parts``; ``holds`` says what it holds."""
    inside = "/".join(parts)
    where = f"$EXPRCLONE_DATA/{inside}, else ../shared/data/{inside}" if parts else "$EXPRCLONE_DATA, else ../shared/data"
    about = f"{holds or 'the data folder'} "
    parser.add_argument("--data", type=folder, default=str(default(*parts)), help=f"{about}(default: {where} beside the checkout)")
