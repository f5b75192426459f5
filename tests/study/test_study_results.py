"""exprclone study results: Table 1 from the ratings saved by the study's server, checked against SciPy's t-interval."""

import numpy as np
import pytest
from fastapi.testclient import TestClient
from scipy import stats
from studies import METHODS, SETS, key, results_csv, study

from exprclone.study.app import create_app
from exprclone.study.results import OVERALL, results

#: what three participants tell and score: (age, gender, {set: {method: score}}); the third rates the first set only.
ANSWERS = [
    (25, "female", {0: {"global": 1, "elastic+eri": 4, "e+md": 5}, 1: {"global": 2, "elastic+eri": 3, "e+md": 4}}),
    (60, "male", {0: {"global": 2, "elastic+eri": 4, "e+md": 3}, 1: {"global": 1, "elastic+eri": 5, "e+md": 5}}),
    (None, None, {0: {"global": 3, "elastic+eri": 4, "e+md": 4}}),
]


def half_width(values) -> float:
    """SciPy's 95% t-interval of the mean of ``values``, as a half-width (0 for equal values, where SciPy gives NaN)."""
    if np.ptp(values) == 0:
        return 0.0
    low, high = stats.t.interval(0.95, len(values) - 1, loc=np.mean(values), scale=stats.sem(values))
    return (high - low) / 2


@pytest.fixture()
def rated(study_folder):
    """The study, rated by :data:`ANSWERS` through its server."""
    client = TestClient(create_app(study_folder))
    methods = key(study_folder)
    for age, gender, sets in ANSWERS:
        pid = client.post("/api/participants").json()["id"]
        state = client.put(f"/api/participants/{pid}/about", json={"age": age, "gender": gender}).json()
        for k, scores in sets.items():
            ratings = {i["id"]: scores[methods[i["id"]][1]] for i in state["sets"][k]["items"]}
            assert client.put(f"/api/participants/{pid}/sets/{k}", json={"ratings": ratings}).status_code == 200
    return study_folder


def test_the_csv_has_each_set_and_method_with_n_mean_and_t_interval(rated, tmp_path):
    rows = results_csv(rated, tmp_path / "table.csv")
    assert [(r["set"], r["method"]) for r in rows] == [(name, m) for name, _, _ in SETS for m in METHODS]  # no total rows
    for row in rows:
        k = [name for name, _, _ in SETS].index(row["set"])
        scores = [sets[k][row["method"]] for _, _, sets in ANSWERS if k in sets]
        assert int(row["n"]) == len(scores) == (3 if k == 0 else 2)
        assert float(row["mean"]) == pytest.approx(np.mean(scores), abs=5e-5)
        assert float(row["ci95"]) == pytest.approx(half_width(scores), abs=5e-5)
    assert float(rows[1]["ci95"]) == 0  # three fours


def test_the_overall_row_and_the_participants(rated):
    found = results(rated)
    for cell in found.overall:
        assert cell.set == OVERALL
        by_person = [[s[cell.method] for s in sets.values()] for _, _, sets in ANSWERS]
        assert cell.n == 5 and cell.mean == pytest.approx(np.mean(sum(by_person, [])))
        assert cell.ci95 == pytest.approx(half_width([np.mean(p) for p in by_person]))  # over participants, not ratings
    p = study("results", rated)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert lines[0].split() == ["set", *METHODS] and lines[3].startswith(OVERALL)
    assert lines[1].startswith("Fig. A") and "2.00 ± 2.48 (3)" in lines[1]  # global: 1, 2, 3
    assert "3 participants (1 female, 1 male, 0 other, 1 not given; aged 25-60)" in p.stdout


def test_a_study_without_ratings_is_refused(study_folder, tmp_path):
    TestClient(create_app(study_folder)).post("/api/participants")  # a participant who rated nothing
    p = study("results", study_folder, "--csv", tmp_path / "table.csv")
    assert (
        p.returncode == 2
        and p.stderr.strip()
        == f"exprclone: error: {study_folder}: no ratings yet: serve the study (exprclone study serve) and let participants rate it"
    )
    assert not (tmp_path / "table.csv").exists()


@pytest.mark.parametrize(
    "spoil, message",
    [
        (lambda folder: (folder / "key.json").unlink(), "not a study folder (no key.json)"),
        (lambda folder: (folder / "ratings" / f"{'c' * 32}.json").write_text("{"), "not a participant's ratings"),
        (lambda folder: (folder / "ratings" / f"{'c' * 32}.json").write_text('{"format": 1, "participant": "x"}'), "its id is not"),
    ],
)
def test_a_spoilt_study_is_one_line(rated, spoil, message):
    spoil(rated)
    p = study("results", rated)
    assert p.returncode == 2 and message in p.stderr and len(p.stderr.strip().splitlines()) == 1, p.stderr


def test_the_csv_goes_nowhere_it_should_not(rated):
    p = study("results", rated, "--csv", rated / "key.json")
    assert p.returncode == 2 and "unknown output format '.json'" in p.stderr
    p = study("results", rated, "--csv", rated / "gone" / "t.csv")
    assert p.returncode == 2 and "does not exist" in p.stderr


def test_a_set_name_a_spreadsheet_would_run_is_written_inert(study_folder, tmp_path):
    """A set named like a formula reaches the CSV with a leading apostrophe, as the other cells keep their text."""
    from exprclone.study.results import Cell, csv_text

    text = csv_text([Cell("=HYPERLINK(1)", "e+md", 1, 4.0, float("nan")), Cell("Fig. 11", "global", 1, 3.0, float("nan"))])
    rows = [line.split(",") for line in text.splitlines()[1:]]
    assert rows[0][0] == "'=HYPERLINK(1)" and rows[1][0] == "Fig. 11"


def test_song_et_als_method_is_a_column_of_table_1(tmp_path):
    """The paper's Table 1 rates Song et al.'s method beside global warping + ERI, elastic + ERI and E+MD: a study of
    those methods, in the table's order, rated by one participant, gives its column in that place."""
    from studies import make

    table_1 = ("global+eri", "song", "elastic+eri", "e+md")
    p = make(tmp_path, sets=SETS[:1], methods=table_1)
    assert p.returncode == 0, p.stderr
    folder = tmp_path / "study"
    client, methods = TestClient(create_app(folder)), key(folder)
    pid = client.post("/api/participants").json()["id"]
    state = client.get(f"/api/participants/{pid}").json()
    score = dict(zip(table_1, (3, 2, 4, 5)))
    ratings = {i["id"]: score[methods[i["id"]][1]] for i in state["sets"][0]["items"]}
    assert client.put(f"/api/participants/{pid}/sets/0", json={"ratings": ratings}).status_code == 200
    shown = study("results", folder).stdout.splitlines()
    assert shown[0].split() == ["set", *table_1]
    assert shown[1].split() == ["Fig.", "A", "3.00", "(1)", "2.00", "(1)", "4.00", "(1)", "5.00", "(1)"]
