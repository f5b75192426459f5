"""Documents that cross the project's edge: JSON from outside parsed with a bound, and CSV cells a spreadsheet reads
safely.

Python's parser recurses once per nesting level, and a text of a few thousand ``[`` under any
size limit ends it in a RecursionError. Every JSON text the project reads from outside is first
scanned for how deep it nests (:func:`json_depth`, linear, no parsing) and refused past
:data:`MAX_DEPTH`, in one line.

A CSV file the project writes (a batch report, a study's results) holds text that came from
outside (file names, a study's set names); a spreadsheet takes a cell that begins with ``=``,
``+``, ``-`` or ``@`` for a formula, so such a cell is written with a leading apostrophe
(:func:`csv_cell`), as OWASP advises.
"""

from __future__ import annotations

import json
import re
from typing import Any

import numpy as np

from ..errors import ExprCloneError

#: the deepest nesting any of the project's documents has (a study's ratings: 4) with room to spare.
MAX_DEPTH = 16
_JSON_STRING = re.compile(r'"(?:[^"\\]|\\.)*"')


def json_depth(text: str) -> int:
    """How deep the brackets of a JSON text nest, strings aside (without parsing it: a linear scan).

    Examples
    --------
    >>> json_depth('{"landmarks": [[1, 2], [3, 4]], "note": "[[["}')
    3
    """
    brackets = np.frombuffer(_JSON_STRING.sub("", text).encode("ascii", "replace"), np.uint8)
    steps = np.isin(brackets, (ord("["), ord("{"))).astype(np.int64) - np.isin(brackets, (ord("]"), ord("}")))
    return int(np.cumsum(steps).max(initial=0))


def csv_cell(value: object) -> object:
    """``value`` as a CSV cell a spreadsheet will not run: text that begins like a formula gets a leading ``'``.

    >>> csv_cell("=HYPERLINK(1)"), csv_cell("Fig. 11"), csv_cell(-0.5)
    ("'=HYPERLINK(1)", 'Fig. 11', -0.5)
    """
    return f"'{value}" if isinstance(value, str) and value[:1] in FORMULA else value


#: what a spreadsheet takes a cell for a formula by, at its start.
FORMULA = ("=", "+", "-", "@", "\t", "\r")


def parse_json(text: str, subject: str, max_depth: int = MAX_DEPTH, **options: Any) -> Any:
    """The document of a JSON text, or ExprCloneError about ``subject``: nested deeper than ``max_depth`` (refused before
    parsing), or not JSON. ``options`` go to :func:`json.loads` (``parse_int=float``).

    Examples
    --------
    >>> parse_json('{"a": [1]}', "message")
    {'a': [1]}
    >>> parse_json("[" * 4000, "message")
    Traceback (most recent call last):
    ...
    exprclone.errors.ExprCloneError: message: not JSON of this kind: nested 4000 deep (at most 16)
    """
    depth = json_depth(text)
    if depth > max_depth:
        raise ExprCloneError(subject, f"not JSON of this kind: nested {depth} deep (at most {max_depth})")
    try:
        return json.loads(text, **options)
    except json.JSONDecodeError as e:
        raise ExprCloneError(subject, f"not JSON ({e.msg} at line {e.lineno}, column {e.colno})") from None
    except (ValueError, RecursionError) as e:  # a number too long to convert, or nesting the scan could not see
        raise ExprCloneError(subject, f"not JSON ({type(e).__name__})") from None
