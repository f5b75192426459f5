"""exprclone: facial expression cloning with elastic and muscle models.

An implementation of Zhang, Lin et al., "Facial Expression Cloning with Elastic and
Muscle Models" (the E+MD algorithm) and of the other methods it compares (Fig. 11).

>>> import exprclone
>>> exprclone.METHODS
('global', 'local', 'elastic', 'global+eri', 'local+eri', 'elastic+eri', 'e+md')
"""

from .clone import METHODS, CloneResult, clone, clone_methods
from .errors import ExprCloneError, ExprCloneWarning

__all__ = ["METHODS", "CloneResult", "ExprCloneError", "ExprCloneWarning", "clone", "clone_methods"]
__version__ = "0.1.0"
