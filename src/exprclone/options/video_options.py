"""The options of a driven video beyond its clone's: how a performance drives the portrait (:class:`Driving`) and how
the result is framed (:class:`Framing`), declared as the clone's are (:mod:`exprclone.options.specs`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..errors import ExprCloneError, quoted
from .specs import Choice, Chosen, Page, Spec, option, switch

#: the words ``neutral_frame`` may be besides a frame number: the frame whose mouth is most closed, or the first.
NEUTRAL_WORDS = ("closed", "first")


def _neutral_frame(value: Any, name: str) -> int | str:
    if value in NEUTRAL_WORDS or (isinstance(value, int) and not isinstance(value, bool) and value >= 0):
        return value
    raise ExprCloneError(name, f"must be closed, first or a frame number >= 0, got {quoted(value)}")


def _frame_text(text: str) -> int | str:
    """``closed``, ``first`` or a frame number, as a text gives it."""
    if text in NEUTRAL_WORDS:
        return text
    if not text.isdigit():
        raise ValueError(f"expected closed, first or a frame number >= 0, got {quoted(text)}")
    return int(text)


#: a video's options that are not a clone's sit in the page's video section.
_VIDEO = "video"


@dataclass(frozen=True, repr=False)
class Driving(Chosen):
    """How a performance drives the portrait, beyond the clone's options (:func:`exprclone.drive.prepare`).

    Examples
    --------
    >>> Driving().neutral_frame, Driving.from_text({"neutral_frame": "12"}).neutral_frame
    ('closed', 12)
    """

    neutral_frame: int | str = option(
        NEUTRAL_WORDS[0],
        Spec(
            "the frame (from 0) with the source's neutral face; closed: the one whose mouth is most closed (expression"
            " motion is measured from it, so parted lips there would make every closing a negative opening); first: the"
            " first frame with a face",
            _neutral_frame,
            _frame_text,
            also=(int,),
            metavar="N|closed|first",
            schema={"pattern": "^(closed|first|[0-9]+)$"},
            surfaces=frozenset({"cli", "form"}),
            page=Page(
                "Neutral face",
                "The frame of the video whose face is taken as the person at rest; every expression is measured from it.",
                _VIDEO,
                (Choice(NEUTRAL_WORDS[0], "frame with the most closed mouth"), Choice(NEUTRAL_WORDS[1], "first frame with a face")),
            ),
        ),
    )
    lambda_per_frame: bool = option(
        False,
        switch(
            "choose lambda_k by the DB metric on every frame (slower)",
            surfaces=frozenset({"cli", "form"}),
            page=Page("λk chosen on every frame (slower)", "The balance is chosen again for each frame's expression.", "method"),
        ),
    )
    smooth: bool = option(
        True,
        switch(
            "smooth the landmarks over time; false uses the raw per-frame fits",
            "use the landmarks as fitted on each frame, not smoothed over time (they may flicker)",
            flag="--no-smooth",
            surfaces=frozenset({"cli", "form"}),
            page=Page("smooth motion", "The face's points are smoothed over time, so that they do not flicker.", _VIDEO),
        ),
    )
    head_motion: bool = option(
        False,
        switch(
            "carry the source's head motion over (a similarity of the whole frame)",
            surfaces=frozenset({"cli", "form"}),
            page=Page("head motion", "The portrait's head turns and moves as the person's in the video does.", _VIDEO),
        ),
    )


#: the sizes a video may be asked for: the portrait's longest side, pixels.
SIZE_RANGE = (16, 4096)
#: the sizes a page offers.
PAGE_SIZES = (256, 512, 1024)


def _size(value: Any, name: str) -> int | None:
    low, high = SIZE_RANGE
    if value is not None and (isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high):
        raise ExprCloneError(name, f"must be from {low} to {high} pixels, or full (the portrait's own size), got {quoted(value)}")
    return value


def _size_text(text: str) -> int | None:
    """A size in pixels, or ``full``: the portrait's own."""
    if text == "full":
        return None
    if not text.isdigit():
        raise ValueError(f"expected a number of pixels or full, got {quoted(text)}")
    return int(text)


@dataclass(frozen=True, repr=False)
class Framing(Chosen):
    """How a driven video is framed (:mod:`exprclone.drive.framing`): the portrait's size, the driving video beside it.

    Examples
    --------
    >>> Framing().size, Framing.from_text({"size": "full", "side_by_side": "true"})
    (512, Framing(size=None, side_by_side=True))
    """

    size: int | None = option(
        512,
        Spec(
            "the portrait's longest side in the output, pixels (full: its own size)",
            _size,
            _size_text,
            int,
            metavar="PIXELS",
            schema={"minimum": SIZE_RANGE[0], "maximum": SIZE_RANGE[1]},
            surfaces=frozenset({"cli", "form", "json"}),
            page=Page(
                "Size", "The portrait's longest side in the result, in pixels.", _VIDEO, tuple(Choice(str(s), str(s)) for s in PAGE_SIZES)
            ),
        ),
    )
    side_by_side: bool = option(
        False,
        switch(
            "the driving video beside the result",
            surfaces=frozenset({"cli", "form"}),
            page=Page("side by side", "The video of the person beside the portrait that follows it.", _VIDEO),
        ),
    )
