"""Fair shares (issue 53): one client cannot take more than its share of the server; a second client's request is
served while the first holds its limit. Clients are named by their API key when the operator gives the server keys,
else by their address (behind a proxy the server believes, ``--forwarded-allow-ips``, the one it says).

The rules themselves on the server's own counters (no server: fast), then on a real server."""

import re
import time
from collections import Counter
from types import SimpleNamespace

import httpx
import pytest
from serving import Server

from exprclone import data as samples
from exprclone.errors import ExprCloneError
from exprclone.server.runtime.clients import read_keys
from exprclone.server.runtime.edits import Edit, Edits
from exprclone.server.runtime.jobs import RETRY_RUNNING, check_room
from exprclone.server.runtime.limits import Busy, Gate, TooMany
from exprclone.server.runtime.protocol import Misuse, Slots
from exprclone.server.settings import Settings

KEYS = {"A": "key-of-client-a-0123456789", "B": "key-of-client-b-0123456789"}


def test_the_gate_keeps_a_place_for_others_and_says_when_one_is_likely_free():
    gate = Gate(limit=3, workers=1, per_client=2)
    with gate.entered("a"), gate.entered("a"):
        with pytest.raises(TooMany, match="this client holds 2 requests at work or waiting already, its share"):
            with gate.entered("a"):
                pass
        with gate.entered("b"), pytest.raises(Busy) as full:  # the third place was b's; the gate is full now
            with gate.entered("c"):
                pass
    assert full.value.retry_after == 2  # nothing timed yet: the default
    assert len(gate.timing.seconds) == 3  # the requests let in, timed as they left
    gate.timing.seconds.clear()
    gate.timing.seconds.extend([9.5, 10.2, 30.0])
    assert gate.timing.retry_after(workers=1) == 11 and gate.timing.retry_after(workers=4) == 3  # the median's share
    assert gate.inside.total() == 0


def test_an_edit_beyond_a_clients_share_is_429_and_anothers_is_kept():
    edits = Edits(limit=4, ttl=600, per_client=2)
    for _ in range(2):
        edits.add(Edit(None, None, {}, None, "a"))
    with pytest.raises(TooMany) as refused:
        edits.add(Edit(None, None, {}, None, "a"))
    assert "this client holds 2 edits already" in str(refused.value) and 599 <= refused.value.retry_after <= 600
    assert edits.add(Edit(None, None, {}, None, "b"))


def test_a_video_job_beyond_a_clients_share_is_429_and_the_store_bound_is_503():
    ended = time.time() - 100
    check_room([(None, "a"), (ended, "b")], limit=3, ttl=3600, client="b", per_client=2)  # b holds one: room
    with pytest.raises(TooMany) as mine:
        check_room([(None, "a"), (None, "a")], limit=3, ttl=3600, client="a", per_client=2)
    assert mine.value.retry_after == RETRY_RUNNING and "when one ends" in str(mine.value)
    with pytest.raises(TooMany) as done:
        check_room([(ended, "a"), (None, "a")], limit=3, ttl=3600, client="a", per_client=2)
    assert 3499 <= done.value.retry_after <= 3500 and "the first done one expires" in str(done.value)
    with pytest.raises(Busy, match="3 video jobs are queued"):
        check_room([(None, "a"), (None, "b"), (None, "c")], limit=3, ttl=3600, client="d", per_client=2)


def test_a_live_session_beyond_a_clients_share_is_refused_and_anothers_starts():
    work = SimpleNamespace(settings=Settings(max_live=3, max_live_per_client=1), live_sessions=Counter())
    mine = Slots(work, "a")
    mine.take()
    with pytest.raises(Misuse, match="this client runs 1 sessions already, its share") as refused:
        Slots(work, "a").take()
    assert refused.value.code == 1013  # try again later
    Slots(work, "b").take()
    mine.release()
    assert work.live_sessions == Counter({"b": 1})


@pytest.mark.parametrize(
    "text, problem",
    [("", "must hold API keys"), ("short\n", "each of at least 16 characters"), ("a key with spaces in it\n", "no spaces")],
)
def test_a_keys_file_must_hold_keys(tmp_path, text, problem):
    path = tmp_path / "keys"
    path.write_text(text)
    with pytest.raises(ExprCloneError, match=problem):
        read_keys(str(path))
    path.write_text(f"# the keys\n{KEYS['A']}\n\n{KEYS['B']}\n")
    assert len(read_keys(str(path))) == 2 and KEYS["A"] not in read_keys(str(path))  # digests only


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    """A server with two API keys, believing the X-Forwarded-For of this machine (as behind nginx on it), each client's
    share one edit and one video job."""
    keys = tmp_path_factory.mktemp("keys") / "keys.txt"
    keys.write_text("\n".join(KEYS.values()) + "\n")
    shares = ("--max-edits-per-client", "1", "--max-jobs-per-client", "1")
    running = Server("--workers", "1", "--max-live", "0", "--api-keys", str(keys), "--forwarded-allow-ips", "127.0.0.1", *shares)
    with httpx.Client(base_url=running.url, timeout=120) as client:
        yield client
    _, err = running.stop()
    assert "Traceback" not in err, err[-3000:]


def as_client(name: str) -> dict[str, str]:
    """The headers of a client: ``A`` or ``B`` by their key, an address (as the proxy says it) otherwise."""
    return {"X-API-Key": KEYS[name]} if name in KEYS else {"X-Forwarded-For": name}


PORTRAIT = {"target_neutral": ("p.jpg", samples.path("003").read_bytes())}
VIDEO = {"portrait": ("p.jpg", samples.path("003").read_bytes()), "driving_video": ("c.mp4", samples.clip().read_bytes())}


@pytest.mark.slow  # servers, browsers, clusters or videos: pytest -m 'not slow' leaves these out
def test_an_unknown_key_is_refused(server):
    r = server.post("/api/landmarks", files={"photo": PORTRAIT["target_neutral"]}, headers={"X-API-Key": "k" * 20})
    assert r.status_code == 401 and r.json() == {"error": "X-API-Key: not a key this server knows"}


def held(r: httpx.Response, what: str) -> None:
    """429: the client holds its share of ``what``; Retry-After as the message says."""
    assert r.status_code == 429 and f"this client holds 1 {what} already, its share" in r.json()["error"], r.text
    assert r.headers["Retry-After"] == re.search(r"try again in (\d+) s", r.json()["error"])[1]


@pytest.mark.slow
@pytest.mark.parametrize("first, second", [("A", "B"), ("203.0.113.7", "203.0.113.8")])
def test_a_client_holding_its_edits_keeps_no_one_else_out(server, first, second):
    """Two clients by their keys, then two by their addresses: the first holds its one edit (and renders it, so that it
    would never expire); its next is refused, the second's is made."""
    data = {"expression": "smile"}
    made = server.post("/api/edits", files=PORTRAIT, data=data, headers=as_client(first))
    assert made.status_code == 201, made.text
    assert server.post(made.json()["render"], data={"strength": "0.5"}, headers=as_client(first)).status_code == 200
    held(server.post("/api/edits", files=PORTRAIT, data=data, headers=as_client(first)), "edits")
    assert server.post("/api/edits", files=PORTRAIT, data=data, headers=as_client(second)).status_code == 201


@pytest.mark.slow
def test_a_client_holding_its_video_jobs_keeps_no_one_else_out(server):
    first = server.post("/api/video", files=VIDEO, data={"size": "128"}, headers=as_client("A"))
    assert first.status_code == 202, first.text
    held(server.post("/api/video", files=VIDEO, data={"size": "128"}, headers=as_client("A")), "video jobs (queued, running or kept)")
    assert server.post("/api/video", files=VIDEO, data={"size": "128"}, headers=as_client("B")).status_code == 202
