"""The expression judge on real photos: trained on some London people, it tells the smiles of others from their neutral faces."""

import numpy as np
from conftest import LONDON, need_full_data

from exprclone.evaluation.judge import MIN_PEOPLE, SMILING, SmileJudge, trained_without
from exprclone.evaluation.london import Dataset


def test_it_tells_other_peoples_smiles_from_their_neutral_faces(photo):
    people = sorted(p.name[:3] for p in need_full_data(LONDON / "neutral_front").glob("*_03.jpg"))[:24]
    faces = {(p, kind): photo(p, kind)[1] for p in people for kind in ("neutral", "smile")}
    judge = SmileJudge.train([faces[p, "neutral"] for p in people[:16]], [faces[p, "smile"] for p in people[:16]])
    held = np.array([[judge(faces[p, kind]) for kind in ("neutral", "smile")] for p in people[16:]])
    assert (held[:, 1] > held[:, 0]).all()  # each person's smile more than their neutral face
    assert ((held[:, 0] < SMILING).sum() + (held[:, 1] >= SMILING).sum()) / held.size >= 0.75


def test_it_is_trained_without_the_people_left_out(photo, london):
    data = Dataset.open(london)  # three people: too few to learn from
    landmarks = {data.path(p, s): photo(p, "smile" if s else "neutral")[1] for p in data.ids for s in (False, True)}
    assert len(data.ids) < MIN_PEOPLE and trained_without(data, landmarks, ()) is None
