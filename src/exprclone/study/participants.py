"""A study's participants and their ratings: one JSON file each in ``ratings/``, written atomically.

A participant is an anonymous random id (32 hex digits, from :mod:`secrets`) that the
page keeps in the browser's localStorage; nothing else identifies them. Their file holds
what they chose to tell about themselves (age and gender, as the paper reports its
participants) and their ratings, set by set::

    {"format": 1, "participant": ID, "about": {"age": 34, "gender": null} or null,
     "ratings": {"0": {ITEM: SCORE, ...}, ...}}

A score is a whole number from 1 (the poorest) to 5 (the best), as in the paper; a set's
ratings are saved together, one score for each of its results. The order in which a
participant sees a set's results is shuffled by a generator seeded with their id and the
set (:func:`order`): a participant who comes back sees the same order, and two
participants see different ones (but by chance).
"""

from __future__ import annotations

import random
import re
import secrets
import threading
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import ExprCloneError
from .folder import FORMAT, RATINGS, Study, read_json, write_json

#: a participant's id.
PARTICIPANT = re.compile(r"[0-9a-f]{32}")
#: the scores a result may get: 1 (the poorest) to 5 (the best).
SCORES = (1, 5)
#: the genders a participant may give (or none).
GENDERS = ("female", "male", "other")
#: the ages a participant may give (or none), in years.
AGES = (1, 120)


class NoSuchParticipant(ExprCloneError):
    """A well-formed participant id that this study has not given out (answered 404)."""


class StudyFull(ExprCloneError):
    """The study has all the participants it may take (answered 409)."""


def order(participant: str, set_index: int, items: tuple[str, ...] | list[str]) -> list[str]:
    """The results of set ``set_index`` in the order ``participant`` sees them: shuffled by a generator seeded with both.

    >>> order("0" * 32, 0, ["a", "b", "c"]) == order("0" * 32, 0, ["c", "b", "a"])
    True
    """
    shuffled = sorted(items)
    random.Random(f"{participant}/{set_index}").shuffle(shuffled)
    return shuffled


@dataclass
class Record:
    """One participant's file: ``about`` (None until they have been asked) and ``ratings``, set index to item to score."""

    participant: str
    about: dict[str, Any] | None = None
    ratings: dict[int, dict[str, int]] = field(default_factory=dict)

    def data(self) -> dict[str, Any]:
        """What the participant's file holds."""
        ratings = {str(k): v for k, v in sorted(self.ratings.items())}
        return {"format": FORMAT, "participant": self.participant, "about": self.about, "ratings": ratings}


def check_about(about: object, name: str) -> dict[str, Any]:
    """``{"age": int or None, "gender": one of GENDERS or None}``, or ExprCloneError about ``name``."""
    if not isinstance(about, dict) or set(about) != {"age", "gender"}:
        raise ExprCloneError(name, "about must have age and gender (each may be null)")
    age, gender = about["age"], about["gender"]
    if age is not None and not (type(age) is int and AGES[0] <= age <= AGES[1]):
        raise ExprCloneError(name, f"age must be a whole number from {AGES[0]} to {AGES[1]}, or null")
    if gender is not None and gender not in GENDERS:
        raise ExprCloneError(name, f"gender must be one of {', '.join(GENDERS)}, or null")
    return {"age": age, "gender": gender}


def check_ratings(study: Study, set_index: int, ratings: object, name: str) -> dict[str, int]:
    """A set's ratings: one score (a whole number in :data:`SCORES`) for each of its results and no other, or ExprCloneError."""
    if not 0 <= set_index < len(study.sets):
        raise ExprCloneError(name, f"no set {set_index}: the study has sets 0 to {len(study.sets) - 1}")
    items = set(study.sets[set_index].items)
    if not isinstance(ratings, dict) or set(ratings) != items:
        unknown = sorted(set(ratings) - items) if isinstance(ratings, dict) else []
        what = f"{unknown[0]!r} is not one of its results" if unknown else "a score for each of its results is needed"
        raise ExprCloneError(name, f"set {set_index}: {what}")
    bad = next((i for i, score in ratings.items() if type(score) is not int or not SCORES[0] <= score <= SCORES[1]), None)
    if bad is not None:
        raise ExprCloneError(name, f"set {set_index}: the score of {bad} must be a whole number from {SCORES[0]} to {SCORES[1]}")
    return dict(ratings)


def read_record(study: Study, path: Path) -> Record:
    """A participant's file, checked against the study, or ExprCloneError about ``path``."""
    data = read_json(path, "a participant's ratings")
    participant = data.get("participant")
    if not isinstance(participant, str) or not PARTICIPANT.fullmatch(participant) or path.stem != participant:
        raise ExprCloneError(str(path), "not a participant's ratings (its id is not its file's name)")
    about = data.get("about")
    ratings = data.get("ratings")
    if not isinstance(ratings, dict) or not all(isinstance(k, str) and k.isdigit() for k in ratings):
        raise ExprCloneError(str(path), "not a participant's ratings (ratings must map set numbers to scores)")
    return Record(
        participant,
        None if about is None else check_about(about, str(path)),
        {int(k): check_ratings(study, int(k), v, str(path)) for k, v in ratings.items()},
    )


def read_all(study: Study) -> list[Record]:
    """Every participant's record in the study's ``ratings/`` (none if it has none)."""
    return [read_record(study, path) for path in files(study.folder / RATINGS)]


def files(folder: Path) -> list[Path]:
    """The participants' files in ``folder`` (not the temporary files of a write under way), sorted."""
    return sorted(p for p in folder.glob("*.json") if PARTICIPANT.fullmatch(p.stem)) if folder.is_dir() else []


class Participants:
    """The participants of a study being served: new ones (at most ``limit``), and their answers saved as they come.

    Thread-safe: each change reads, changes and writes a participant's file under one lock.
    """

    def __init__(self, study: Study, limit: int) -> None:
        self.study, self.limit = study, limit
        self.folder = study.folder / RATINGS
        self.folder.mkdir(exist_ok=True)
        self.lock = threading.Lock()

    def path(self, participant: str) -> Path:
        if not PARTICIPANT.fullmatch(participant):
            raise ExprCloneError("participant", "not a participant id (32 hex digits)")
        return self.folder / f"{participant}.json"

    def create(self) -> Record:
        """A new participant, saved with no answers yet; StudyFull past the limit."""
        with self.lock:
            if len(files(self.folder)) >= self.limit:
                raise StudyFull("study", f"it has its {self.limit} participants already")
            record = Record(secrets.token_hex(16))
            write_json(self.path(record.participant), record.data())
            return record

    def load(self, participant: str) -> Record:
        """A participant's record; NoSuchParticipant for an id this study has not given out."""
        path = self.path(participant)
        if not path.is_file():
            raise NoSuchParticipant("participant", "no such participant in this study")
        return read_record(self.study, path)

    def tell(self, participant: str, about: dict[str, Any]) -> Record:
        """Save what a participant told about themselves."""
        checked = check_about(about, "about")
        with self.lock:
            record = self.load(participant)
            record.about = checked
            write_json(self.path(participant), record.data())
            return record

    def rate(self, participant: str, set_index: int, ratings: dict[str, int]) -> Record:
        """Save a participant's ratings of one set (replacing any given before)."""
        checked = check_ratings(self.study, set_index, ratings, "ratings")
        with self.lock:
            record = self.load(participant)
            record.ratings[set_index] = checked
            write_json(self.path(participant), record.data())
            return record
