"""The HTTP API of ``exprclone serve``, on a real server and the sample photos: results, errors, limits, jobs, concurrency."""

import base64
import io
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import threading
import time

import httpx
import numpy as np
import pytest
from PIL import Image
from serving import Server
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import connect

import exprclone
import exprclone.landmarks.backends
from exprclone import data as samples
from exprclone import expressions
from exprclone.evaluation.panels import BAND, CELL, HEIGHT
from exprclone.io.images import load_image
from exprclone.io.landmarks import read_landmarks, write_landmarks
from exprclone.io.video import probe, read_frames
from exprclone.landmarks.backends import LANDMARKERS
from exprclone.landmarks.layout import DLIB68
from exprclone.landmarks.lips import uncross

pytestmark = pytest.mark.slow  # servers, browsers, clusters or videos: pytest -m 'not slow' leaves these out

PHOTOS = {"source_neutral": samples.path("126"), "source_expression": samples.path("126", "smile"), "target_neutral": samples.path("003")}


def files(**replaced) -> dict:
    """The three sample photos as multipart files, some replaced by ``field=(name, bytes)``."""
    out = {field: (path.name, path.read_bytes()) for field, path in PHOTOS.items()}
    out.update(replaced)
    return out


def grey(size=(300, 300)) -> bytes:
    """A PNG with no face in it."""
    out = io.BytesIO()
    Image.fromarray(np.full((*size, 3), 128, np.uint8)).save(out, "PNG")
    return out.getvalue()


@pytest.fixture(scope="module")
def server():
    running = Server("--workers", "2", "--max-requests-per-client", "6", "--max-jobs-per-client", "8")  # (one client's tests)
    yield running.url
    running.stop()


@pytest.fixture(scope="module")
def client(server):
    with httpx.Client(base_url=server, timeout=120) as c:
        yield c


@pytest.fixture(scope="module")
def expected():
    """The e+md clone of the sample photos, as the Python API makes it."""
    images = [load_image(p) for p in PHOTOS.values()]
    return exprclone.clone(*images, method="e+md")


def test_health(client):
    assert client.get("/api/health").json() == {"status": "ok", "version": exprclone.__version__}


def test_clone_answers_the_png_of_the_python_api(client, expected):
    r = client.post("/api/clone", files=files())
    assert r.status_code == 200 and r.headers["content-type"] == "image/png"
    image = np.asarray(Image.open(io.BytesIO(r.content)).convert("RGB"))
    assert np.array_equal(image, expected.image)  # lossless, the target's size, the same pixels


@pytest.mark.parametrize(("answer", "media_type", "pillow"), [("jpeg", "image/jpeg", "JPEG"), ("webp", "image/webp", "WEBP")])
def test_clone_as_jpeg_or_webp_is_the_same_image_smaller(client, expected, answer, media_type, pillow):
    png = client.post("/api/clone", files=files())
    r = client.post(f"/api/clone?format={answer}", files=files())
    assert r.status_code == 200 and r.headers["content-type"] == media_type
    decoded = Image.open(io.BytesIO(r.content))
    assert decoded.format == pillow and decoded.size == expected.image.shape[1::-1]
    error = np.abs(np.asarray(decoded.convert("RGB"), float) - expected.image)
    assert error.mean() < 2.0  # quality 95: the same picture, a level or so off on average
    assert len(r.content) < len(png.content) / 3


def test_clone_as_json_with_options_and_a_landmark_file(client):
    tem = samples.template("003")
    form = {"method": "elastic", "lambda": "2", "mouth": "false"}
    r = client.post("/api/clone?format=json", files=files(target_neutral_landmarks=("any name.tem", tem.read_bytes())), data=form)
    assert r.status_code == 200, r.text
    record = r.json()
    assert record["method"] == "elastic" and record["lambda_k"] == 2.0 and record["db_curve"] is None
    given = uncross(read_landmarks(tem, (1350, 1350, 3)), DLIB68)
    assert np.allclose(record["landmarks"]["target_neutral"], given, atol=1e-3)  # the file's landmarks, not detected ones
    image = Image.open(io.BytesIO(base64.b64decode(record["png"])))
    assert image.size == (1350, 1350)


def test_compare_answers_the_sheet(client):
    r = client.post("/api/compare", files=files())
    assert r.status_code == 200 and Image.open(io.BytesIO(r.content)).size == (9 * CELL, BAND + 4 * HEIGHT)
    r = client.post("/api/compare", files=files(), data={"retarget": "false"})  # the paper's stages alone
    assert r.status_code == 200 and Image.open(io.BytesIO(r.content)).size == (9 * CELL, BAND + 3 * HEIGHT)


def test_compare_answers_figure_17_on_song_et_als_global_warp_alone(client):
    r = client.post("/api/compare", files=files(), data={"figure": "17"})
    assert r.status_code == 200 and Image.open(io.BytesIO(r.content)).size == (7 * CELL, HEIGHT)
    r = client.post("/api/compare", files=files(), data={"figure": "17", "global_warp": "rbf"})
    assert r.status_code == 400 and r.json()["error"].startswith("global_warp: Fig. 17 shows the methods on Song et al.'s global warp")


def test_landmarks_of_one_photo(client):
    r = client.post("/api/landmarks", files={"photo": ("p.jpg", samples.path("001").read_bytes())})
    found = r.json()
    assert (found["width"], found["height"]) == (1350, 1350) and np.array(found["landmarks"]).shape == (68, 2)


@pytest.mark.parametrize("name", LANDMARKERS)
def test_each_landmarker_reaches_the_api_and_the_record(client, name):
    photo = samples.path("001").read_bytes()
    found = client.post("/api/landmarks", files={"photo": ("p.jpg", photo)}, data={"landmarker": name}).json()
    expected = exprclone.landmarks.backends.shared(name).detect(load_image(samples.path("001")))
    assert np.abs(np.array(found["landmarks"]) - expected).max() < 0.01
    r = client.post("/api/clone?format=json", files=files(), data={"method": "global", "landmarker": name})
    assert r.status_code == 200 and r.json()["landmarker"] == name, r.text
    bad = client.post("/api/landmarks", files={"photo": ("p.jpg", photo)}, data={"landmarker": "hog"})
    assert bad.status_code == 400 and bad.json()["error"].startswith("landmarker: unknown landmarker 'hog'")


@pytest.mark.parametrize(
    "replaced, form, status, message",
    [
        (dict(target_neutral=("t.jpg", b"not an image")), {}, 400, "target_neutral: not an image"),
        (dict(source_expression=("s.jpg", b"")), {}, 400, "source_expression: "),
        (dict(target_neutral=("t.png", grey())), {}, 422, "target_neutral: no face found"),
        ({}, {"method": "warp"}, 400, "method: unknown method 'warp'"),
        ({}, {"method": "song", "global_warp": "rbf"}, 400, "global_warp: method song warps by its own global warp, vtc"),
        ({}, {"lambda": "-1"}, 400, "lambda: must be 'auto' or a number >= 0"),
        ({}, {"landmarker": "hog"}, 400, "landmarker: unknown landmarker 'hog'; choose one of: dlib, mesh"),
        ({}, {"lambda": "nan"}, 400, "lambda: "),
        ({}, {"mouth": "perhaps"}, 400, "mouth: "),
        (dict(target_neutral_landmarks=("t.txt", b"[]")), {}, 400, "target_neutral_landmarks: a landmark file must be .json or .tem"),
        (dict(target_neutral_landmarks=("t.json", b"[[1, 2]]")), {}, 400, "target_neutral_landmarks: found 1 landmarks, expected 68"),
        (dict(target_neutral_landmarks=("t.json", b"{nope")), {}, 400, "target_neutral_landmarks: not JSON"),
    ],
)
def test_bad_input_is_a_one_line_json_error_naming_the_field(client, replaced, form, status, message):
    r = client.post("/api/clone", files=files(**replaced), data=form)
    assert r.status_code == status and r.json()["error"].startswith(message), r.text
    assert "\n" not in r.json()["error"] and "Traceback" not in r.text


def test_a_missing_photo_and_a_bad_query(client):
    missing = files()
    del missing["target_neutral"]
    r = client.post("/api/clone", files=missing)
    assert r.status_code == 400 and r.json() == {"error": "target_neutral: missing"}
    r = client.post("/api/clone?format=gif", files=files())
    assert r.status_code == 400 and r.json()["error"].startswith("format: ")


def test_a_decompression_bomb_is_refused_before_it_is_decoded(client):
    bomb = io.BytesIO()
    Image.new("L", (10_000, 10_000)).save(bomb, "PNG")  # 100 megapixels, 100 kB compressed
    r = client.post("/api/clone", files=files(target_neutral=("bomb.png", bomb.getvalue())))
    assert r.status_code == 400 and "too large" in r.json()["error"] and r.json()["error"].startswith("target_neutral: ")


def test_the_server_keeps_serving_after_every_bad_request(client, expected):
    for junk in (b"", b"\x89PNG\r\n\x1a\n" + os.urandom(500), os.urandom(5000)):
        client.post("/api/clone", files=files(source_neutral=("x.png", junk)))
    r = client.post("/api/clone", files=files())
    assert r.status_code == 200 and len(r.content) > 100_000


def test_concurrent_requests_all_succeed(client, expected):
    results = []

    def one():
        results.append(client.post("/api/clone", files=files()))

    threads = [threading.Thread(target=one) for _ in range(6)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert [r.status_code for r in results] == [200] * 6
    assert all(np.array_equal(np.asarray(Image.open(io.BytesIO(r.content)).convert("RGB")), expected.image) for r in results)


def test_a_video_job_from_start_to_finish(client):
    form = {"size": "128", "side_by_side": "true", "method": "elastic"}
    video_files = {"portrait": ("p.jpg", samples.path("003").read_bytes()), "driving_video": ("c.mp4", samples.clip().read_bytes())}
    r = client.post("/api/video", files=video_files, data=form)
    assert r.status_code == 202, r.text
    job = r.json()
    seen = set()
    deadline = time.time() + 120
    while time.time() < deadline:
        state = client.get(job["status"]).json()
        seen.add(state["state"])
        if state["state"] in ("done", "failed"):
            break
        early = client.get(job["result"]).status_code  # 409: not before it is done
        if early != 409:  # unless it was done between the two requests
            assert early == 200 and client.get(job["status"]).json()["state"] == "done", early
        time.sleep(0.2)
    assert state["state"] == "done" and state["progress"] == 1.0, state
    assert state["info"]["frames"] == 75 and state["info"]["neutral_frame"] is not None
    r = client.get(job["result"])
    assert r.status_code == 200 and r.headers["content-type"] == "video/mp4"
    with tempfile.NamedTemporaryFile(suffix=".mp4") as out:
        out.write(r.content)
        out.flush()
        info = probe(out.name)
        assert (info.frames, info.height, info.has_audio) == (75, 128, True)
        assert info.width == 128 + 160  # the 360x288 clip at 128 high, then the portrait
        assert len(list(read_frames(out.name))) == 75


@pytest.mark.parametrize(
    "replaced, form, status, message",
    [
        (dict(portrait=("p.png", grey())), {}, 422, "portrait: no face found"),
        (dict(driving_video=("v.mp4", b"not a video at all")), {}, 400, "driving_video: not a video"),
        ({}, {"size": "8"}, 400, "size: "),
        ({}, {"neutral_frame": "middle"}, 400, "neutral_frame: expected closed, first or a frame number"),
    ],
)
def test_a_bad_video_job_is_refused_at_once(client, replaced, form, status, message):
    video_files = {"portrait": ("p.jpg", samples.path("003").read_bytes()), "driving_video": ("c.mp4", samples.clip().read_bytes())}
    video_files.update(replaced)
    r = client.post("/api/video", files=video_files, data=form)
    assert r.status_code == status and r.json()["error"].startswith(message), r.text


def test_a_job_that_fails_later_says_why(client):
    video_files = {"portrait": ("p.jpg", samples.path("003").read_bytes()), "driving_video": ("c.mp4", samples.clip().read_bytes())}
    job = client.post("/api/video", files=video_files, data={"neutral_frame": "500", "size": "64"}).json()
    for _ in range(200):
        state = client.get(job["status"]).json()
        if state["state"] in ("done", "failed"):
            break
        time.sleep(0.1)
    assert state["state"] == "failed" and state["error"].startswith("driving_video: no frame 500")
    assert client.get(job["result"]).status_code == 409


@pytest.mark.parametrize("job_id", ["zzz", "%2E%2E", "0" * 32, "A" * 32, "a" * 8000])
def test_job_ids_are_checked(client, job_id):
    """Any id but one the server made is unknown; an error quotes a short prefix of it, not the whole of a long one."""
    for path in (f"/api/jobs/{job_id}", f"/api/jobs/{job_id}/result", f"/api/edits/{job_id}/render"):
        r = client.post(path) if path.endswith("render") else client.get(path)
        assert r.status_code == 404 and r.json()["error"].startswith(("no job", "no edit")) and len(r.text) < 200, r.text[:300]


def test_the_page_and_the_docs_are_served(client):
    page = client.get("/")
    assert page.status_code == 200 and 'id="clone"' in page.text and "cdn" not in page.text.lower()
    assert client.get("/static/app.js").status_code == 200
    assert client.get("/docs").status_code == 200 and "/api/clone" in client.get("/openapi.json").text
    assert client.get("/api/samples/driving_video").content == samples.clip().read_bytes()
    assert client.get("/api/samples/passwd").status_code == 400


def test_no_cross_origin_calls_unless_asked(client):
    r = client.options("/api/clone", headers={"Origin": "http://elsewhere.example", "Access-Control-Request-Method": "POST"})
    assert "access-control-allow-origin" not in r.headers


def test_limits_upload_size_and_work_queue():
    """413 over the upload limit (declared, or streamed without a length); 503 with Retry-After when the queue is full;
    serve's bounds on photos and live sessions as its flags set them."""
    small = Server("--workers", "1", "--queue", "0", "--max-upload-mb", "1", "--max-megapixels", "1.9", "--max-live", "0")
    try:
        big = files(target_neutral=("big.jpg", os.urandom(1_200_000)))
        wide = io.BytesIO()
        Image.new("RGB", (1400, 1400), (128, 100, 90)).save(wide, "JPEG")  # 1.96 megapixels, a small file
        with connect(small.url.replace("http", "ws") + "/api/live") as live:
            live.send('{"type": "start"}')
            assert json.loads(live.recv())["error"] == "live: live mode is off on this server (serve --max-live 0)"
            with pytest.raises(ConnectionClosed) as closed:
                live.recv()
            assert closed.value.rcvd.code == 1008
        with httpx.Client(base_url=small.url, timeout=120) as c:
            r = c.post("/api/clone", files=files(target_neutral=("wide.jpg", wide.getvalue())))
            expected = "target_neutral: image is too large (1400x1400 pixels; at most 1.9 megapixels)"
            assert r.status_code == 400 and r.json()["error"] == expected
            r = c.post("/api/clone", files=big)
            assert r.status_code == 413 and r.json()["error"].startswith("upload too large")
            upload = httpx.Request("POST", "/", files=big)  # the same upload, streamed in chunks with no length
            body = upload.read()
            chunks = (body[i : i + 65536] for i in range(0, len(body), 65536))
            headers = {"content-type": upload.headers["content-type"]}
            r = c.post("/api/clone", content=chunks, headers=headers)
            assert r.status_code == 413, r.text
            answers = []
            threads = [threading.Thread(target=lambda: answers.append(c.post("/api/clone", files=files()))) for _ in range(3)]
            for t in threads:
                t.start()
            for t in threads:
                t.join()
            codes = sorted(r.status_code for r in answers)
            assert codes[0] == 200 and 503 in codes, codes
            busy = next(r for r in answers if r.status_code == 503)
            said = re.search(r"busy \(1 requests at work or waiting\); try again in (\d+) s", busy.json()["error"])
            assert said and busy.headers["retry-after"] == said[1], busy.json()  # about a clone's time, here with one worker
            assert c.post("/api/clone", files=files()).status_code == 200  # and it serves again
    finally:
        out, err = small.stop()
    assert "Traceback" not in err, err


def test_ctrl_c_stops_the_server_and_removes_its_temporary_files(tmp_path):
    running = Server("--workers", "1", env={"TMPDIR": str(tmp_path)})  # a folder of its own: other servers may be running
    made = set(tmp_path.glob("exprclone-serve-*"))
    assert len(made) == 1
    out, err = running.stop()
    assert running.process.returncode == 130 and out.endswith("exprclone: stopped\n") and "interrupted" not in err, err
    assert not any(p.exists() for p in made)
    assert json.dumps(err).count("Traceback") == 0


def test_a_port_in_use_is_a_one_line_error_not_a_stopped_server():
    import socket

    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        done = subprocess.run(
            [sys.executable, "-m", "exprclone", "serve", "--workers", "1", "--port", str(port)], capture_output=True, text=True, timeout=120
        )
    assert done.returncode == 2 and "stopped" not in done.stdout, done
    assert f"exprclone: error: serve: could not start on 127.0.0.1:{port}" in done.stderr and "Traceback" not in done.stderr


@pytest.fixture(scope="module")
def sample_images():
    images = [load_image(p) for p in PHOTOS.values()]
    return images, [exprclone.landmarks.backends.default_detector().detect(im) for im in images]


def test_clone_with_the_transfer_options_answers_the_python_apis_image(client, sample_images):
    images, landmarks = sample_images
    options = dict(global_warp="rbf", image_warp="tps", strength=0.5, only=("mouth", "eyes"), retarget=False)
    expected = exprclone.clone(*images, method="elastic+eri", landmarks=tuple(landmarks), **options)
    form = {"method": "elastic+eri", "global_warp": "rbf", "image_warp": "tps", "strength": "0.5", "only": "mouth,eyes"}
    form["retarget"] = "false"
    r = client.post("/api/clone?format=json", files=files(), data=form)
    assert r.status_code == 200, r.text
    record = r.json()
    regions = {"mouth": 0.5, "eyes": 0.5, "brows": 0.0}
    assert record["options"] == {
        **{"global_warp": "rbf", "image_warp": "tps", "strength": 0.5, "only": ["mouth", "eyes"], "retarget": False},
        **{"region_strengths": regions, "strength_shading": 1.0},
    }
    image = np.asarray(Image.open(io.BytesIO(base64.b64decode(record["png"]))).convert("RGB"))
    assert np.array_equal(image, expected.image)


@pytest.mark.parametrize("form", [{"method": "song"}, {"method": "elastic+eri", "global_warp": "vtc", "lambda": "1"}])
def test_song_and_its_global_warp_answer_the_python_apis_image(client, sample_images, form):
    images, landmarks = sample_images
    expected = exprclone.clone(*images, landmarks=tuple(landmarks), options=exprclone.Options.from_text(form))
    r = client.post("/api/clone?format=json", files=files(), data=form)
    assert r.status_code == 200, r.text
    assert r.json()["options"]["global_warp"] == "vtc"
    image = np.asarray(Image.open(io.BytesIO(base64.b64decode(r.json()["png"]))).convert("RGB"))
    assert np.array_equal(image, expected.image)


def test_strength_zero_answers_the_target(client, sample_images):
    images, _ = sample_images
    r = client.post("/api/clone", files=files(), data={"strength": "0"})
    assert r.status_code == 200, r.text
    assert np.abs(np.asarray(Image.open(io.BytesIO(r.content)).convert("RGB")).astype(int) - images[2]).max() <= 1


def test_given_global_landmarks_as_a_file(client, sample_images, tmp_path):
    """Fig. 21's setting over HTTP: the default GI, given as a file, gives the default result."""
    images, landmarks = sample_images
    default = exprclone.clone(*images, landmarks=tuple(landmarks))
    write_landmarks(tmp_path / "gi.json", default.landmarks["global"])
    r = client.post("/api/clone", files=files(global_landmarks=("gi.json", (tmp_path / "gi.json").read_bytes())))
    assert r.status_code == 200, r.text
    assert np.array_equal(np.asarray(Image.open(io.BytesIO(r.content)).convert("RGB")), default.image)


def test_compare_draws_figure_19(client):
    r = client.post("/api/compare", files=files(), data={"figure": "19"})
    assert r.status_code == 200 and Image.open(io.BytesIO(r.content)).size == (6 * CELL, HEIGHT)


@pytest.mark.parametrize(
    "replaced, form, message",
    [
        ({}, {"global_warp": "affine"}, "global_warp: unknown global warp 'affine'"),
        ({}, {"image_warp": "spline"}, "image_warp: unknown image warp 'spline'"),
        ({}, {"strength": "3"}, "strength: "),
        ({}, {"strength": "strong"}, "strength: "),
        ({}, {"only": "nose"}, "only: unknown region 'nose'"),
        ({}, {"retarget": "perhaps"}, "retarget: "),
        ({}, {"figure": "12"}, "figure: must be 11 or 16 or 17 or 19"),
        (dict(global_landmarks=("gi.json", b"[[1, 2]]")), {}, "global_landmarks: found 1 landmarks, expected 68"),
        (dict(global_landmarks=("gi.txt", b"[]")), {}, "global_landmarks: a landmark file must be .json or .tem"),
        (dict(global_landmarks=("gi.tem", samples.template("003").read_bytes())), {"global_warp": "rbf"}, "global_landmarks: given"),
    ],
)
def test_bad_transfer_options_are_one_line_errors_naming_the_field(client, replaced, form, message):
    r = client.post("/api/compare" if "figure" in form else "/api/clone", files=files(**replaced), data=form)
    assert r.status_code == 400 and r.json()["error"].startswith(message), r.text


def test_a_video_job_with_the_transfer_options(client):
    form = {"size": "96", "method": "e+md", "global_warp": "rbf", "image_warp": "tps", "strength": "1.5", "only": "mouth"}
    form["landmarker"] = "mesh"
    video_files = {"portrait": ("p.jpg", samples.path("003").read_bytes()), "driving_video": ("c.mp4", samples.clip().read_bytes())}
    job = client.post("/api/video", files=video_files, data=form).json()
    for _ in range(600):
        state = client.get(job["status"]).json()
        if state["state"] in ("done", "failed"):
            break
        time.sleep(0.2)
    assert state["state"] == "done" and state["info"]["frames"] == 75, state
    r = client.post("/api/video", files=video_files, data={"strength": "-1"})
    assert r.status_code == 400 and r.json()["error"].startswith("strength: "), r.text


def test_the_built_in_expressions_are_listed(client):
    """The prototype smile first (the page offers it first), though "angry" sorts before it; then the others by name."""
    listed = client.get("/api/expressions").json()["expressions"]
    others = [name for name in expressions.names() if name != "smile"]
    assert [e["name"] for e in listed] == ["smile", *others] and all(e["description"] for e in listed)


def test_clone_one_photo_with_a_built_in_expression_answers_the_python_apis_image(client, sample_images):
    images, landmarks = sample_images
    expected = expressions.clone(images[2], "smile", strength=0.5, only=("mouth",), target_landmarks=landmarks[2])
    target = {"target_neutral": files()["target_neutral"]}
    r = client.post("/api/clone?format=json", files=target, data={"expression": "smile", "strength": "0.5", "only": "mouth"})
    assert r.status_code == 200, r.text
    record = r.json()
    assert record["inputs"]["source_expression"] == "expression smile (expression)" and record["options"]["only"] == ["mouth"]
    assert np.array_equal(np.asarray(Image.open(io.BytesIO(base64.b64decode(record["png"]))).convert("RGB")), expected.image)
    r = client.post("/api/compare", files=target, data={"expression": "smile-001"})
    assert r.status_code == 200 and Image.open(io.BytesIO(r.content)).size == (9 * CELL, BAND + 4 * HEIGHT)
    r = client.post("/api/compare", files=files(), data={"retarget": "false"})  # the paper's stages alone
    assert r.status_code == 200 and Image.open(io.BytesIO(r.content)).size == (9 * CELL, BAND + 3 * HEIGHT)


@pytest.mark.parametrize(
    "sent, form, message",
    [
        (("target_neutral",), {"expression": "grin"}, "expression: unknown expression 'grin'; the built-in expressions are: angry, sad"),
        (PHOTOS, {"expression": "smile"}, "source_neutral: not with an expression"),
        (("source_expression", "target_neutral"), {"expression": "smile"}, "source_expression: not with an expression"),
        (("target_neutral",), {}, "source_neutral: missing"),
    ],
)
def test_a_built_in_expression_with_the_wrong_photos_is_one_error(client, sent, form, message):
    r = client.post("/api/clone", files={f: files()[f] for f in sent}, data=form)
    assert r.status_code == 400 and r.json()["error"].startswith(message), r.text


@pytest.mark.parametrize("command", [("serve", "--workers", "1"), ("study", "serve", "STUDY")])
def test_serving_is_said_only_once_the_server_answers(command, tmp_path):
    """ "serving on ..." came 19 s before /api/health answered on a loaded machine: now its first request, sent the moment
    the line is read, is answered."""
    from serving import free_port, interruptible
    from studies import SETS, make

    if "STUDY" in command:
        assert make(tmp_path, sets=SETS[:1], methods=("global",)).returncode == 0
    words = [str(tmp_path / "study") if w == "STUDY" else w for w in command]
    port = free_port()
    process = subprocess.Popen(
        [sys.executable, "-m", "exprclone", *words, "--port", str(port)], stdout=subprocess.PIPE, text=True, preexec_fn=interruptible
    )
    try:
        line = process.stdout.readline()
        assert line.startswith("exprclone: serving") and f"127.0.0.1:{port}" in line, line
        assert httpx.get(f"http://127.0.0.1:{port}/api/health", timeout=5).json()["status"] == "ok"
    finally:
        process.send_signal(signal.SIGINT)
        assert process.wait(timeout=30) == 130 and process.stdout.read() == "exprclone: stopped\n"  # 128 + SIGINT
