"""Live in a real browser: Chromium plays a GRID clip as a fake camera; the portrait follows it."""

import contextlib
import json
import struct
import time

import numpy as np
import pytest
from browser import chromium, write_y4m
from serving import Server
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import connect

from exprclone import data as samples
from exprclone.errors import ExprCloneError
from exprclone.io.images import load_image
from exprclone.io.video import read_frames
from exprclone.landmarks.backends import default_detector
from exprclone.landmarks.layout import DLIB68
from exprclone.mouth import measure
from exprclone.options import Options
from exprclone.server.session import Session, decode_jpeg, encode_jpeg

pytestmark = pytest.mark.slow  # servers, browsers, clusters or videos: pytest -m 'not slow' leaves these out

#: the session is watched for at least this many seconds (the clip, 3 s, plays in a loop) and until ANSWERS answers
#: came back (a loaded machine answers fewer frames a second: the tests count frames, not the rate), at most TIMEOUT s.
WATCH = 10.0
ANSWERS = 80
TIMEOUT = 180.0
#: answers in the first seconds, while the neutral face is captured, show the portrait unchanged.
SETTLE = 2.0


@pytest.fixture(scope="module")
def session(tmp_path_factory):
    """A live session watched for WATCH seconds: (sent frames by number, answers as (time, number, JPEG), the page's fps)."""
    camera = tmp_path_factory.mktemp("camera") / "grid.y4m"
    write_y4m(samples.clip(), camera)
    server = Server("--workers", "1")
    sent, answers = {}, []
    flags = ("--use-fake-ui-for-media-stream", "--use-fake-device-for-media-stream", f"--use-file-for-fake-video-capture={camera}")
    try:
        with chromium(*flags) as page:

            def watch(ws):
                ws.on(
                    "framesent",
                    lambda payload: isinstance(payload, bytes) and sent.__setitem__(struct.unpack(">I", payload[:4])[0], payload[4:]),
                )
                ws.on(
                    "framereceived",
                    lambda payload: (
                        isinstance(payload, bytes) and answers.append((time.time(), struct.unpack(">I", payload[:4])[0], payload[4:]))
                    ),
                )

            page.on("websocket", watch)
            page.goto(f"{server.url}/live")
            page.set_input_files("input[type=file][name=portrait]", str(samples.path("001")))
            page.select_option("#size", "256")
            page.click("#start")
            started = time.time()
            while (time.time() - started < WATCH or len(answers) < ANSWERS) and time.time() - started < TIMEOUT:
                page.wait_for_timeout(250)
            fps = float(page.text_content("#fps"))
            message = page.text_content("#message")
            error = page.text_content("#error")
            if page.is_enabled("#stop"):
                page.click("#stop")
    finally:
        server.stop()
    return sent, answers, fps, message, error


def test_output_frames_arrive(session):
    sent, answers, fps, message, error = session
    assert not error and "Following your face" in message, (message, error)
    assert len(answers) >= ANSWERS, len(answers)
    image = decode_jpeg(answers[-1][2])
    assert max(image.shape[:2]) == 256


def test_the_fps_readout_is_a_measurement(session):
    _, answers, fps, _, _ = session
    times = np.array([t for t, _, _ in answers])
    measured = ((times > times[-1] - 3) & (times <= times[-1])).sum() / 3  # answers a second over the last 3 s
    assert fps > 0 and abs(fps - measured) <= max(3, 0.3 * measured), (fps, measured)


def test_the_output_mouth_follows_the_camera(session):
    """The mouth opening of each output frame against that of the camera frame it answers (landmarks detected on both)."""
    sent, answers, _, _, _ = session
    start = answers[0][0]
    detector = default_detector()
    driver, output = [], []
    for t, number, jpeg in answers:
        if t - start < SETTLE or number not in sent:
            continue
        camera, result = decode_jpeg(sent[number]), decode_jpeg(jpeg)
        found = [detector.faces(image) for image in (camera, result)]
        if all(found):
            driver.append(measure.opening(detector.fit(camera, found[0][0]), DLIB68))
            output.append(measure.opening(detector.fit(result, found[1][0]), DLIB68))
    assert len(driver) > 20
    r = np.corrcoef(driver, output)[0, 1]
    assert r > 0.7, r


def frames_as_jpeg(count):
    """The first frames of the sample clip, each a 4-byte number and a JPEG, as the page sends them."""
    out = []
    for number, frame in zip(range(count), read_frames(samples.clip())):
        out.append(struct.pack(">I", number) + encode_jpeg(frame))
    return out


@pytest.fixture(scope="module")
def live_server():
    running = Server("--workers", "1", "--max-live-per-client", "2")
    yield running.url.replace("http", "ws") + "/api/live"
    running.stop()


@contextlib.contextmanager
def start(url, size=256):
    """A live connection, started with the sample portrait."""
    with connect(url, max_size=None) as socket:
        socket.send(json.dumps({"type": "start", "method": "e+md", "size": size}))
        socket.send(samples.path("003").read_bytes())
        yield socket


def test_the_protocol_answers_every_frame_in_turn_and_says_when_the_face_goes(live_server):
    with start(live_server) as socket:
        assert json.loads(socket.recv())["type"] == "ready"
        statuses, numbers = [], []
        blank = struct.pack(">I", 999) + encode_jpeg(np.full((288, 360, 3), 90, np.uint8))
        for message in frames_as_jpeg(40) + [blank]:
            if message[:4] == struct.pack(">I", 10):
                socket.send(json.dumps({"type": "neutral"}))  # "Set neutral": the next frame is the neutral face
            socket.send(message)
            while True:  # one frame in flight: every frame is answered, in order
                answer = socket.recv()
                if isinstance(answer, str):
                    statuses.append(json.loads(answer))
                    continue
                numbers.append(struct.unpack(">I", answer[:4])[0])
                break
        assert numbers == list(range(40)) + [999]
        assert statuses[0]["face"] and not statuses[0]["neutral"]
        assert any(s["neutral"] for s in statuses)
        assert statuses[-1]["face"] is False  # the blank frame has no face


def test_only_the_newest_frame_is_kept(live_server):
    with start(live_server) as socket:
        assert json.loads(socket.recv())["type"] == "ready"
        for message in frames_as_jpeg(30):  # all at once: the server cannot keep up, and must not queue them
            socket.send(message)
        numbers = []
        deadline = time.time() + 30
        while time.time() < deadline and 29 not in numbers:
            answer = socket.recv(timeout=10)
            if isinstance(answer, bytes):
                numbers.append(struct.unpack(">I", answer[:4])[0])
        assert numbers[-1] == 29 and len(numbers) < 30 and numbers == sorted(numbers)


def test_sessions_are_bounded_and_bad_starts_are_refused(live_server):
    with start(live_server) as first, start(live_server) as second:
        assert json.loads(first.recv())["type"] == "ready" and json.loads(second.recv())["type"] == "ready"
        with connect(live_server) as third:  # refused at its start message (a connection holds a slot from it)
            third.send('{"type": "start"}')
            refused = json.loads(third.recv())
            assert refused["type"] == "error" and "sessions are running already" in refused["error"]
            with pytest.raises(ConnectionClosed) as closed:
                third.recv()
            assert closed.value.rcvd.code == 1013  # try again later
    time.sleep(0.5)  # the server removes a session's state when it closes: a new one is let in
    with start(live_server) as again:
        assert json.loads(again.recv())["type"] == "ready"
    with connect(live_server) as bad:
        bad.send('{"type": "start", "size": 300}')
        assert json.loads(bad.recv())["error"].startswith("size: must be one of 256, 512")
    with connect(live_server) as bad:
        bad.send('{"type": "start"}')
        bad.send(b"not a photo")
        assert json.loads(bad.recv())["error"].startswith("portrait: not an image")


def test_strength_and_regions_reach_a_session_and_can_change_in_it():
    session = Session(load_image(samples.path("003")), Options(lambda_k=0.0, strength=0.0), 256)
    portrait = decode_jpeg(encode_jpeg(session.portrait))
    frames = list(zip(range(40), read_frames(samples.clip())))
    outputs = []
    for number, frame in frames[:30]:
        if number == 1:
            session.recapture(now=True)
        outputs.append(decode_jpeg(session.process(encode_jpeg(frame), number / 25)[0]))
    assert session.driver is not None and all(np.array_equal(out, portrait) for out in outputs[2:])  # strength 0: the portrait
    session.change(Options(lambda_k=0.0, strength=1.0, only=("mouth",)))
    moved = [decode_jpeg(session.process(encode_jpeg(frame), number / 25)[0]) for number, frame in frames[30:]]
    assert session.driver.cloner.options.only == ("mouth",)
    assert max(np.abs(out.astype(int) - portrait).max() for out in moved) > 40  # the mouth moves again
    with pytest.raises(ExprCloneError, match="strength"):
        session.change(Options(lambda_k=0.0, strength=3))


def test_a_bad_transfer_option_is_refused_at_the_start(live_server):
    with connect(live_server) as bad:
        bad.send('{"type": "start", "landmarker": "hog"}')
        assert json.loads(bad.recv())["error"].startswith("landmarker: unknown landmarker 'hog'")
    with connect(live_server) as bad:
        bad.send('{"type": "start", "strength": 3}')  # refused before the portrait (which would race the close)
        assert json.loads(bad.recv())["error"].startswith("strength: must be a number from 0 to 2")
    with connect(live_server) as bad:
        bad.send('{"type": "start", "only": ["lips"]}')
        assert json.loads(bad.recv())["error"].startswith("only:")


def test_the_status_is_json_even_for_an_infinite_lambda():
    """lambda_k = inf (the local result) was sent as ``Infinity``, which is not JSON: it goes as ``"inf"``."""
    session = Session(load_image(samples.path("003")), Options(lambda_k=float("inf")), 256)
    assert json.loads(json.dumps(session.status(True), allow_nan=False))["lambda_k"] == "inf"
