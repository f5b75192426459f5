"""deploy/nginx.conf, as shipped, in front of a real server: requests and live sessions pass, nginx's refusals are JSON,
and the slow or silent clients that uvicorn keeps forever are cut off."""

import json
import os
import socket
import time

import httpx
import pytest
from serving import Server, nginx
from websockets.sync.client import connect

from exprclone import data as samples

pytestmark = pytest.mark.slow  # servers, browsers, clusters or videos: pytest -m 'not slow' leaves these out

#: the shipped client_header_timeout, in seconds.
HEADER_TIMEOUT = 10


@pytest.fixture(scope="module")
def proxy(tmp_path_factory):
    """nginx on a free port of 127.0.0.1 with the shipped configuration, in front of ``exprclone serve``: its URL."""
    backend = Server("--workers", "1")
    try:
        with nginx(tmp_path_factory.mktemp("nginx"), [backend.port]) as url:
            yield url
    finally:
        _, err = backend.stop()
    assert "Traceback" not in err, err


def test_requests_pass_and_errors_stay_json(proxy):
    assert httpx.get(f"{proxy}/api/health").json()["status"] == "ok"
    r = httpx.post(f"{proxy}/api/landmarks", files={"photo": ("p.jpg", samples.path("001").read_bytes())}, timeout=120)
    assert r.status_code == 200 and len(r.json()["landmarks"]) == 68
    r = httpx.post(f"{proxy}/api/landmarks", files={"photo": ("p.jpg", b"not an image")}, timeout=120)
    assert r.status_code == 400 and r.json()["error"].startswith("photo: not an image")  # exprclone's own answer, passed on
    r = httpx.post(f"{proxy}/api/landmarks", files={"photo": ("p.jpg", os.urandom(21 * 2**20))}, timeout=120)
    assert r.status_code == 413 and r.json() == {"error": "upload too large: at most 20 MB per request"}  # nginx's, as JSON


def test_a_live_session_passes_and_closes_pass_through(proxy):
    live = proxy.replace("http", "ws") + "/api/live"
    with connect(live, max_size=None) as session:
        session.send(json.dumps({"type": "start", "size": 256}))
        session.send(samples.path("003").read_bytes())
        assert json.loads(session.recv(timeout=60))["type"] == "ready"
    with connect(live) as misuse:
        misuse.send(b"junk")
        assert json.loads(misuse.recv(timeout=30))["error"].startswith("live: expected a JSON text message")
        with pytest.raises(Exception) as closed:
            misuse.recv(timeout=30)
        assert closed.value.rcvd.code == 1003


def test_silent_and_slow_clients_are_cut_off(proxy):
    """N2: a socket that says nothing and one that sends its headers a byte a second; uvicorn alone keeps both forever."""
    port = int(proxy.rsplit(":", 1)[1])
    silent, slow = (socket.create_connection(("127.0.0.1", port)) for _ in range(2))
    request = b"GET /api/health HTTP/1.1\r\nHost: x\r\nX-Slow: " + b"a" * 100
    start, closed = time.time(), {}
    for byte in request[: 3 * HEADER_TIMEOUT]:
        for name, s in (("silent", silent), ("slow", slow)):
            if name in closed:
                continue
            try:
                if name == "slow":
                    s.send(bytes([byte]))
                s.settimeout(0.05)
                if s.recv(100) == b"":
                    closed[name] = time.time() - start
            except TimeoutError:
                pass
            except OSError:
                closed[name] = time.time() - start
        if len(closed) == 2:
            break
        time.sleep(1)
    for s in (silent, slow):
        s.close()
    assert set(closed) == {"silent", "slow"} and max(closed.values()) < HEADER_TIMEOUT + 3, closed
