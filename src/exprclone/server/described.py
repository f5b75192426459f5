"""The options described for clients (``GET /api/options``): each option's name, kind, range, choices, default and
words, made from their one declaration (:mod:`exprclone.options`), so that a page draws its controls from the answer.

The answer says of each option what the OpenAPI schema says of its form field (its JSON type, ``enum``, ``minimum``,
``maximum``, ``pattern``, ``default``, its help in the description: :func:`exprclone.server.forms.options_form` makes
both from the same spec), and what only a person needs: the page's label, a plain sentence, where its control sits and
the values a menu offers in words (the methods with their panel letters in Fig. 11, the DB metric's lambdas).
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel

from ..options import RENDER, VALUES, flag, key, names, spec
from .session import SIZES

#: an option's kind, as JSON Schema names the type of its form field.
KINDS = {str: "string", bool: "boolean", int: "integer", float: "number"}


class OptionChoice(BaseModel):
    """One value a page offers, in words: the value as a form field gives it, its label, what it does, and for a method its
    letter in Fig. 11."""

    value: str
    label: str
    sentence: str
    panel: str | None = None


class OptionPage(BaseModel):
    """How a page shows an option: its control's label, a plain sentence, the section it sits in (``main``,
    ``strengths``, ``method``, ``transfer``, ``video``; ``method`` and ``transfer`` are the paper's choices, which a page
    folds away as advanced), the values its menu offers, the words of a first entry that sends nothing
    (when that is not the default), a slider's step, and the key of the option a slider follows until it is moved."""

    label: str
    sentence: str
    section: str
    choices: list[OptionChoice]
    unset: str | None
    step: float | None
    follows: str | None


class OptionDescribed(BaseModel):
    """One option: its name in Python and its key in forms, JSON messages and manifests; which value holds it
    (``Options``, a clone's; ``Driving`` and ``Framing``, a video's); its kind, default, the values allowed and its
    bounds, as the schema says them; its help, its command line flag (and that flag's help when it turns the option
    off); where it is offered; whether a prepared clone renders again with it (``POST /api/edits/{id}/render``); and
    how a page shows it (none for a file, or the faces picked on a photo)."""

    name: str
    key: str
    value: Literal["Options", "Driving", "Framing"]
    kind: Literal["string", "boolean", "integer", "number"]
    file: bool
    default: str | bool | int | float | None
    choices: list[str] | None
    minimum: float | None
    maximum: float | None
    pattern: str | None
    help: str
    flag: str | None
    flag_help: str | None
    surfaces: list[str]
    render: bool
    page: OptionPage | None


class LiveBounds(BaseModel):
    """What the live WebSocket takes beyond the options' own bounds: the output sizes it renders."""

    sizes: list[int]


class OptionsAnswer(BaseModel):
    """Every option offered outside Python, in the order of their declaration, and the live WebSocket's bounds."""

    options: list[OptionDescribed]
    live: LiveBounds


def default_of(cls: type, name: str) -> Any:
    """The default of the option ``name`` of ``cls`` as JSON gives it (None for none)."""
    value = getattr(cls(), name)
    return value if value is None or isinstance(value, (str, bool, int, float)) else str(value)


def page_of(cls: type, name: str) -> OptionPage | None:
    page = spec(cls, name).page
    if page is None:
        return None
    choices = [OptionChoice(value=c.value, label=c.label, sentence=c.sentence, panel=c.panel) for c in page.offered()]
    follows = None if page.follows is None else key(cls, page.follows)
    return OptionPage(
        label=page.label, sentence=page.sentence, section=page.section, choices=choices, unset=page.unset, step=page.step, follows=follows
    )


def described(cls: type, name: str) -> OptionDescribed:
    """The option ``name`` of ``cls`` as the answer describes it."""
    option = spec(cls, name)
    return OptionDescribed(
        name=name,
        key=key(cls, name),
        value=cls.__name__,  # type: ignore[arg-type]  # (one of VALUES: checked by the model)
        kind=KINDS[option.kind],  # type: ignore[arg-type]  # (a kind of KINDS: checked by the model)
        file=option.file,
        default=default_of(cls, name),
        choices=None if option.choices is None else list(option.choices),
        minimum=option.schema.get("minimum"),
        maximum=option.schema.get("maximum"),
        pattern=option.schema.get("pattern"),
        help=option.help,
        flag=flag(cls, name) if "cli" in option.surfaces else None,
        flag_help=option.flag_help,
        surfaces=sorted(option.surfaces),
        render=cls is VALUES[0] and name in RENDER,
        page=page_of(cls, name),
    )


def options_answer() -> OptionsAnswer:
    """Every option of :data:`exprclone.options.VALUES` offered outside Python, described."""
    listed = [described(cls, name) for cls in VALUES for name in names(cls) if spec(cls, name).surfaces]
    return OptionsAnswer(options=listed, live=LiveBounds(sizes=list(SIZES)))
