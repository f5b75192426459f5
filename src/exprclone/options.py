"""How a clone is made beyond its method: the global warp, the image warp, how much of the expression is transferred, retargeting.

Pure data, like :mod:`exprclone.methods`: the command line lists the choices without
loading numpy. An :class:`Options` value is handed to the :class:`~exprclone.cloner.Cloner`
(checked at the door by :func:`exprclone.checks.check_options`); it is not a method of
Fig. 11, but changes how every method's stages run:

- ``global_warp``: which global warping gives GI, the shape every other stage starts
  from. ``similarity`` is the paper's (Liu et al.: the source's motion rotated and
  scaled into the target by one similarity); ``rbf`` carries each landmark's motion by
  the local Jacobian of a radial-basis-function map between the two neutral faces (Seol
  and Lewis, the paper's Figs. 19-20; :func:`exprclone.global_warp.rbf_landmarks`).
- ``global_landmarks``: GI given from outside, the result of any other method, which the
  elastic model then refines (the paper's Fig. 21).
- ``image_warp``: how the photo follows its landmarks: ``mesh``, the piecewise-affine
  warp over the Delaunay mesh (the paper's), or ``tps``, a thin-plate spline
  (Bookstein), smooth across the mesh's triangle edges (:mod:`exprclone.tps`).
- ``strength`` and ``only`` (not in the paper): how much of the expression is
  transferred, and where (:mod:`exprclone.transfer`).
- ``retarget`` (not in the paper; on by default): the source's motion is cleaned of the
  landmark fitter's scatter and of its lopsided part before any global warp, and local
  re-shaping aims at the target's own organs moved by the source instead of the source's
  organs (:mod:`exprclone.retarget`). ``retarget=False`` runs the paper's global and local
  stages as they are.

>>> Options().global_stage, Options(global_warp="rbf").global_stage
('similarity', 'rbf')
>>> Options().full, Options(strength=0.5).full, Options(only=("mouth",)).full
(True, False, False)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np

#: the global warps (``global_warp``); the first is the default, the paper's.
GLOBAL_WARPS = ("similarity", "rbf")
#: the global stage's name when GI is given (``global_landmarks``).
GIVEN = "given"
#: the image warps (``image_warp``); the first is the default, the paper's.
IMAGE_WARPS = ("mesh", "tps")
#: the regions ``only`` may name (:attr:`exprclone.layout.Layout.regions` of the 68-point layout).
REGIONS = ("mouth", "eyes", "brows")
#: the strengths allowed: 0 leaves the target as it is, 1 is the whole expression, 2 twice its motion.
STRENGTH_RANGE = (0.0, 2.0)


@dataclass(frozen=True, eq=False)
class Options:
    """The options of one :class:`~exprclone.cloner.Cloner` (see the module's notes).

    Attributes
    ----------
    global_warp : str
        One of :data:`GLOBAL_WARPS`.
    global_landmarks : ndarray of shape (N, 2) or None
        GI given from outside, in the target photo; replaces ``global_warp``.
    image_warp : str
        One of :data:`IMAGE_WARPS`.
    strength : float
        Within :data:`STRENGTH_RANGE`.
    only : tuple of str or None
        Regions (:data:`REGIONS`) whose motion alone is transferred; None for all.
    retarget : bool
        Make the source's motion the target's before the global and local stages
        (:mod:`exprclone.retarget`); False: the paper's stages.

    Parameters
    ----------
    global_warp, global_landmarks, image_warp, strength, only, retarget
        As the attributes. :func:`exprclone.clone`, :class:`~exprclone.cloner.Cloner` and
        :func:`exprclone.drive.prepare` take them as ``options=Options(...)`` or as keywords
        (``strength=0.5``), not both, and check them (:func:`exprclone.checks.check_options` raises
        :class:`~exprclone.ExprCloneError` naming the option).

    See Also
    --------
    exprclone.clone : whose result keeps its options (``result.options``).

    Examples
    --------
    >>> Options(strength=0.5, only=("mouth",))
    Options(global_warp='similarity', global_landmarks=None, image_warp='mesh', strength=0.5, only=('mouth',), retarget=True)
    >>> Options(global_warp="rbf").global_stage, Options(strength=0.5).full
    ('rbf', False)
    """

    global_warp: str = GLOBAL_WARPS[0]
    global_landmarks: np.ndarray | None = None
    image_warp: str = IMAGE_WARPS[0]
    strength: float = 1.0
    only: tuple[str, ...] | None = None
    retarget: bool = True

    @property
    def global_stage(self) -> str:
        """The global warp that gives GI: :data:`GIVEN` when its landmarks are given, else ``global_warp``."""
        return GIVEN if self.global_landmarks is not None else self.global_warp

    @property
    def full(self) -> bool:
        """Whether the whole expression is transferred everywhere (strength 1, every region), as in the paper."""
        return self.strength == 1 and self.only is None
