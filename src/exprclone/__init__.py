"""exprclone: facial expression cloning with elastic and muscle models.

An implementation of Zhang, Lin et al., "Facial Expression Cloning with Elastic and
Muscle Models" (the E+MD algorithm) and of the other methods it compares (Fig. 11).

>>> import exprclone
>>> exprclone.METHODS
('global', 'local', 'elastic', 'global+eri', 'local+eri', 'elastic+eri', 'e+md')
"""

from .errors import ExprCloneError, ExprCloneWarning
from .methods import METHODS

__all__ = ["METHODS", "CloneResult", "ExprCloneError", "ExprCloneWarning", "clone", "clone_methods"]
__version__ = "0.1.0"


def __getattr__(name: str) -> object:
    """The pipeline (numpy, OpenCV, SciPy) is imported on first use, not with the package."""
    if name in ("clone", "clone_methods", "CloneResult"):
        from . import pipeline

        return getattr(pipeline, name)
    raise AttributeError(f"module 'exprclone' has no attribute {name!r}")
