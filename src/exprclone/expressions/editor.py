"""The expression editor: one photo, named controls (:mod:`exprclone.expressions.controls`), rendered by the clone's stages.

An edit is a clone whose GI is given (the paper's Fig. 21: GI from outside, here from the controls):

1. the photo's landmarks are moved by the controls' motions, each times its value, summed in the face's own frame
   and brought back to the photo's pixels (:meth:`Editor.landmarks`; an eye closes no further than closed,
   :func:`~exprclone.expressions.controls.limit_lids`);
2. those landmarks are GI of a clone onto the photo whose source is a built-in expression's pair of photos
   (:data:`SHADING`, the prototype smile): E+MD with ``lambda_k`` 0, so that the final landmarks are GI (the elastic
   model keeps the whole face's motion alone); FI is the photo warped to them;
3. the smile's own folds and shadows (its ERI, weighted by the MD model) come with the ``smile`` control, as much as
   its value (``strength_shading`` times it): the smile is the one control with a real photo of its motion; any other
   control's motion comes without shading. Where the edit opens the mouth, the smile's mouth interior (teeth) is
   pasted into it, as a clone pastes the source's.

The photo's two neutral faces are prepared once (:func:`exprclone.pipeline.request.pair`: a
:class:`~exprclone.pipeline.cloner.Cloner`); each set of values then costs the shape stages with GI given and a render:
tens of milliseconds at a preview's size, so that the page's sliders re-render as they move.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import numpy as np

from ..geometry.expression_shape import ExpressionShape, in_pixels, normalised
from ..options import Options
from ..pipeline import request as door
from ..pipeline.cloner import Cloner
from ..pipeline.request import Landmarks, Request
from ..pipeline.result import CloneResult
from . import load
from .controls import CONTROLS, Motions, check_values, default_motions, limit_lids

#: the built-in expression whose photos give an edit the smile's shading and an opened mouth's interior.
SHADING = "smile"
#: the method an edit renders by: E+MD, its lambda_k 0 (the final landmarks are GI).
METHOD, LAMBDA_K = "e+md", 0.0


class Editor:
    """One photo prepared for edits: :meth:`render` gives it with any values of the controls.

    Parameters
    ----------
    cloner : Cloner
        The built-in expression's neutral face (:data:`SHADING`) and the photo's, prepared (:meth:`of` makes it at the
        door); its options are the edit's (E+MD, lambda_k 0).
    expression : tuple of ndarray
        The built-in expression's photo and its landmarks.
    motions : Motions, optional
        The controls' motions; the shipped ones if None.
    model : ExpressionShape, optional
        How a face smiles (the smile control); the shipped one if None.

    Attributes
    ----------
    neutral : ndarray of shape (N, 2)
        The photo's landmarks (pixels).
    at_one : dict of str to ndarray of shape (N, 2)
        Each control's motion at 1 on this face, normalised.

    Examples
    --------
    >>> from exprclone import data
    >>> editor = Editor.of(request(data.photo("003")))
    >>> moved = editor.landmarks({"brows_up": 1.0}) - editor.neutral
    >>> bool(moved[17:27, 1].mean() < -5), bool(np.abs(moved[48:68]).max() == 0)
    (True, True)
    """

    def __init__(
        self,
        cloner: Cloner,
        expression: tuple[np.ndarray, np.ndarray],
        motions: Motions | None = None,
        model: ExpressionShape | None = None,
    ) -> None:
        self.cloner, self.expression = cloner, expression
        layout = cloner.faces.layout
        self.neutral = cloner.faces.t_neu
        self.normalised = normalised(self.neutral, self.neutral, layout)
        chosen = motions or default_motions()
        self.at_one = {c.name: chosen.motion(c.name, self.normalised, layout, model) for c in CONTROLS}

    @classmethod
    def of(cls, request: Request, motions: Motions | None = None, model: ExpressionShape | None = None) -> Editor:
        """The editor of the request's target photo, the request's source photos giving the shading and the mouth's
        interior (:data:`SHADING`'s, as :func:`request` makes them): its two neutral faces made at the door
        (:func:`exprclone.pipeline.request.pair`; the photo's largest face, unless its landmarks are given), with the
        request's options made the edit's (E+MD, lambda_k 0)."""
        options = dataclasses.replace(request.options, method=METHOD, lambda_k=LAMBDA_K, global_landmarks=None, global_warp="similarity")
        made = dataclasses.replace(request, options=options)
        se = made.source_expression
        assert se is not None and se.points is not None, "a built-in expression's photos, with their landmarks"
        return cls(door.pair(made), (se.image, se.points), motions, model if model is not None else options.expression_shape)

    def landmarks(self, values: Mapping[str, float]) -> np.ndarray:
        """The photo's landmarks edited (pixels): each control's motion times its value (:func:`check_values`), summed
        in the face's frame, the eyes closed no further than closed."""
        checked = check_values(values)
        layout = self.cloner.faces.layout
        total = sum((v * self.at_one[name] for name, v in checked.items()), np.zeros_like(self.neutral))
        return self.neutral + in_pixels(self.neutral, limit_lids(self.normalised, total, layout), layout)

    def render(self, values: Mapping[str, float]) -> CloneResult:
        """The photo with the controls at ``values`` (name to a number from 0 to 1; those not given at 0): E+MD with
        the edited landmarks as GI, the smile's shading as much as its value (see the module's notes)."""
        checked = check_values(values)
        cloner = self.cloner.changed(global_landmarks=self.landmarks(checked))
        shading = cloner.options.strength_shading * checked.get("smile", 0.0)
        (result,) = cloner.prepare(*self.expression).render(strength_shading=shading).values()
        return dataclasses.replace(result, options=dataclasses.replace(result.options, strength_shading=cloner.options.strength_shading))


def request(photo: np.ndarray, landmarks: np.ndarray | None = None, options: Options | None = None) -> Request:
    """The request an :class:`Editor` is made of: :data:`SHADING`'s photos as the source, ``photo`` the target (its
    landmarks placed by the options' landmarker unless given)."""
    shading = load(SHADING)
    given: Landmarks = (shading.neutral.points, shading.expression.points, landmarks)
    return Request.of(shading.neutral.image, shading.expression.image, photo, landmarks=given, options=options, check_roles=False)


def edit(
    photo: np.ndarray,
    values: Mapping[str, float] | None = None,
    *,
    landmarks: np.ndarray | None = None,
    options: Options | None = None,
    **controls: float,
) -> CloneResult:
    """The photo with its expression edited by named controls (:data:`~exprclone.expressions.controls.CONTROLS`).

    Parameters
    ----------
    photo : ndarray of shape (H, W, 3), uint8 RGB
    values : mapping of str to float, optional
        Each control's value from 0 (the face as it is) to 1; those not given stay at 0.
    landmarks : ndarray of shape (68, 2), optional
        The photo's landmarks; placed by the options' landmarker if not given.
    options : Options, optional
        How it is rendered: ``image_warp``, ``mouth``, ``strength_shading``, ``landmarker``, ... (the method is E+MD with
        lambda_k 0, its GI the edited landmarks).
    **controls
        Values as keywords (``smile=0.5``), added to ``values``.

    Returns
    -------
    CloneResult
        Its ``landmarks["global"]`` are the edited landmarks.

    Raises
    ------
    ExprCloneError
        An unknown control or a value out of range (its subject the control's name); a photo without a face
        (``NoFaceError``, about ``target_neutral``).

    Examples
    --------
    >>> from exprclone import data
    >>> result = edit(data.photo("003"), smile=0.5, brows_up=1)
    >>> result.image.shape, result.method
    ((1350, 1350, 3), 'e+md')
    """
    return Editor.of(request(photo, landmarks, options)).render({**(values or {}), **controls})


def describe(values: Mapping[str, float]) -> str:
    """The values given, in words: ``smile 0.5, brows up 1`` (``no change`` for none above 0).

    >>> describe({"smile": 0.5, "brows_up": 1.0, "frown": 0.0})
    'smile 0.5, brows up 1'
    """
    said = [f"{name.replace('_', ' ')} {value:g}" for name, value in values.items() if value > 0]
    return ", ".join(said) or "no change"
