"""The web application of ``exprclone study serve``: the page, the study's images, the participants' answers.

Nothing it serves names a method. The page and its script are the same for every study;
the images are served by their random ids, and only those ``study.json`` lists; a
participant's state lists each set's results by id, in the order shuffled for them
(:func:`exprclone.study.participants.order`). The key (``key.json``) is never read here.

Every request body is bounded (:class:`exprclone.server.runtime.limits.UploadLimit`) and checked,
its shape by the models below and its values by :mod:`exprclone.study.participants`;
every error is one line of JSON, ``{"error": "..."}``: 400 for a bad request, 404 for an
unknown participant or image, 409 when the study is full, 413 for a body over the limit,
429 for a client that asks for new participants too often.

A participant is made by the page's own flow, one ``POST /api/participants`` when a person
starts; an address gets at most :data:`NEW_PER_ADDRESS` of them an hour (``--new-per-address``), so
that plain POSTs cannot use up the study's places, nor rate as many made-up participants.
The application serves no API documentation (``/docs``, ``/redoc``, ``/openapi.json``): a
participant needs none.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Annotated, Any

from fastapi import APIRouter, Depends, FastAPI
from fastapi import Path as InPath
from fastapi.responses import FileResponse
from fastapi.staticfiles import StaticFiles
from pydantic import BaseModel, ConfigDict, Field, StrictInt, StrictStr
from starlette.exceptions import HTTPException
from starlette.requests import HTTPConnection, Request

from .. import __version__
from ..server.app import add_error_answers
from ..server.runtime.limits import Paced, UploadLimit
from .folder import ID, SUFFIX, Study, read_study
from .participants import NoSuchParticipant, Participants, Record, StudyFull, order

#: the largest request body, in bytes (a set's ratings take a few hundred).
MAX_BODY = 16 * 1024
#: participants a study takes by default.
MAX_PARTICIPANTS = 1000
#: the most results a set's ratings may name (the paper compares seven methods at most).
MAX_ITEMS = 64
#: new participants one client address may start in :data:`PACE_SECONDS` (a family sharing a connection: a few).
NEW_PER_ADDRESS, PACE_SECONDS = 5, 3600.0

router = APIRouter()
Participant = Annotated[str, InPath(pattern=r"^[0-9a-f]{32}$", description="the participant's id (32 hex digits)")]


class Error(BaseModel):
    error: str = Field(description="what is wrong, on one line")


class NewParticipant(BaseModel):
    id: str = Field(description="the new participant's id (32 hex digits): keep it to come back")


class About(BaseModel):
    """What a participant tells about themselves; either may be null."""

    model_config = ConfigDict(extra="forbid")
    age: StrictInt | None = Field(description="in years, 1 to 120")
    gender: Annotated[StrictStr, Field(max_length=16)] | None = Field(description="female, male or other")


class Ratings(BaseModel):
    """A set's ratings: each of its results' id to a score, a whole number from 1 (the poorest) to 5 (the best)."""

    model_config = ConfigDict(extra="forbid")
    ratings: Annotated[dict[Annotated[str, Field(max_length=16)], StrictInt], Field(max_length=MAX_ITEMS)]


class Item(BaseModel):
    id: str = Field(description="the result's id, the key of its score")
    image: str = Field(description="the result's URL")


class SetView(BaseModel):
    photos: dict[str, str] = Field(description="the URLs of the source's two photos and the target's")
    items: list[Item] = Field(description="the results, in the order this participant sees them")


class State(BaseModel):
    participant: str
    about: dict[str, Any] | None = Field(description="age and gender as told, or null before they were asked")
    sets: list[SetView]
    ratings: dict[str, dict[str, int]] = Field(description="the sets rated so far (by index): each result's id to its score")


ERRORS: dict[int | str, dict[str, Any]] = {status: {"model": Error} for status in (400, 404, 413)}


def image_url(image_id: str) -> str:
    return f"/images/{image_id}{SUFFIX}"


def view(study: Study, record: Record) -> dict[str, Any]:
    """A participant's state: their answers, and each set with its results in the order shuffled for them."""
    sets = [
        {
            "photos": {role: image_url(i) for role, i in s.photos.items()},
            "items": [{"id": i, "image": image_url(i)} for i in order(record.participant, k, s.items)],
        }
        for k, s in enumerate(study.sets)
    ]
    return {"participant": record.participant, "about": record.about, "sets": sets, "ratings": record.data()["ratings"]}


@dataclass(frozen=True)
class Served:
    """What the server holds: the study, the ids of the images its page may show, and its participants."""

    study: Study
    images: frozenset[str]
    participants: Participants
    paced: Paced


def the_study(connection: HTTPConnection) -> Served:
    """The study being served (:class:`Served`, made with the application): a FastAPI dependency."""
    served: Served = connection.app.state.served
    return served


#: a route's parameter for the study being served (:func:`the_study`).
Server = Annotated[Served, Depends(the_study)]


@router.get("/", include_in_schema=False)
def page() -> FileResponse:
    return FileResponse(Path(str(resources.files(__package__) / "static" / "index.html")))


@router.get("/static/call.js", include_in_schema=False)
def shared_script() -> FileResponse:
    """The fetch that exprclone's pages share (the clone page's ``static/call.js``)."""
    return FileResponse(Path(str(resources.files("exprclone.server") / "static" / "call.js")), media_type="text/javascript")


@router.get("/api/health")
def health() -> dict[str, str]:
    """The server is up: ``{"status": "ok", "version": ...}``."""
    return {"status": "ok", "version": __version__}


@router.post("/api/participants", status_code=201, response_model=NewParticipant, responses={409: {"model": Error}, 429: {"model": Error}})
def new_participant(server: Server, request: Request) -> dict[str, str]:
    """A new anonymous participant (409 when the study has all it may take; 429 when this address has started
    :data:`NEW_PER_ADDRESS` in the last :data:`PACE_SECONDS`)."""
    server.paced.admit(request.client.host if request.client else "", time.monotonic())
    return {"id": server.participants.create().participant}


@router.get("/api/participants/{participant}", response_model=State, responses=ERRORS)
def state(server: Server, participant: Participant) -> dict[str, Any]:
    """A participant's state: what they told, the sets (their results in this participant's order), the ratings saved."""
    return view(server.study, server.participants.load(participant))


@router.put("/api/participants/{participant}/about", response_model=State, responses=ERRORS)
def tell(server: Server, participant: Participant, about: About) -> dict[str, Any]:
    """Save a participant's age and gender (either may be null); their state."""
    return view(server.study, server.participants.tell(participant, about.model_dump()))


@router.put("/api/participants/{participant}/sets/{index}", response_model=State, responses=ERRORS)
def rate(server: Server, participant: Participant, index: Annotated[int, InPath(ge=0, le=100_000)], body: Ratings) -> dict[str, Any]:
    """Save a participant's scores of one set's results (each of them, 1 to 5), replacing any saved before; their state."""
    return view(server.study, server.participants.rate(participant, index, body.ratings))


@router.get("/images/{name}", response_class=FileResponse, responses={200: {"content": {"image/png": {}}}, 404: {"model": Error}})
def image(server: Server, name: Annotated[str, InPath(max_length=32)]) -> FileResponse:
    """A photo or result of the study, by its id."""
    image_id = name.removesuffix(SUFFIX)
    if not (name.endswith(SUFFIX) and ID.fullmatch(image_id) and image_id in server.images):
        raise HTTPException(404, f"no image {name!r} in this study")
    return FileResponse(server.study.image(image_id), media_type="image/png")


def create_app(folder: str | Path, max_participants: int = MAX_PARTICIPANTS, new_per_address: int = NEW_PER_ADDRESS) -> FastAPI:
    """The application serving the study in ``folder`` (ExprCloneError if it is not a whole study); one client address
    starts at most ``new_per_address`` participants in :data:`PACE_SECONDS`."""
    study = read_study(folder)
    app = FastAPI(
        title="exprclone study",
        version=__version__,
        description="A user study: rate each result from 1 to 5.",
        docs_url=None,
        redoc_url=None,
        openapi_url=None,
    )
    paced = Paced(new_per_address, PACE_SECONDS)
    app.state.served = Served(study, frozenset(study.images()), Participants(study, max_participants), paced)
    add_error_answers(app, {NoSuchParticipant: 404, StudyFull: 409})
    app.include_router(router)
    app.mount("/static", StaticFiles(directory=Path(str(resources.files(__package__) / "static"))), name="static")
    app.add_middleware(UploadLimit, max_bytes=MAX_BODY)
    return app
