"""The seven methods of the paper's Fig. 11 as data: a shape stage and the detail stages after it.

Pure data, kept apart from the pipeline so that the command line can list the methods
without loading numpy, OpenCV and SciPy. A method is looked up by name once, at the door
(:func:`lookup`); everything after that reads its fields, never its name.

>>> [m.name for m in TABLE if m.shape == "elastic"]
['elastic', 'elastic+eri', 'e+md']
>>> lookup(("e+md",))[0].details
('eri', 'md')
"""

from __future__ import annotations

from dataclasses import dataclass

from .errors import ExprCloneError, quoted

#: the shape stages, in the order they are computed (each may use the ones before it).
SHAPES = ("global", "local", "elastic")


@dataclass(frozen=True)
class Method:
    """One method of Fig. 11.

    Attributes
    ----------
    name : str
    panel : str
        Its letter in Figs. 11-13.
    title : str
        Its name in a person's words, as a page shows it.
    sentence : str
        What it does, in a person's words (a page's, the options' answer over HTTP).
    shape : str
        The landmarks it warps the target to: ``global`` (GI), ``local`` (LI) or
        ``elastic`` (the elastic model's balance of the two, Eqs. 3-8).
    details : tuple of str
        The illumination-detail stages after the warp: ``eri`` (Liu et al.'s expression
        ratio image), ``md`` (the muscle-distribution model weighting it, Eqs. 9-11).
    """

    name: str
    panel: str
    title: str
    sentence: str
    shape: str
    details: tuple[str, ...] = ()

    @property
    def uses_lambda(self) -> bool:
        """Whether the elastic model, hence the elasticity ratio lambda_k, is used."""
        return self.shape == "elastic"

    @property
    def eri(self) -> bool:
        """Whether the ERI is applied (and, with it, the mouth interior pasted)."""
        return "eri" in self.details

    @property
    def md(self) -> bool:
        """Whether the ERI is weighted by the MD model's mask."""
        return "md" in self.details


#: what the detail stages add, said once for the sentences below.
_SHADING = "with the source's folds and shadows of the expression carried over"

TABLE = (
    Method(
        "global",
        "a",
        "global warping",
        "The source's motion, turned and scaled to fit the target's face as one piece: each feature moves as the source's did.",
        "global",
    ),
    Method(
        "local",
        "b",
        "local re-shaping",
        "Each feature (mouth, eyes, brows) takes the shape the source's took: exact shapes, which may sit oddly on another face.",
        "local",
    ),
    Method(
        "elastic",
        "c",
        "elastic model",
        "A balance of the two: each feature is pulled towards its own new shape, the face around it holding it like springs.",
        "elastic",
    ),
    Method("global+eri", "d", "global + ERI", f"Global warping, {_SHADING}.", "global", ("eri",)),
    Method("local+eri", "e", "local + ERI", f"Local re-shaping, {_SHADING}.", "local", ("eri",)),
    Method("elastic+eri", "f", "elastic + ERI", f"The elastic model, {_SHADING}.", "elastic", ("eri",)),
    Method(
        "e+md",
        "g",
        "E+MD",
        f"The paper's own: the elastic model, {_SHADING} where the face's muscles move and nowhere else.",
        "elastic",
        ("eri", "md"),
    ),
)
#: the methods' names, in the order of Fig. 11.
METHODS = tuple(m.name for m in TABLE)
#: the paper's figures that compare methods (``exprclone compare --figure``): Fig. 11 (with Figs. 12-13), the seven
#: methods; Fig. 19 (with Figs. 20-21), the elastic model on the result of another global warp.
FIGURES = ("11", "19")
BY_NAME = {m.name: m for m in TABLE}


def lookup(names: tuple[str, ...] | list[str]) -> tuple[Method, ...]:
    """The methods named, or ExprCloneError (subject ``method``) for the first unknown name."""
    unknown = [n for n in names if n not in BY_NAME]
    if unknown:
        raise ExprCloneError("method", f"unknown method {quoted(unknown[0])}; choose one of: {', '.join(METHODS)}")
    return tuple(BY_NAME[n] for n in names)
