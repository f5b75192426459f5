"""The options as an HTTP form's fields: each option a form field made from its spec (:mod:`exprclone.options`).

A route takes a value's options by one parameter, ``Annotated[Asked, Depends(options_form(Options))]``:
the dependency's fields are the options offered to forms (their names, or ``lambda`` for
``lambda_k``), each with its type, its help as its description and its default said there;
the value is checked as the Python API checks it. Files (``global_landmarks``) come as
uploads, which the route reads.
"""

from __future__ import annotations

import inspect
from collections.abc import Awaitable, Callable
from dataclasses import dataclass
from typing import Annotated, Any

from fastapi import Form

from ..options import changed, from_text, key, offered, spec


@dataclass(frozen=True)
class Asked:
    """The options a form asks for, and which of them it gave (Fig. 19 shows the RBF transfer unless a global warp was
    given)."""

    options: Any
    given: frozenset[str] = frozenset()


def options_form(cls: type, chosen: tuple[str, ...] | None = None) -> Callable[..., Awaitable[Asked]]:
    """A FastAPI dependency reading the options of ``cls`` offered to forms, of ``chosen`` (all by default), but files."""
    default = cls()
    names = tuple(n for n in offered(cls, "form", chosen) if not spec(cls, n).file)
    parameters = []
    for name in names:
        option, value = spec(cls, name), getattr(default, name)
        said = "" if value is None else f" (default: {str(value).lower() if isinstance(value, bool) else value})"
        # in the schema (as GET /api/options says them: exprclone.server.described); checked here
        extra = ({"enum": list(option.choices)} if option.choices else {}) | dict(option.schema)
        extra |= {} if value is None else {"default": value}
        alias = key(cls, name) if key(cls, name) != name else None
        field = Form(alias=alias, description=option.help + said, json_schema_extra=extra or None)
        annotation = Annotated[option.kind, field]  # type: ignore[name-defined]  # absent is None; a form cannot say null
        parameters.append(inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, default=None, annotation=annotation))

    async def read(**fields: Any) -> Asked:
        given = {name: value for name, value in fields.items() if value is not None}
        texts = {key(cls, n): v for n, v in given.items() if spec(cls, n).kind is str}
        values = {n: v for n, v in given.items() if spec(cls, n).kind is not str}
        return Asked(changed(cls, from_text(cls, texts), values), frozenset(given))

    read.__signature__ = inspect.Signature(parameters, return_annotation=Asked)  # type: ignore[attr-defined]
    return read
