"""How much of the expression a clone transfers, and where: the strengths' range, the regions, and the specs of the
strengths' options (:class:`~exprclone.options.Options`' ``strength``, ``only``, a region's own, the shading's;
:mod:`exprclone.geometry.weights` applies them)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ..errors import ExprCloneError, quoted
from .specs import Page, Spec, parse_number

#: the regions ``only`` may name (:attr:`exprclone.landmarks.layout.Layout.regions` of the 68-point layout).
REGIONS = ("mouth", "eyes", "brows")
#: the strengths allowed: 0 leaves the target as it is, 1 is the whole expression, 2 twice its motion.
STRENGTH_RANGE = (0.0, 2.0)


def check_strength(value: Any, name: str) -> float:
    """``value`` as a float within :data:`STRENGTH_RANGE`, or ExprCloneError about ``name``."""
    low, high = STRENGTH_RANGE
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not low <= value <= high:
        raise ExprCloneError(name, f"must be a number from {low:g} to {high:g}, got {quoted(value)}")
    return float(value)


def _region_strength(value: Any, name: str) -> float | None:
    return None if value is None else check_strength(value, name)


def strength_spec(help: str, page: Page, check: Callable[[Any, str], Any] = check_strength) -> Spec:
    """The spec of a strength (``strength``, a region's, the shading's): a number within :data:`STRENGTH_RANGE`, a
    slider of the page's strengths."""
    schema = {"minimum": STRENGTH_RANGE[0], "maximum": STRENGTH_RANGE[1]}
    return Spec(help, check, parse_number, float, also=(int,), metavar="S", schema=schema, page=page)


def region_spec(region: str) -> Spec:
    """The spec of a region's own strength (``strength_mouth``...): None follows ``strength``."""
    return strength_spec(
        f"the strength of the {region} alone (motion and shading), from 0 (the target's own {region}) to 2; by default the strength",
        Page(region.capitalize(), f"How much the {region} change, on their own.", "strengths", step=0.1, follows="strength"),
        _region_strength,
    )


def check_regions(only: Any, name: str = "only", regions: tuple[str, ...] = REGIONS) -> tuple[str, ...] | None:
    """``only`` as a tuple of known region names without repeats (a comma-separated string is split), or None for all
    (also when it names every region: the whole face)."""
    if only is None:
        return None
    names = tuple(n.strip() for n in only.split(",")) if isinstance(only, str) else tuple(only)
    bad = [n for n in names if n not in regions]
    if not names or bad:
        raise ExprCloneError(name, f"unknown region {quoted(bad[0] if bad else '')}; choose from: {', '.join(regions)}")
    return None if set(names) == set(regions) else tuple(dict.fromkeys(names))
