"""The models a clone needs, each loaded once, lazily, and shared by every call that passes none of its own."""

from __future__ import annotations

import functools

from .eigenface import Eigenfaces
from .landmarks import Detector


@functools.cache
def default_detector() -> Detector:
    """One shared lazily-loaded detector for calls that pass none."""
    return Detector()


@functools.cache
def default_eigenfaces() -> Eigenfaces:
    """The eigenface basis shipped with the package, loaded once."""
    return Eigenfaces.default()
