"""Every option a user can choose, declared once: each a field with its default, its check and its words.

Three values hold them: :class:`Options`, a clone's (its method, lambda_k, warps, strength...:
:mod:`.clone_options`, the strengths' specs in :mod:`.strengths`); :class:`Driving`, how a video drives a portrait
(its neutral frame, smoothing, head motion), and :class:`Framing`, how a driven video is framed (its size, the driving
video beside it: :mod:`.video_options`). Pure data, like :mod:`exprclone.methods`: the command line builds its arguments from them
without loading numpy. A value is checked when it is made (a bad value raises :class:`~exprclone.ExprCloneError`
naming the option), so a value that exists is a valid one; what can only be checked against the photos
(``global_landmarks`` inside the target photo) is checked by the :class:`~exprclone.Cloner`.

Each field's :class:`~.specs.Spec` says how the option is given outside Python and holds each of its texts (the
command line's help, the page's label and plain sentence, its choices in words: a :class:`~.specs.Page`); every surface
turns its own input into a value through one adapter made from those specs (:mod:`.specs`): keywords in Python
(:meth:`Options.of`, :func:`changed`), the words of a command line (:func:`exprclone.cli.inputs.add_options`), the
fields of an HTTP form (:func:`exprclone.server.forms.options_form`), texts such as a manifest's cells
(:func:`from_text`), JSON such as a live session's messages (:func:`from_json`), and the page's controls, drawn from
the server's answer (``GET /api/options``). A new option is one field, and its use.
"""

from .clone_options import (
    EDIT,
    FACE_WORDS,
    GIVEN,
    GLOBAL_WARPS,
    IMAGE_WARPS,
    RENDER,
    Options,
    check_faces,
    check_lambda,
    parse_lambda,
)
from .specs import (
    ADVANCED,
    SECTIONS,
    SURFACES,
    Choice,
    Page,
    Spec,
    changed,
    differing,
    expected,
    flag,
    from_json,
    from_text,
    json_kinds,
    key,
    names,
    offered,
    option,
    spec,
)
from .strengths import REGIONS, STRENGTH_RANGE, check_regions
from .video_options import SIZE_RANGE, Driving, Framing

#: the values of options, in the order the documentation and the options' answer list them.
VALUES = (Options, Driving, Framing)

__all__ = [
    "ADVANCED",
    "EDIT",
    "FACE_WORDS",
    "GIVEN",
    "GLOBAL_WARPS",
    "IMAGE_WARPS",
    "REGIONS",
    "RENDER",
    "SECTIONS",
    "SIZE_RANGE",
    "STRENGTH_RANGE",
    "SURFACES",
    "VALUES",
    "Choice",
    "Driving",
    "Framing",
    "Options",
    "Page",
    "Spec",
    "changed",
    "check_faces",
    "check_lambda",
    "check_regions",
    "differing",
    "expected",
    "flag",
    "from_json",
    "from_text",
    "json_kinds",
    "key",
    "names",
    "offered",
    "option",
    "parse_lambda",
    "spec",
]
