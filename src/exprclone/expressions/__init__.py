"""Built-in expressions: source pairs shipped with the package, so that one photo, the target's, is enough.

A clone takes a source person's neutral face and expression; a built-in expression is
such a pair, shipped with its landmarks (:class:`~exprclone.expressions.files.Expression`):

- ``smile``: a prototype smile that belongs to no one, the shape-normalised composites
  (:mod:`exprclone.expressions.composite`) of the neutral and smiling photos of the London
  Set's people whose smile shows teeth, with one real smile's teeth: an open smile;
- ``smile-gentle``: the same of every London Set person: the average smile, lips parted a little;
- ``smile-001``, ``smile-003``, ``smile-126``: the smiles of the sample people
  (:mod:`exprclone.data`);
- ``surprise``, ``sad``, ``angry``: made by the expression editor (:mod:`exprclone.expressions.editor`) from its
  controls on ``smile-gentle``'s neutral composite, whose photo they share.

``tools/build_expressions.py`` makes them from the London Set; their credits are in
``exprclone/data/CREDITS.md``.

>>> names()
('angry', 'sad', 'smile', 'smile-001', 'smile-003', 'smile-126', 'smile-gentle', 'surprise')
>>> smile = load("smile")
>>> smile.expression.points.shape
(68, 2)
"""

from __future__ import annotations

import functools
from pathlib import Path
from typing import Any

import numpy as np

from .. import data
from ..errors import ExprCloneError
from ..pipeline.clone import clone as clone_pair
from ..pipeline.result import CloneResult
from .files import Expression, read

__all__ = ["Expression", "clone", "folder", "load", "names"]

#: the name a built-in expression is asked for by, when none is given.
DEFAULT = "smile"


def folder() -> Path:
    """The folder of the built-in expressions (inside the installed package)."""
    return data.folder() / "expressions"


def names() -> tuple[str, ...]:
    """The built-in expressions' names, sorted."""
    return tuple(sorted(p.stem for p in folder().glob("*.json")))


def load(name: str) -> Expression:
    """A built-in expression by name, or one written to a ``.json`` file (:mod:`exprclone.expressions.files`).

    Raises
    ------
    ExprCloneError
        About ``expression``: an unknown name, with the names there are; or about the
        file, if it cannot be read.
    """
    if name in names():
        return _shipped(name)
    if str(name).endswith(".json") and Path(name).is_file():
        return read(name)
    raise ExprCloneError("expression", f"unknown expression {name!r}; the built-in expressions are: {', '.join(names())}")


@functools.cache
def _shipped(name: str) -> Expression:
    """A built-in expression, read once (its photos are read-only)."""
    return read(folder() / f"{name}.json")


def clone(
    target_neutral: np.ndarray,
    expression: str | Expression = DEFAULT,
    *,
    target_landmarks: np.ndarray | None = None,
    **options: Any,
) -> CloneResult:
    """Put a built-in expression on the target's face: :func:`exprclone.clone` with the expression as the source pair.

    Parameters
    ----------
    target_neutral : ndarray of shape (H, W, 3), uint8 RGB
        The one photo needed.
    expression : str or Expression
        A name of :func:`names` (or a ``.json`` file, :func:`load`), or a loaded expression.
    target_landmarks : ndarray of shape (68, 2), optional
        The target's landmarks; detected if not given.
    **options
        As for :func:`exprclone.clone`: ``options=Options(...)``, or options as keywords (``method``, ``lambda_k``,
        ``strength``, ...: :class:`~exprclone.options.Options`).

    Returns
    -------
    exprclone.CloneResult

    Examples
    --------
    >>> from exprclone import data
    >>> result = clone(data.photo("003"), "smile", strength=0.5)
    >>> result.image.shape
    (1350, 1350, 3)
    """
    chosen = expression if isinstance(expression, Expression) else load(expression)
    landmarks = (chosen.neutral.points, chosen.expression.points, target_landmarks)
    options.setdefault("check_roles", False)  # (the role check judges the source's pair: this one is shipped, not given)
    return clone_pair(chosen.neutral.image, chosen.expression.image, target_neutral, landmarks=landmarks, **options)
