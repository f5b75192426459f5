"""The scores of exprclone evaluate: they must measure what they claim."""

import numpy as np
import pytest

from exprclone import geometry
from exprclone.evaluate import Dataset, smile_strength, summarise
from exprclone.evaluation import SAME_PERSON, FaceDescriptor, identity_distance, landmark_error
from exprclone.layout import DLIB68


@pytest.fixture(scope="module")
def descriptor():
    return FaceDescriptor()


def test_result_equal_to_the_real_smile_scores_zero(photo):
    _, truth = photo("003", "smile")
    err = landmark_error(truth, truth, DLIB68)
    assert err == {"overall": 0.0, "mouth": 0.0, "eyes_brows": 0.0}


def test_similarity_transformed_copy_scores_the_same(photo):
    _, truth = photo("003", "smile")
    _, result = photo("003")
    t = np.array([[0.9 * np.cos(0.2), -0.9 * np.sin(0.2), 40.0], [0.9 * np.sin(0.2), 0.9 * np.cos(0.2), -25.0]])
    a, b = landmark_error(result, truth, DLIB68), landmark_error(geometry.apply(t, result), truth, DLIB68)
    assert a == pytest.approx(b, rel=1e-9)
    assert a["overall"] > 0


def test_no_change_scores_worse_than_the_real_smile(photo):
    errors = {}
    for face_id in ("003", "005", "006", "007"):
        _, neutral = photo(face_id)
        _, smile = photo(face_id, "smile")
        errors[face_id] = (smile_strength(neutral, smile), landmark_error(neutral, smile, DLIB68))
        assert errors[face_id][1]["overall"] > landmark_error(smile, smile, DLIB68)["overall"] + 0.005
    # for the broadest of these smiles the change is mostly at the mouth
    _, broadest = max(errors.values(), key=lambda e: e[0])
    assert broadest["mouth"] > broadest["eyes_brows"]


def test_identity_is_small_for_one_person_and_large_across_people(photo, descriptor):
    (n3, l3), (s3, ls3), (n5, l5) = photo("003"), photo("003", "smile"), photo("005")
    d3 = descriptor(n3, l3)
    assert identity_distance(d3, descriptor(s3, ls3)) < SAME_PERSON
    assert identity_distance(d3, descriptor(n5, l5)) > SAME_PERSON


def test_smile_strength_is_zero_for_no_change_and_positive_for_a_smile(photo):
    _, neutral = photo("005")
    _, smile = photo("005", "smile")
    assert smile_strength(neutral, neutral) == pytest.approx(0.0, abs=1e-9)
    assert smile_strength(neutral, smile) > 0.0


def test_pairs_are_reproducible_and_of_different_people(london):
    data = Dataset.open(london)
    assert len(data.ids) == 72
    p1, p2 = data.pairs(20, seed=3), data.pairs(20, seed=3)
    assert p1 == p2 and len(set(p1)) == 20 and all(a != b for a, b in p1)
    assert data.pairs(20, seed=4) != p1
    assert len(data.pairs(0, seed=0)) == 72 * 71


def test_summary_counts_failures_and_never_drops_them():
    def row(method, pair, mouth, failed="", smile=0.05):
        score = "" if failed else mouth
        return {
            "source": pair[0],
            "target": pair[1],
            "method": method,
            "target_smile": smile,
            "failed": failed,
            "overall": score,
            "mouth": score,
            "eyes_brows": score,
            "identity": "" if failed else 0.3 + mouth * 10,
        }

    rows = [
        row("global", "ab", 0.02, smile=0.3),
        row("global", "ac", 0.0, failed="no face found"),
        row("global", "ad", 0.04),
        row("e+md", "ab", 0.01, smile=0.3),
        row("e+md", "ac", 0.03),
        row("e+md", "ad", 0.035),
    ]
    g, e = summarise(rows)
    assert g["pairs"] == 3 and g["failed"] == 1 and e["failed"] == 0
    assert g["overall_mean"] == pytest.approx(0.03) and g["same_person"] == pytest.approx(0.5)
    # paired with global only where both succeeded: (0.01 - 0.02 + 0.035 - 0.04) / 2
    assert e["mouth_vs_baseline"] == pytest.approx(-0.0075) and g["mouth_vs_baseline"] == 0
    assert summarise(rows, strong_only=True)[0]["pairs"] == 1
