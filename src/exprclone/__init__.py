"""exprclone: facial expression cloning with elastic and muscle models.

An implementation of Zhang, Lin et al., "Facial Expression Cloning with Elastic and
Muscle Models" (the E+MD algorithm) and of the other methods it compares (Fig. 11, and Song et al.'s of Figs. 16-17).

>>> import exprclone
>>> exprclone.METHODS
('global', 'local', 'elastic', 'global+eri', 'local+eri', 'elastic+eri', 'e+md', 'song')
>>> exprclone.Options(method="global", strength=0.5)
Options(method='global', strength=0.5)
"""

from typing import TYPE_CHECKING

from .errors import ExprCloneError, ExprCloneWarning
from .methods import METHODS
from .options import Options

if TYPE_CHECKING:  # what type checkers see; at run time the pipeline is imported on first use (__getattr__)
    from .expressions.editor import edit
    from .pipeline.clone import clone, clone_methods, prepare
    from .pipeline.cloner import Cloner, Prepared
    from .pipeline.result import CloneResult, FaceResult

__all__ = [
    "METHODS",
    "CloneResult",
    "Cloner",
    "ExprCloneError",
    "ExprCloneWarning",
    "FaceResult",
    "Options",
    "Prepared",
    "clone",
    "clone_methods",
    "edit",
    "prepare",
]
__version__ = "0.1.0"

#: the names of the pipeline's face, imported on first use (numpy, OpenCV and SciPy with them).
LAZY = ("clone", "clone_methods", "prepare", "CloneResult", "Cloner", "FaceResult", "Prepared")


def __getattr__(name: str) -> object:
    """The pipeline (numpy, OpenCV, SciPy) is imported on first use, not with the package."""
    if name in LAZY:
        from .pipeline import clone

        return getattr(clone, name)
    if name == "edit":  # the expression editor (exprclone.expressions.editor)
        from .expressions.editor import edit

        return edit
    raise AttributeError(f"module 'exprclone' has no attribute {name!r}")
