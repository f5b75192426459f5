"""A real server probed as an attacker would (issue D1-D5, N1): 4xx with one line, errors then proper closes on the
WebSocket, idle connections closed, failed jobs giving their place back, memory bounded, and no traceback in the log."""

import io
import json
import struct
import time
from fractions import Fraction

import httpx
import numpy as np
import pytest
from memory import peak_growth
from PIL import Image
from serving import Server
from test_app import files
from websockets.sync.client import connect

from exprclone import data as samples
from exprclone.io.video import write_video
from exprclone.server.protocol import START_SECONDS

pytestmark = pytest.mark.slow  # servers, browsers, clusters or videos: pytest -m 'not slow' leaves these out

#: the largest rise of one server process's peak memory that one hostile request or frame may cause.
MAX_GROWTH = 500 * 2**20


def png(width: int, height: int, mode: str = "RGB") -> bytes:
    out = io.BytesIO()
    Image.new(mode, (width, height)).save(out, "PNG")
    return out.getvalue()


@pytest.fixture(scope="module")
def hostile():
    """A server with one worker; at the end, its log must hold no traceback."""
    running = Server("--workers", "1")
    yield running
    _, err = running.stop()
    assert "Traceback" not in err, err[-3000:]


@pytest.fixture(scope="module")
def client(hostile):
    with httpx.Client(base_url=hostile.url, timeout=120) as c:
        yield c


STRIP = png(32, 40000)  # D1: 13 kB, shrunk to the detector's 512 pixels it has no columns left


@pytest.mark.parametrize("field", ["source_neutral", "source_expression", "target_neutral"])
def test_a_strip_is_refused_as_any_photo(hostile, client, field):
    growth, r = peak_growth(hostile.process.pid, lambda: client.post("/api/clone", files=files(**{field: ("s.png", STRIP)})))
    assert (
        r.status_code == 400
        and r.json()["error"] == f"{field}: image is too narrow (32x40000 pixels; the long side may be at most 8 times the short one)"
    )
    assert growth < MAX_GROWTH, growth
    print(f"\n{field} strip: peak memory of a server process rose by {growth / 2**20:.0f} MB")
    for path, name in (("/api/landmarks", "photo"), ("/api/compare", field)):
        form = {"photo": ("s.png", STRIP)} if name == "photo" else files(**{field: ("s.png", STRIP)})
        r = client.post(path, files=form)
        assert r.status_code == 400 and r.json()["error"].startswith(f"{name}: image is too narrow"), r.text


TEM = samples.template("003").read_text().splitlines()
IDENTICAL = json.dumps([[500, 500]] * 68)
FLAT_TEM = "\n".join(TEM[:1] + [f"{line.split()[0]} 600" for line in TEM[1:190]] + TEM[190:])  # the real template, squashed onto a line


@pytest.mark.parametrize(
    "name, content, problem",
    [
        ("deep.json", "[" * 100_000 + "]" * 100_000, "invalid landmark file (brackets nested 100000 deep; at most 8)"),
        ("same.json", IDENTICAL, "not a face: the outer eye corners (points 36 and 45) are 0 pixels apart"),
        ("digits.json", "[" + ",".join(["[1" + "0" * 5000 + ", 2]"] + ["[1, 2]"] * 67) + "]", "point 0 has a non-finite coordinate"),
        ("huge.json", "[" + ",".join([f"[{10**400}, 2]"] + ["[1, 2]"] * 67) + "]", "point 0 has a non-finite coordinate"),
        ("count.tem", "1" * 5000 + "\n", "not a .tem template (the first line must be the point count"),
        ("line.tem", FLAT_TEM, "not a face: the landmarks lie (almost) on one line"),
        ("big.json", " " * 1_000_001, "too large for a landmark file"),
    ],
)
def test_broken_landmark_files_are_refused(client, name, content, problem):
    r = client.post("/api/clone", files=files(target_neutral_landmarks=(name, content.encode())))
    assert r.status_code == 400 and r.json()["error"].startswith(f"target_neutral_landmarks: {problem}"), r.text


def refused(socket) -> tuple[str, int]:
    """The error a refused connection is sent, and the code it is then closed with."""
    message = json.loads(socket.recv(timeout=30))
    assert message["type"] == "error", message
    with pytest.raises(Exception) as closed:
        socket.recv(timeout=30)
    return message["error"], closed.value.rcvd.code


def ws(server: Server) -> str:
    return server.url.replace("http", "ws") + "/api/live"


START = json.dumps({"type": "start", "size": 256})
PORTRAIT = samples.path("003").read_bytes()


@pytest.mark.parametrize(
    "messages, error, code",
    [
        ([b"junk"], "live: expected a JSON text message, got a binary message", 1003),
        ([START, "where the portrait goes"], "live: expected a binary message (the portrait, or a frame), got a text message", 1003),
        (['{"type": "start", "only": 5}'], "only: must be a string or a list, got 5", 1008),
        (['{"type": "start", "size": "big"}'], 'size: must be an integer, got "big"', 1008),
        (["[1, 2]"], "live: a text message must be a JSON object", 1008),
        (['{"type": "neutral"}'], "live: the first message must be", 1008),
        ([START, PORTRAIT, b"\0\0\0\1"], "frame: a frame is a 4-byte sequence number and a JPEG or PNG image", 1008),
        ([START, PORTRAIT, b"\0\0\0\1" + STRIP], "frame: image is too narrow (32x40000 pixels", 1008),
        ([START, PORTRAIT, '{"type": "dance"}'], 'live: unknown message type "dance"', 1008),
        ([START, PORTRAIT, '{"type": "start"}'], "live: a start message comes only first", 1008),
    ],
)
def test_a_misused_socket_gets_an_error_then_a_close(hostile, messages, error, code):
    with connect(ws(hostile), max_size=None) as socket:
        for message in messages:
            socket.send(message)
        if PORTRAIT in messages:
            assert json.loads(socket.recv(timeout=60))["type"] == "ready"
        said, closed = refused(socket)
    assert said.startswith(error) and closed == code, (said, closed)


def test_a_bad_option_value_in_a_session_is_answered_and_the_session_goes_on(hostile):
    with connect(ws(hostile), max_size=None) as socket:
        socket.send(START)
        socket.send(PORTRAIT)
        assert json.loads(socket.recv(timeout=60))["type"] == "ready"
        socket.send('{"type": "options", "strength": 3}')
        assert json.loads(socket.recv(timeout=30))["error"].startswith("strength: must be a number from 0 to 2")
        socket.send(struct.pack(">I", 7) + PORTRAIT)
        while isinstance(answer := socket.recv(timeout=60), str):
            pass
        assert answer[:4] == struct.pack(">I", 7)


def test_a_decompression_bomb_frame_is_refused_unread(hostile):
    """D5: a 30000x30000 1-bit PNG (151 kB) as a frame; decoded, it took 5.5 GB."""
    bomb = png(30000, 30000, "1")
    with connect(ws(hostile), max_size=None) as socket:
        socket.send(START)
        socket.send(PORTRAIT)
        assert json.loads(socket.recv(timeout=60))["type"] == "ready"
        growth, (said, code) = peak_growth(hostile.process.pid, lambda: (socket.send(b"\0\0\0\1" + bomb), refused(socket))[1])
    assert said.startswith("frame: image is too large") and code == 1008 and growth < MAX_GROWTH, (said, code, growth)
    print(f"\nbomb frame: peak memory of a server process rose by {growth / 2**20:.0f} MB")


def test_connections_without_a_start_hold_no_slot_and_are_closed(hostile):
    """D4: two sockets that never speak; a real session starts meanwhile, and they are closed after START_SECONDS."""
    opened = time.time()
    with connect(ws(hostile)) as idle, connect(ws(hostile)) as quiet:
        with connect(ws(hostile), max_size=None) as real:
            real.send(START)
            real.send(PORTRAIT)
            assert json.loads(real.recv(timeout=60))["type"] == "ready"
        for socket in (idle, quiet):
            said, code = refused(socket)
            assert said == f"live: no start message and portrait within {START_SECONDS:g} s" and code == 1008
    assert START_SECONDS <= time.time() - opened < START_SECONDS + 10


def test_failed_jobs_give_their_place_back_at_once(client):
    """N1: more jobs that fail later than the server keeps (8); each is accepted, and each failure stays readable."""
    video_files = {"portrait": ("p.jpg", PORTRAIT), "driving_video": ("c.mp4", samples.clip().read_bytes())}
    jobs = []
    for _ in range(10):
        r = client.post("/api/video", files=video_files, data={"neutral_frame": "500", "size": "64"})
        assert r.status_code == 202, r.text
        jobs.append(r.json())
        for _ in range(300):  # each fails within seconds
            if client.get(jobs[-1]["status"]).json()["state"] == "failed":
                break
            time.sleep(0.1)
    states = [client.get(job["status"]).json() for job in jobs]
    assert all(s["state"] == "failed" and s["error"].startswith("driving_video: no frame 500") for s in states), states


def test_swapped_source_photos_are_answered_with_a_warning(hostile, client):
    swapped = files(
        source_neutral=("s.jpg", samples.path("126", "smile").read_bytes()), source_expression=("n.jpg", samples.path("126").read_bytes())
    )
    r = client.post("/api/clone?format=json", files=swapped, data={"method": "elastic"})
    assert r.status_code == 200 and any("swapped" in w for w in r.json()["warnings"]), r.text[:300]
    growth, r = peak_growth(hostile.process.pid, lambda: client.post("/api/clone?format=json", files=files(), data={"method": "elastic"}))
    assert r.status_code == 200 and r.json()["warnings"] == []
    print(f"\na real clone (elastic, for comparison): peak memory of a server process rose by {growth / 2**20:.0f} MB")


def test_a_strip_of_a_video_is_refused_before_its_job(client, tmp_path):
    write_video(tmp_path / "strip.mp4", (np.zeros((640, 32, 3), np.uint8) for _ in range(5)), Fraction(25))
    video_files = {"portrait": ("p.jpg", PORTRAIT), "driving_video": ("v.mp4", (tmp_path / "strip.mp4").read_bytes())}
    r = client.post("/api/video", files=video_files, data={"size": "64"})
    assert r.status_code == 400 and r.json()["error"].startswith("driving_video: image is too narrow (32x640 pixels"), r.text
