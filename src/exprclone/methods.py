"""The methods as data: the seven of the paper's Fig. 11 and Song et al.'s of its Figs. 16-17, each a shape stage and
the detail stages after it.

Pure data, kept apart from the pipeline so that the command line can list the methods
without loading numpy, OpenCV and SciPy. A method is looked up by name once, at the door
(:func:`lookup`); everything after that reads its fields, never its name.

>>> [m.name for m in TABLE if m.shape == "elastic"]
['elastic', 'elastic+eri', 'e+md']
>>> lookup(("e+md",))[0].details, lookup(("song",))[0].stage
(('eri', 'md'), 'global@vtc')
"""

from __future__ import annotations

from dataclasses import dataclass

from .errors import ExprCloneError, quoted

#: the shape stages, in the order they are computed (each may use the ones before it).
SHAPES = ("global", "local", "elastic")
#: the ratios a method's details may apply: Liu et al.'s expression ratio image, or Song et al.'s mesh image.
RATIOS = ("eri", "mesh")


@dataclass(frozen=True)
class Method:
    """One method: of Fig. 11, or Song et al.'s.

    Attributes
    ----------
    name : str
    panel : str
        Its letter in Figs. 11-13; empty for a method not in them.
    title : str
        Its name in a person's words, as a page shows it.
    sentence : str
        What it does, in a person's words (a page's, the options' answer over HTTP).
    shape : str
        The landmarks it warps the target to: ``global`` (GI), ``local`` (LI) or
        ``elastic`` (the elastic model's balance of the two, Eqs. 3-8).
    details : tuple of str
        The illumination-detail stages after the warp: first the ratio it applies (:data:`RATIOS`: ``eri``, Liu et
        al.'s expression ratio image, or ``mesh``, Song et al.'s mesh image), then ``md`` (the muscle-distribution
        model weighting it, Eqs. 9-11).
    warp : str or None
        The global warp its shapes start from whatever the options' (one of
        :data:`exprclone.options.GLOBAL_WARPS`: ``vtc`` for Song et al.'s); None: the options' ``global_warp``.
    """

    name: str
    panel: str
    title: str
    sentence: str
    shape: str
    details: tuple[str, ...] = ()
    warp: str | None = None

    @property
    def uses_lambda(self) -> bool:
        """Whether the elastic model, hence the elasticity ratio lambda_k, is used."""
        return self.shape == "elastic"

    @property
    def eri(self) -> bool:
        """Whether Liu et al.'s ERI is applied."""
        return "eri" in self.details

    @property
    def ratio(self) -> str | None:
        """The ratio its details apply (:data:`RATIOS`), None without details; with one, the mouth interior is pasted."""
        return next((d for d in self.details if d in RATIOS), None)

    def key(self, stage: str) -> str:
        """The name under which this method's shape stage ``stage`` (of :data:`SHAPES`) is kept among a prepared clone's
        shapes: ``stage`` on the options' global warp, ``stage@warp`` on its own :attr:`warp`."""
        return stage if self.warp is None else f"{stage}@{self.warp}"

    @property
    def stage(self) -> str:
        """The name its own shape is kept under (:meth:`key`)."""
        return self.key(self.shape)

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
    Method(
        "song",
        "",
        "Song et al.",
        "Song et al.'s: each small patch of the face bends as the source's did, the source's folds and shadows of the"
        " expression carried over as seen on a face halfway between the two people.",
        "global",
        ("mesh",),
        warp="vtc",
    ),
)
#: the methods' names: Fig. 11's in its order, then Song et al.'s.
METHODS = tuple(m.name for m in TABLE)
#: the seven methods of Fig. 11, in its order.
FIG11 = tuple(m.name for m in TABLE if m.panel)
#: the paper's figures that compare methods (``exprclone compare --figure``): Fig. 11 (with Figs. 12-13), the seven
#: methods; Fig. 16, E+MD beside global warping + ERI, Song et al.'s method and elastic + ERI; Fig. 17, Song et al.'s
#: method beside elastic + ERI and E+MD on its global warp; Fig. 19 (with Figs. 20-21), the elastic model on the
#: result of another global warp.
FIGURES = ("11", "16", "17", "19")
BY_NAME = {m.name: m for m in TABLE}


def lookup(names: tuple[str, ...] | list[str]) -> tuple[Method, ...]:
    """The methods named, or ExprCloneError (subject ``method``) for the first unknown name."""
    unknown = [n for n in names if n not in BY_NAME]
    if unknown:
        raise ExprCloneError("method", f"unknown method {quoted(unknown[0])}; choose one of: {', '.join(METHODS)}")
    return tuple(BY_NAME[n] for n in names)
