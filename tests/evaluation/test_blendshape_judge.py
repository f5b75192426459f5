"""The blendshape judge of exprclone evaluate: it must tell a clone that moves the face as the source did from one that does not."""

import itertools

import numpy as np
import pytest

from exprclone import data as samples
from exprclone.evaluation import runner
from exprclone.evaluation.blendshape_judge import COLUMNS, distances, judged, rise_kept
from exprclone.evaluation.london import Dataset
from exprclone.evaluation.statistics import blendshape_summary
from exprclone.landmarks.backends import shared
from exprclone.landmarks.blendshapes import Blendshapes


@pytest.fixture(scope="module")
def rows():
    """Every ordered pair of the three sample people, scored with e+md (and the two references): {pair: {method: row}}."""
    data = Dataset.open(samples.london())
    landmarks = {data.path(p, s): shared("dlib").detect(runner.photo(data.path(p, s))) for p in data.ids for s in (False, True)}
    return {
        pair: {r["method"]: r for r in runner.score_pair(data, pair, ("e+md",), landmarks)} for pair in itertools.permutations(data.ids, 2)
    }


def test_the_regions_distances_make_up_the_total_on_real_faces():
    judge = Blendshapes()
    a, b = judge.scores(samples.photo("001", "smile")), judge.scores(samples.photo("126"))
    d = distances(a, b)
    assert d["total"] ** 2 == pytest.approx(d["mouth"] ** 2 + d["eyes"] ** 2 + d["brows"] ** 2)
    assert d["mouth"] > d["brows"] and distances(a, a) == dict.fromkeys(d, 0.0)


def test_a_clone_is_closer_to_its_sources_expression_than_the_targets_neutral_face_is(rows):
    mouth = np.array([[float(r[m]["to_source_mouth"]) for m in ("e+md", "no change")] for r in rows.values()])
    # on average, and on most pairs: 003's neutral face already smiles a little (mouthSmile 0.3), and its faint smile
    # cloned onto 126 is no closer to it than 126's neutral face is (0.500 against 0.476)
    assert mouth[:, 0].mean() < mouth[:, 1].mean() - 0.1 and (mouth[:, 0] < mouth[:, 1]).sum() >= 5


def test_a_clone_moves_the_face_more_as_a_clear_source_did_than_no_change_does(rows):
    # no change's change is none: its distance is the source's own change, 1.04 for 001 and 1.35 for 126; 003 smiles
    # faintly (0.18), and the same small motion reads as another on another face (its clones: 0.22 and 0.53)
    clear = [pair for pair in rows.values() if float(pair["no change"]["change"]) > 0.5]
    assert len(clear) == 4 and all(float(p["e+md"]["change"]) < float(p["no change"]["change"]) - 0.2 for p in clear)


def test_the_clone_keeps_part_of_the_sources_rise_and_no_change_none(rows):
    for pair in rows.values():
        assert pair["no change"]["rise_kept"] == 0.0 and pair["real"]["to_real"] == 0.0
        assert pair["e+md"]["rise_kept"] > 0.2  # 0.35 to 1.7: the clone raises what the source raised


def test_what_is_not_scored_is_left_blank():
    scores = np.linspace(0, 1, 52)
    assert judged(None, (scores, scores), (scores, scores)) == dict.fromkeys(COLUMNS, "")
    partly = judged(scores, (None, scores), (scores, None))
    assert partly["to_source"] == 0.0 and partly["to_real"] == "" and partly["rise_kept"] == ""
    assert np.isnan(rise_kept(scores, scores, scores, scores))  # a source that does not move has no rise to keep


def test_the_summary_gives_each_column_with_an_interval(rows):
    e_md = [pair["e+md"] for pair in rows.values()] + [dict.fromkeys(COLUMNS, "")]
    line = blendshape_summary(e_md)
    for key in COLUMNS:
        assert line[f"{key}_n"] == 6 and line[f"{key}_low"] <= line[key] <= line[f"{key}_high"]
    assert line["to_source"] == pytest.approx(np.mean([float(r["to_source"]) for r in e_md[:-1]]))
