"""The study's server without a browser: participants, resuming, and every malformed request a one-line JSON error, never a 500."""

import json

import httpx
import pytest
from fastapi.testclient import TestClient
from hypothesis import given, settings
from hypothesis import strategies as st
from studies import METHOD_NAME, study

from exprclone.study.app import MAX_BODY, create_app
from exprclone.study.folder import read_study
from exprclone.study.participants import order


@pytest.fixture()
def client(study_folder):
    return TestClient(create_app(study_folder), raise_server_exceptions=False)


def new(client) -> str:
    r = client.post("/api/participants")
    assert r.status_code == 201, r.text
    return r.json()["id"]


def items(state: dict, k: int) -> list[str]:
    return [i["id"] for i in state["sets"][k]["items"]]


def one_line_error(r, status: int, *words: str) -> None:
    assert r.status_code == status, r.text
    message = r.json()["error"]
    assert "\n" not in message and all(w in message for w in words), message


def test_a_participant_sees_every_result_of_each_set_and_resumes_where_they_were(client, study_folder):
    pid = new(client)
    state = client.get(f"/api/participants/{pid}").json()
    study = read_study(study_folder)
    assert state["about"] is None and state["ratings"] == {}
    assert [sorted(items(state, k)) for k in range(len(study.sets))] == [sorted(s.items) for s in study.sets]
    for s in state["sets"]:
        for url in [*s["photos"].values(), *(i["image"] for i in s["items"])]:
            r = client.get(url)
            assert r.status_code == 200 and r.headers["content-type"] == "image/png" and r.content[:4] == b"\x89PNG"
    assert client.put(f"/api/participants/{pid}/about", json={"age": 41, "gender": None}).status_code == 200
    scores = dict(zip(items(state, 0), (5, 1, 3)))
    assert client.put(f"/api/participants/{pid}/sets/0", json={"ratings": scores}).status_code == 200
    again = TestClient(create_app(study_folder)).get(f"/api/participants/{pid}").json()  # the server started anew
    assert again["ratings"] == {"0": scores} and again["about"] == {"age": 41, "gender": None}
    assert [items(again, k) for k in (0, 1)] == [items(state, k) for k in (0, 1)]  # the same order
    saved = json.loads((study_folder / "ratings" / f"{pid}.json").read_text())
    assert saved["ratings"] == {"0": scores}


def test_the_order_is_shuffled_by_participant_and_set():
    shown = {tuple(order(f"{n:032x}", k, ["a", "b", "c", "d"])) for n in range(12) for k in (0, 1)}
    assert len(shown) > 4  # 24 participant-sets: a fixed or per-set order would give 1 or 2
    assert order("f" * 32, 3, ["a", "b", "c", "d"]) == order("f" * 32, 3, ["d", "c", "b", "a"])


def test_nothing_the_server_gives_names_a_method(client):
    pid = new(client)
    texts = [
        client.get(path).text
        for path in ("/", "/static/call.js", "/static/study.js", "/static/study.css", "/openapi.json", f"/api/participants/{pid}")
    ]
    assert all(not METHOD_NAME.search(t) for t in texts), [METHOD_NAME.search(t) for t in texts]
    assert METHOD_NAME.search("a.png by e+md, Global warp") and not METHOD_NAME.search("localStorage")  # the check sees them


@pytest.mark.parametrize("path", ["/key.json", "/images/key.json", "/images/..%2Fkey.json", "/static/..%2F..%2Fkey.json", "/study.json"])
def test_the_key_cannot_be_fetched(client, path):
    r = client.get(path)
    assert r.status_code == 404 and "e+md" not in r.text


@pytest.mark.parametrize(
    "path, status, words",
    [
        ("/api/participants/zz", 400, ("participant",)),
        (f"/api/participants/{'A' * 32}", 400, ("participant",)),
        (f"/api/participants/{'a' * 32}", 404, ("no such participant",)),
        ("/images/0123456789abcdef.png", 404, ("no image",)),
        ("/images/nothing", 404, ("no image",)),
    ],
)
def test_bad_ids_are_refused(client, path, status, words):
    one_line_error(client.get(path), status, *words)


@pytest.mark.parametrize(
    "body, words",
    [
        ({"ratings": {}}, ("a score for each of its results",)),
        ({"ratings": "all fives"}, ("ratings",)),
        ({"scores": {}}, ("ratings",)),
        (["not", "an", "object"], ("request",)),
    ],
)
def test_a_set_s_ratings_must_score_each_result(client, body, words):
    pid = new(client)
    one_line_error(client.put(f"/api/participants/{pid}/sets/0", json=body), 400, *words)


@pytest.mark.parametrize("bad", [0, 6, -1, 2.5, "3", True, None, 10**30])
def test_a_score_is_a_whole_number_from_1_to_5(client, study_folder, bad):
    pid = new(client)
    state = client.get(f"/api/participants/{pid}").json()
    ratings = dict.fromkeys(items(state, 0), 3) | {items(state, 0)[1]: bad}
    one_line_error(client.put(f"/api/participants/{pid}/sets/0", json={"ratings": ratings}), 400, "ratings")
    assert json.loads((study_folder / "ratings" / f"{pid}.json").read_text())["ratings"] == {}  # nothing saved


def test_results_of_another_set_or_no_set_are_refused(client):
    pid = new(client)
    state = client.get(f"/api/participants/{pid}").json()
    other_set = dict.fromkeys(items(state, 1), 3)
    one_line_error(client.put(f"/api/participants/{pid}/sets/0", json={"ratings": other_set}), 400, "is not one of its results")
    one_line_error(client.put(f"/api/participants/{pid}/sets/2", json={"ratings": other_set}), 400, "no set 2")
    one_line_error(client.put(f"/api/participants/{pid}/sets/-1", json={"ratings": other_set}), 400, "index")
    one_line_error(client.put(f"/api/participants/{'b' * 32}/sets/1", json={"ratings": other_set}), 404, "no such participant")


@pytest.mark.parametrize(
    "about, words",
    [
        ({"age": 0, "gender": None}, ("age",)),
        ({"age": 300, "gender": None}, ("age",)),
        ({"age": "30", "gender": None}, ("age",)),
        ({"age": 30.5, "gender": None}, ("age",)),
        ({"age": None, "gender": "robot"}, ("gender must be one of female, male, other",)),
        ({"age": None, "gender": None, "name": "Ann"}, ("name",)),
        ({"age": None}, ("gender", "missing")),
    ],
)
def test_age_and_gender_are_checked(client, about, words):
    one_line_error(client.put(f"/api/participants/{new(client)}/about", json=about), 400, *words)


def test_a_body_over_the_limit_is_refused(client):
    pid = new(client)
    r = client.put(f"/api/participants/{pid}/about", content=b"{" + b" " * MAX_BODY + b"}", headers={"content-type": "application/json"})
    one_line_error(r, 413, "too large")


def test_the_study_takes_so_many_participants(study_folder):
    client = TestClient(create_app(study_folder, max_participants=2))
    new(client), new(client)
    one_line_error(client.post("/api/participants"), 409, "2 participants")


#: any JSON document (small).
JSON = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats(allow_nan=False, allow_infinity=False) | st.text(max_size=20),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=20), inner, max_size=4),
    max_leaves=12,
)


def test_any_json_is_answered_without_a_500(client):
    pid = new(client)
    ids = st.sampled_from(items(client.get(f"/api/participants/{pid}").json(), 0))
    ratings = st.dictionaries(ids | st.text(max_size=20), JSON | st.integers(0, 6), max_size=4)

    @settings(max_examples=80, deadline=None)
    @given(body=JSON, scores=ratings)
    def check(body, scores):
        for path, sent in (("sets/0", body), ("sets/0", {"ratings": scores}), ("about", body), ("about", {"age": body, "gender": body})):
            r = client.put(f"/api/participants/{pid}/{path}", json=sent)
            assert r.status_code in (200, 400) and (r.status_code == 200 or "\n" not in r.json()["error"]), (sent, r.text)

    check()


def test_serving_a_folder_that_is_not_a_study_is_one_line(tmp_path):
    p = study("serve", tmp_path, "--port", "9")
    assert (
        p.returncode == 2
        and p.stderr.strip() == f"exprclone: error: {tmp_path}: not a study folder (no study.json): make one with exprclone study make"
    )


def test_an_address_starts_a_few_participants_an_hour(study_folder):
    """Plain POSTs cannot use up the study's places nor rate as many made-up participants: an address starts at most
    ``new_per_address`` an hour, the next is answered 429 with when to try again."""
    client = TestClient(create_app(study_folder, new_per_address=3), raise_server_exceptions=False)
    [new(client) for _ in range(3)]
    r = client.post("/api/participants")
    one_line_error(r, 429, "at most 3 per 3600 s")
    assert 3500 <= int(r.headers["retry-after"]) <= 3601


def test_parallel_requests_of_one_address_are_paced_as_one_after_another():
    """The participants' route runs in FastAPI's thread pool: 32 threads counting at once for one address, switching
    as often as Python can, admit exactly ``count`` (without the lock, up to 10 of 5 got through)."""
    import sys
    import threading

    from exprclone.server.runtime.limits import Paced, TooMany

    interval = sys.getswitchinterval()
    sys.setswitchinterval(1e-6)
    try:
        for _ in range(30):
            paced, start, admitted = Paced(5, 3600), threading.Barrier(32), []

            def ask(paced=paced, start=start, admitted=admitted):
                start.wait()
                try:
                    paced.admit("10.0.0.1", 0.0)
                    admitted.append(True)
                except TooMany:
                    pass

            threads = [threading.Thread(target=ask) for _ in range(32)]
            for t in threads:
                t.start()
            for t in threads:
                t.join()
            assert len(admitted) == 5
    finally:
        sys.setswitchinterval(interval)


@pytest.mark.parametrize("path", ["/docs", "/redoc", "/openapi.json"])
def test_the_study_serves_no_api_documentation(client, path):
    assert client.get(path).status_code == 404


@pytest.mark.slow  # a real server: uvicorn reads X-Forwarded-For, not the test client
@pytest.mark.parametrize("proxy", [None, "127.0.0.1"])
def test_an_address_is_the_connections_unless_a_proxy_the_server_believes_says_otherwise(study_folder, proxy):
    """A local client cannot pose as many addresses by sending X-Forwarded-For: without ``--forwarded-allow-ips`` its
    own address counts, whatever it says; behind a proxy named by it (nginx on this machine), the address the proxy
    gives counts, each its own."""
    from serving import Server

    believed = () if proxy is None else ("--forwarded-allow-ips", proxy)
    running = Server(str(study_folder), "--new-per-address", "2", *believed, command=("study", "serve"))
    try:
        said = [f"198.51.100.{n}" for n in (1, 2, 3, 3, 3)]
        codes = [httpx.post(f"{running.url}/api/participants", headers={"X-Forwarded-For": a}).status_code for a in said]
    finally:
        running.stop()
    assert codes == ([201, 201, 429, 429, 429] if proxy is None else [201, 201, 201, 201, 429]), codes
