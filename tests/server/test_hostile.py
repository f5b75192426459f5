"""A real server probed as an attacker would (issue D1-D5, N1): 4xx with one line, errors then proper closes on the
WebSocket, idle connections closed, failed jobs giving their place back, memory bounded, and no traceback in the log."""

import contextlib
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
from exprclone.server.runtime.protocol import START_SECONDS

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
        ("deep.json", "[" * 100_000 + "]" * 100_000, "not JSON of this kind: nested 100000 deep (at most 8)"),
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
        (["[" * 4000], "live: a text message must be a JSON object", 1008),  # under the message limit, nested too deep
        ([START, PORTRAIT, "[" * 4000], "live: a text message must be a JSON object", 1008),
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


#: the most one video upload may add to a server process's peak memory, whatever it holds under the body limit.
MAX_VIDEO_GROWTH = 200 * 2**20


def mjpeg_packets(width: int, height: int) -> list:
    """One grey frame of ``width`` by ``height`` encoded as Motion JPEG: its packets."""
    import av

    codec = av.CodecContext.create("mjpeg", "w")
    codec.width, codec.height, codec.pix_fmt, codec.time_base = width, height, "yuvj420p", Fraction(1, 25)
    frame = av.VideoFrame.from_ndarray(np.full((height, width, 3), 128, np.uint8), format="rgb24").reformat(format="yuvj420p")
    return list(codec.encode(frame)) + list(codec.encode(None))


def mjpeg_video(sizes: list[tuple[int, int]], declared: tuple[int, int]) -> bytes:
    """A Matroska file of Motion JPEG frames of ``sizes``, its header declaring frames of ``declared`` size."""
    import av

    out = io.BytesIO()
    with av.open(out, "w", format="matroska") as container:
        stream = container.add_stream("mjpeg", rate=25)
        stream.width, stream.height, stream.pix_fmt = *declared, "yuvj420p"
        for k, packet in enumerate(p for size in sizes for p in mjpeg_packets(*size)):
            packet.stream, packet.pts, packet.dts, packet.time_base = stream, k, k, Fraction(1, 25)
            container.mux(packet)
    return out.getvalue()


def test_a_video_of_huge_frames_is_refused_from_its_headers(hostile, client):
    """A 1 MB video holding one 8000x8000 frame: refused from its headers, its frame never decoded."""
    video = mjpeg_video([(8000, 8000)], (8000, 8000))
    form = {"portrait": ("p.jpg", PORTRAIT), "driving_video": ("v.mkv", video)}
    growth, r = peak_growth(hostile.process.pid, lambda: client.post("/api/video", files=form, data={"size": "64"}))
    assert r.status_code == 400 and r.json()["error"].startswith("driving_video: its frames are larger than 25 megapixels"), r.text
    print(f"\nvideo of an 8000x8000 frame: peak memory of a server process rose by {growth / 2**20:.0f} MB")
    assert growth < MAX_VIDEO_GROWTH, growth


def test_a_later_frame_over_the_limit_fails_its_job(client):
    """A video whose header and first frame are small, its second frame 36 megapixels: its job fails at that frame,
    which the decoder refuses before it holds its pixels."""
    video = mjpeg_video([(320, 240), (6000, 6000), (320, 240)], (320, 240))
    form = {"portrait": ("p.jpg", PORTRAIT), "driving_video": ("v.mkv", video)}
    job = client.post("/api/video", files=form, data={"size": "64", "method": "global"}).json()
    deadline = time.time() + 120
    while (state := client.get(job["status"]).json())["state"] in ("queued", "running") and time.time() < deadline:
        time.sleep(0.5)
    assert state["state"] == "failed" and "over its limit" in state["error"], state


def test_a_video_too_long_is_refused_from_its_headers(client, tmp_path):
    """6,000 grey frames (4 minutes at 25 fps, a few hundred kB) held the only video worker for 318 s: over the
    two-minute bound, refused at the door."""
    write_video(tmp_path / "long.mp4", (np.full((64, 64, 3), 128, np.uint8) for _ in range(6000)), Fraction(25))
    form = {"portrait": ("p.jpg", PORTRAIT), "driving_video": ("v.mp4", (tmp_path / "long.mp4").read_bytes())}
    r = client.post("/api/video", files=form, data={"size": "64"})
    assert r.status_code == 400 and r.json()["error"].startswith("driving_video: is too long (6000 frames; at most 120 s"), r.text


def test_an_idle_live_session_is_closed_and_frees_its_slot():
    """Two clients that start and then send nothing held live mode for everyone: with ``--live-idle 2`` they are closed
    after 2 s (an error, then 1008), and a third starts."""
    server = Server("--workers", "1", "--max-live", "2", "--max-live-per-client", "2", "--live-idle", "2")
    try:
        with contextlib.ExitStack() as opened:
            sockets = [opened.enter_context(connect(ws(server), max_size=None)) for _ in range(2)]
            for socket in sockets:
                socket.send(START)
                socket.send(PORTRAIT)
                assert json.loads(socket.recv(timeout=60))["type"] == "ready"
            started = time.time()
            for socket in sockets:
                said, code = refused(socket)
                assert said == "live: no frame for 2 s: the session ends and its slot is free" and code == 1008
            assert time.time() - started < 10
        with connect(ws(server), max_size=None) as third:
            third.send(START)
            third.send(PORTRAIT)
            assert json.loads(third.recv(timeout=60))["type"] == "ready"
    finally:
        _, err = server.stop()
    assert "Traceback" not in err, err[-3000:]


def test_an_error_quotes_a_short_prefix_of_a_bad_value(client):
    """A 100 kB field value: the one-line error quotes 40 characters of it, not the whole."""
    r = client.post("/api/clone", files=files(), data={"method": "x" * 100_000})
    assert r.status_code == 400 and len(r.text) < 300 and r.json()["error"].startswith("method: unknown method 'xxxx"), r.text[:300]


def test_compare_answers_in_the_format_asked(client):
    r = client.post("/api/compare?format=jpeg", files=files())
    assert r.status_code == 200 and r.headers["content-type"] == "image/jpeg" and r.content[:2] == b"\xff\xd8"
