"""How an option is declared and read: its :class:`Spec` (and the :class:`Page` that shows it), the checks it shares
with others, and the adapters that make an options value from each surface's input.

Every value of options (:class:`~exprclone.options.Options`, :class:`~exprclone.options.Driving`,
:class:`~exprclone.options.Framing`) is a frozen dataclass whose fields are made by :func:`option`: each field its
default and its :class:`Spec`. The functions here read those specs only, never an option's name, so that a new field
reaches every surface: keywords in Python (:func:`changed`), texts (:func:`from_text`: a form's fields, a manifest's
cells), JSON (:func:`from_json`: a live session's messages), the command line
(:func:`exprclone.cli.inputs.add_options`), an HTTP form (:func:`exprclone.server.forms.options_form`) and the
options' answer over HTTP that the page draws its controls from (``GET /api/options``).
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, TypeVar

from ..errors import ExprCloneError, quoted

#: where an option may be offered outside Python: the command line, an HTTP form, a JSON message (live), a manifest's cell.
SURFACES = frozenset({"cli", "form", "json", "manifest"})
#: the parts of a page an option's control may sit in (:attr:`Page.section`), in the order a page shows them: a choice a
#: person makes beside the strengths (the teeth), the strengths' sliders (which a prepared clone follows as they move),
#: the paper's method (which method, its lambda_k, what places the landmarks), how the paper carries the motion over
#: (the warps, retargeting), a video's own.
SECTIONS = ("main", "strengths", "method", "transfer", "video")
#: the sections a page folds away under "Advanced": the paper's choices, which speak its language (a person needs none).
ADVANCED = ("method", "transfer")


@dataclass(frozen=True)
class Choice:
    """One value a page offers for an option, in a person's words.

    Attributes
    ----------
    value : str
        As a form field or a JSON message gives it.
    label : str
        Its name on the page.
    sentence : str
        What it does, plainly (empty when the label says it).
    panel : str or None
        A method's letter in the paper's Figs. 11-13.
    """

    value: str
    label: str
    sentence: str = ""
    panel: str | None = None


@dataclass(frozen=True)
class Page:
    """How a page shows one option: a person's words for it, where its control sits, the values it offers.

    The control follows from the option: a menu of :attr:`choices` when there are some, a checkbox for a switch, a
    slider for a number with a range.

    Attributes
    ----------
    label : str
        The control's label: the paper's words and symbols (lambda_k, GI...) only in a section of :data:`ADVANCED`.
    sentence : str
        What it does, in a person's words: no paper's symbols or jargon.
    section : str
        The part of a page it sits in (:data:`SECTIONS`); those of :data:`ADVANCED` are folded away.
    choices : tuple of Choice, or a callable giving them
        The values a menu offers (those allowed, or the ones worth trying of a number), with their words; a callable
        when they come from a room that loads numpy (the DB metric's lambdas), asked for only by a page.
    unset : str or None
        A first entry of the menu that sends nothing, in words, for an option whose absence is not its default (a
        compare sheet of Fig. 19 takes the RBF warp unless a global warp is given).
    step : float or None
        A slider's step.
    follows : str or None
        The option whose value a slider shows until it is moved (a region's strength follows the whole one's).
    """

    label: str
    sentence: str
    section: str = SECTIONS[0]
    choices: tuple[Choice, ...] | Callable[[], tuple[Choice, ...]] = ()
    unset: str | None = None
    step: float | None = None
    follows: str | None = None

    def offered(self) -> tuple[Choice, ...]:
        """:attr:`choices`, asked for if a callable gives them."""
        return self.choices() if callable(self.choices) else self.choices


@dataclass(frozen=True)
class Spec:
    """How one option is given outside Python, how it is checked, and its words on every surface.

    Attributes
    ----------
    help : str
        What it does, for the command line's help, the HTTP API's documentation and the docs.
    check : callable
        ``check(value, name)``: the value as the option holds it, or ExprCloneError about ``name``.
    parse : callable or None
        ``parse(text)``: the value a text gives (a command line's word, a form field, a manifest's cell);
        None when the text is the value.
    kind : type
        What a form or a JSON message gives: ``str``, ``bool``, ``int`` or ``float``; text for ``str``,
        which ``parse`` reads.
    also : tuple of type
        Other JSON types a message may give it as (its value itself: ``"lambda": 0.5``, ``"only": ["mouth"]``).
    choices : tuple of str or None
        The values allowed, when they are a list of names.
    key : str or None
        Its name in forms, JSON and manifests when it is not the field's (``lambda``).
    flag : str or None
        Its command line flag when it is not ``--`` and the key with dashes (``--no-mouth``).
    flag_help : str or None
        The command line's help of a switch whose flag turns it off (``--no-mouth``): what giving the flag does.
    metavar : str or None
        What the command line's help shows for its value.
    file : bool
        Given outside Python as a file (landmarks, an eigenface basis), which the surface reads.
    surfaces : frozenset of str
        Where it is offered (:data:`SURFACES`); nowhere but in Python when empty.
    schema : dict
        What a form field's value meets beyond its kind, in JSON Schema's words (``pattern``, ``minimum``...), for
        an HTTP API's schema; the check still decides.
    page : Page or None
        How a page shows it; None for an option a page draws no control of (a file, the faces picked on the photo).
    """

    help: str
    check: Callable[[Any, str], Any]
    parse: Callable[[str], Any] | None = None
    kind: type = str
    also: tuple[type, ...] = ()
    choices: tuple[str, ...] | None = None
    key: str | None = None
    flag: str | None = None
    flag_help: str | None = None
    metavar: str | None = None
    file: bool = False
    surfaces: frozenset[str] = SURFACES
    schema: Mapping[str, Any] = dataclasses.field(default_factory=dict)
    page: Page | None = None


def option(default: Any, spec: Spec) -> Any:
    """A field of an options value: its default, and its :class:`Spec` in the field's metadata."""
    return dataclasses.field(default=default, metadata={"spec": spec})


def one_of(choices: tuple[str, ...]) -> Callable[[Any, str], str]:
    """A check: one of ``choices``, or ExprCloneError naming them."""

    def check(value: Any, name: str) -> str:
        if value not in choices:
            raise ExprCloneError(name, f"unknown {name.replace('_', ' ')} {quoted(value)}; choose one of: {', '.join(choices)}")
        return str(value)

    return check


def check_boolean(value: Any, name: str) -> bool:
    if type(value).__name__ not in ("bool", "bool_"):  # numpy's bool_ too
        raise ExprCloneError(name, f"must be True or False, got {quoted(value)}")
    return bool(value)


def parse_number(text: str) -> float:
    """A number, as a text gives it."""
    try:
        return float(text)
    except ValueError:
        raise ValueError(f"expected a number, got {quoted(text)}") from None


#: the words a text may say a switch with, as forms, manifests and ``evaluate --retargets`` write them.
BOOLEAN_WORDS = {"true": True, "1": True, "yes": True, "on": True, "false": False, "0": False, "no": False, "off": False}


def parse_boolean(text: str) -> bool:
    """``true``/``false`` (``1``/``0``, ``yes``/``no``, ``on``/``off``), as forms and manifests write them."""
    if text.strip().lower() not in BOOLEAN_WORDS:
        raise ValueError(f"expected true or false, got {quoted(text)}")
    return BOOLEAN_WORDS[text.strip().lower()]


def switch(help: str, flag_help: str | None = None, **rest: Any) -> Spec:
    """The spec of a switch (True or False); ``flag_help`` with a ``--no-X`` ``flag`` (an option on by default)."""
    return Spec(help, check_boolean, parse_boolean, bool, flag_help=flag_help, **rest)


def given(value: Any, name: str) -> Any:
    """Anything: checked where it is used (``global_landmarks`` against the target photo, ``eigenfaces`` and ``layout``
    by their types)."""
    return value


class Chosen:
    """What :class:`~exprclone.options.Options`, ``Driving`` and ``Framing`` share: fields made by :func:`option`, each
    checked by its spec as the value is made, the value made from keywords, texts or JSON, and shown by what differs
    from the defaults."""

    def __post_init__(self) -> None:
        checked(self)

    @classmethod
    def of(cls: type[C], base: C | None = None, keywords: Mapping[str, Any] | None = None) -> C:
        """The value of a Python call: ``base`` (the defaults if None), changed by the options given as keywords
        (:func:`changed`: an ExprCloneError about a keyword that is not an option, or a bad value)."""
        return changed(cls, base, keywords or {})

    @classmethod
    def from_text(cls: type[C], given: Mapping[str, str], base: C | None = None) -> C:
        """The value a mapping of texts gives (a manifest's cells, a form's fields: :func:`from_text`)."""
        return from_text(cls, given, base)

    @classmethod
    def from_json(cls: type[C], given: Mapping[str, Any], base: C | None = None) -> C:
        """The value a JSON object gives (a live session's messages: :func:`from_json`)."""
        return from_json(cls, given, base)

    def __repr__(self) -> str:
        return shown(self)


C = TypeVar("C", bound=Chosen)
T = TypeVar("T")


def checked(value: Any) -> None:
    """Check every field of an options value made of :func:`option` fields, in place (its ``__post_init__``)."""
    cls: type = type(value)
    for name, found in _specs(cls).items():
        object.__setattr__(value, name, found.check(getattr(value, name), found.key or name))


def names(cls: type) -> tuple[str, ...]:
    """The options of ``cls`` (:class:`~exprclone.options.Options` or another value made of :func:`option` fields), in
    their order."""
    return tuple(_specs(cls))


def spec(cls: type, name: str) -> Spec:
    """The :class:`Spec` of the option ``name`` of ``cls``."""
    return _specs(cls)[name]


@functools.cache
def _specs(cls: type) -> dict[str, Spec]:
    """Each option's :class:`Spec` by name, read once per class (every value made checks every option)."""
    return {f.name: f.metadata["spec"] for f in dataclasses.fields(cls)}


def key(cls: type, name: str) -> str:
    """The option's name in forms, JSON and manifests (``lambda`` for ``lambda_k``)."""
    return spec(cls, name).key or name


def flag(cls: type, name: str) -> str:
    """The option's command line flag: its spec's, or ``--`` and its key with dashes (``--global-warp``)."""
    return spec(cls, name).flag or f"--{key(cls, name).replace('_', '-')}"


def offered(cls: type, surface: str, chosen: tuple[str, ...] | None = None) -> tuple[str, ...]:
    """The options of ``cls`` that ``surface`` (of :data:`SURFACES`) offers, of ``chosen`` (all by default), in order."""
    return tuple(n for n in (chosen or names(cls)) if surface in spec(cls, n).surfaces)


def changed(cls: type[T], base: T | None, changes: Mapping[str, Any]) -> T:
    """``base`` (the defaults if None) with ``changes`` by option name, checked; ExprCloneError about a name that is not
    an option of ``cls``, or a bad value."""
    unknown = sorted(set(changes) - set(names(cls)))
    if unknown:
        raise ExprCloneError(unknown[0], f"not an option; choose from {', '.join(names(cls))}")
    start = base if base is not None else cls()
    return dataclasses.replace(start, **changes) if changes else start  # type: ignore[type-var]


def from_text(cls: type[T], given: Mapping[str, str], base: T | None = None) -> T:
    """The options of ``cls`` a mapping of texts gives by key (a manifest's cells, a form's fields), each read by its
    :attr:`Spec.parse`; empty texts and keys that are not options are left out, the others as in ``base``."""
    changes = {}
    for name in names(cls):
        text = given.get(key(cls, name))
        if text is None or text == "":
            continue
        parse = spec(cls, name).parse
        try:
            changes[name] = text if parse is None else parse(text)
        except ExprCloneError:
            raise
        except ValueError as e:
            raise ExprCloneError(key(cls, name), str(e)) from None
    return changed(cls, base, changes)


def from_json(cls: type[T], given: Mapping[str, Any], base: T | None = None) -> T:
    """The options of ``cls`` a JSON object gives by key (a live session's messages): a text option may come as text
    or as its value (``"lambda": 0.5``, ``"only": ["mouth"]``); keys that are not options offered to JSON are left out,
    the others as in ``base``."""
    changes = {}
    for name in offered(cls, "json"):
        value = given.get(key(cls, name))
        if value is None:
            continue
        parse = spec(cls, name).parse
        kinds = (spec(cls, name).kind, *spec(cls, name).also)
        if not isinstance(value, kinds) or (isinstance(value, bool) and bool not in kinds):
            raise ExprCloneError(key(cls, name), f"must be {expected(kinds)}, got {quoted(value)}")
        if isinstance(value, str) and parse is not None:
            value = parse(value)
        changes[name] = tuple(value) if isinstance(value, list) else value
    return changed(cls, base, changes)


#: how a JSON type is named in errors.
JSON_NAMES = {str: "a string", bool: "true or false", int: "an integer", float: "a number", list: "a list"}


def expected(kinds: tuple[type, ...]) -> str:
    """What JSON values of ``kinds`` are, for an error: ``a string or a list``."""
    return " or ".join(dict.fromkeys(JSON_NAMES[float if k is int and float in kinds else k] for k in kinds))


def json_kinds(cls: type) -> dict[str, tuple[type, ...]]:
    """The JSON types each option of ``cls`` offered to JSON may come as, by key."""
    return {key(cls, n): (spec(cls, n).kind, *spec(cls, n).also) for n in offered(cls, "json")}


def shown(value: Any) -> str:
    """An options value as its type and the options that are not the defaults: ``Options(method='global', strength=0.5)``."""
    return f"{type(value).__name__}({', '.join(f'{n}={v!r}' for n, v in differing(value).items())})"


def differing(value: Any) -> dict[str, Any]:
    """The options of an options value that are not its type's defaults, by name, in their order."""
    default = type(value)()
    return {n: getattr(value, n) for n in names(type(value)) if not _same(getattr(value, n), getattr(default, n))}


def _same(a: Any, b: Any) -> bool:
    return a is b or (type(a) is type(b) and not hasattr(a, "shape") and a == b)
