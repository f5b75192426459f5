"""What the package ships, for the page's "try the samples": the sample photos and clip (:mod:`exprclone.data`), and
the built-in expressions' names (:mod:`exprclone.expressions`)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Annotated

from fastapi import APIRouter
from fastapi import Path as InPath
from fastapi.responses import FileResponse

from ... import data as samples
from ... import expressions
from ...errors import ExprCloneError
from ...roles import SOURCE_EXPRESSION, SOURCE_NEUTRAL, TARGET_NEUTRAL
from ..answers import ExpressionListed, Expressions
from ..openapi import errors

router = APIRouter(tags=["samples"])

#: the samples the page's "try the sample photos" fetches, by name.
SAMPLES: dict[str, Callable[[], Path]] = {
    SOURCE_NEUTRAL: lambda: samples.path(samples.SOURCE),
    SOURCE_EXPRESSION: lambda: samples.path(samples.SOURCE, "smile"),
    TARGET_NEUTRAL: lambda: samples.path(samples.TARGET),
    "portrait": lambda: samples.path(samples.TARGET),
    "driving_video": samples.clip,
}


#: what a sample is answered as: its file, a photo or a video.
FILES = {"image/jpeg": {"schema": {"type": "string", "format": "binary"}}, "video/mp4": {"schema": {"type": "string", "format": "binary"}}}


@router.get(
    "/api/samples/{name}", response_class=FileResponse, responses={200: {"content": FILES, "description": "the file"}, **errors(400)}
)
async def sample(name: Annotated[str, InPath(json_schema_extra={"enum": list(SAMPLES)})]) -> FileResponse:
    """A sample shipped in the package (:mod:`exprclone.data`): ``source_neutral``, ``source_expression``,
    ``target_neutral``, ``portrait`` or ``driving_video``."""
    if name not in SAMPLES:
        raise ExprCloneError("sample", f"no sample {name!r}; choose one of {', '.join(SAMPLES)}")
    path = SAMPLES[name]()
    return FileResponse(path, filename=path.name)


@router.get("/api/expressions")
async def expression_names() -> Expressions:
    """The built-in expressions, for the ``expression`` field of ``/api/clone`` and ``/api/compare``:
    ``{"expressions": [{"name", "description"}, ...]}``, the prototype smile first (the one a page offers first), then
    the others by name."""
    ordered = sorted(expressions.names(), key=lambda name: name != expressions.DEFAULT)
    listed = [ExpressionListed(name=name, description=expressions.load(name).description) for name in ordered]
    return Expressions(expressions=listed)
