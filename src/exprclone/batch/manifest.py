"""What a batch job is asked to do: rows of (source neutral, source expression, target neutral, output), checked at the door.

A manifest is a CSV file with the header ``source_neutral,source_expression,target_neutral,output``
and optional columns of the clone's options (:data:`OPTIONAL`: ``method``, ``lambda``, ``strength``, ...),
each a row's own value of that option where it is not empty; its paths are relative to its own folder
(outputs to ``--out`` when given). The other form puts one expression on every portrait
of a folder or glob, writing ``OUT/<target name>.png``. A manifest that cannot be used
(unreadable, columns missing, two rows writing the same output, an output that is one of
the inputs, outside the output folder or not an image file) stops the job before any work (exit status 2); a bad value in one row (an
unknown method) only fails that row.
"""

from __future__ import annotations

import csv
import glob
import os
from dataclasses import dataclass
from pathlib import Path

from ..errors import ExprCloneError, quoted
from ..io.images import PHOTO_SUFFIXES
from ..options import Options, key, offered
from ..roles import ROLES

#: the columns every manifest has.
COLUMNS = (*ROLES, "output")
#: the columns a manifest may have, overriding the job's options row by row: those of the options offered to manifests.
OPTIONAL = tuple(key(Options, name) for name in offered(Options, "manifest"))


@dataclass(frozen=True)
class Row:
    """One clone of a batch job: its number in the manifest (from 1), its files, and the texts of its own options
    (:data:`OPTIONAL` columns that are not empty, by column), read with the job's (:meth:`exprclone.options.Options.from_text`)."""

    number: int
    source_neutral: str
    source_expression: str
    target_neutral: str
    output: str
    cells: tuple[tuple[str, str], ...] = ()

    @property
    def photos(self) -> tuple[str, str, str]:
        return self.source_neutral, self.source_expression, self.target_neutral


def read_manifest(path: str, out: str | None = None) -> list[Row]:
    """The rows of a manifest CSV (see the module's notes), checked (:func:`check_rows`)."""
    records = read_records(path, COLUMNS)
    outputs = Path(os.path.abspath(out if out else Path(path).parent))
    return check_rows([_row(k, r, path, outputs) for k, r in enumerate(records, 1)], path)


def _row(number: int, record: dict[str, str], path: str, outputs: Path) -> Row:
    """One manifest row: its photos in the folder of the manifest at ``path``, its output in ``outputs``, its own options
    if given."""
    cells = tuple((column, record[column]) for column in OPTIONAL if record.get(column))
    return Row(number, *photos_of(record, path), output_of(record["output"], outputs, path, number), cells)


def output_of(name: str, outputs: Path, path: str, number: int) -> str:
    """Row ``number``'s output file ``name`` in the folder ``outputs``: an image file (:data:`PHOTO_SUFFIXES`) inside it
    (its links followed), else ExprCloneError about the manifest at ``path``; its path as given, made absolute."""
    output = Path(os.path.abspath(outputs / name))
    if not Path(os.path.realpath(output)).is_relative_to(os.path.realpath(outputs)):
        raise ExprCloneError(path, f"row {number}'s output {quoted(name)} is outside the output folder {outputs}")
    if output.suffix.lower() not in PHOTO_SUFFIXES:
        raise ExprCloneError(path, f"row {number}'s output {quoted(name)} is no image file ({', '.join(sorted(PHOTO_SUFFIXES))})")
    return str(output)


def read_records(path: str, columns: tuple[str, ...]) -> list[dict[str, str]]:
    """The records of a manifest CSV, each a dict of column to its text (stripped; ``""`` for a cell left out).

    Raises
    ------
    ExprCloneError
        About ``path``: it cannot be read, is not a CSV file, has none of one of ``columns``,
        or a row leaves one of them empty or has a NUL character in one.
    """
    try:
        with open(path, newline="", encoding="utf-8-sig") as f:
            reader = csv.DictReader(f)
            header = reader.fieldnames or []
            missing = [c for c in columns if c not in header]
            if missing:
                raise ExprCloneError(path, f"the manifest has no column {', '.join(missing)} (it needs {','.join(columns)})")
            records = [{k: (v or "").strip() for k, v in r.items() if isinstance(k, str)} for r in reader]
    except OSError as e:
        raise ExprCloneError(path, f"cannot be read ({e.strerror})") from None
    except (UnicodeDecodeError, csv.Error) as e:
        raise ExprCloneError(path, f"not a CSV manifest ({e})") from None
    for k, record in enumerate(records, 1):
        empty = [c for c in columns if not record[c]]
        if empty:
            raise ExprCloneError(path, f"row {k} has no {', '.join(empty)}")
        if any("\0" in record[c] for c in columns):
            raise ExprCloneError(path, f"row {k} has a NUL character in a path")
    return records


def photos_of(record: dict[str, str], path: str) -> tuple[str, str, str]:
    """A record's three photos (in :data:`exprclone.roles.ROLES`' order), as paths relative to the folder of the manifest at
    ``path``, made absolute (links kept: the report names the paths given)."""
    folder = Path(path).parent
    source_neutral, source_expression, target_neutral = (os.path.abspath(folder / record[role]) for role in ROLES)
    return source_neutral, source_expression, target_neutral


def rows_for_targets(source_neutral: str, source_expression: str, targets: str, out: str) -> list[Row]:
    """One expression on every portrait of a folder (or a glob), written to ``out/<target name>.png``."""
    if os.path.isdir(targets):
        found = sorted(str(p) for p in Path(targets).iterdir() if p.suffix.lower() in PHOTO_SUFFIXES)
    else:
        found = sorted(p for p in glob.glob(targets) if Path(p).suffix.lower() in PHOTO_SUFFIXES)
    if not found:
        raise ExprCloneError(targets, "no photos (.jpg, .png, ...) found")
    neutral, expression = (os.path.abspath(p) for p in (source_neutral, source_expression))
    rows = [
        Row(k, neutral, expression, os.path.abspath(t), os.path.abspath(Path(out) / f"{Path(t).stem}.png")) for k, t in enumerate(found, 1)
    ]
    return check_rows(rows, targets)


def check_rows(rows: list[Row], name: str) -> list[Row]:
    """The rows, unless two write the same output or an output is one of the inputs (ExprCloneError about ``name``)."""
    inputs = {os.path.realpath(p) for row in rows for p in row.photos}
    seen: dict[str, int] = {}
    for row in rows:
        output = os.path.realpath(row.output)
        if output in seen:
            raise ExprCloneError(name, f"rows {seen[output]} and {row.number} both write {row.output}")
        if output in inputs:
            raise ExprCloneError(name, f"row {row.number} would overwrite an input: {row.output}")
        seen[output] = row.number
    return rows
