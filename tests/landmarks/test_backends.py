"""``landmarker`` reaches every surface (Python, command line, batch, video, live) and the record names it.

The HTTP API's form field is tested with the server (``test_server.py``), the live start message's refusal with
the live server (``test_live.py``)."""

import json
import subprocess
import sys

import cv2
import numpy as np
import pytest

from exprclone import clone, drive
from exprclone import data as samples
from exprclone.batch import job
from exprclone.batch.manifest import read_manifest
from exprclone.drive import tracking
from exprclone.errors import ExprCloneError
from exprclone.io.video import read_frames
from exprclone.landmarks.backends import LANDMARKERS, check_landmarker, shared
from exprclone.landmarks.dlib import Detector
from exprclone.landmarks.facemesh import MeshDetector
from exprclone.landmarks.layout import DLIB68
from exprclone.options import Options
from exprclone.server.session import Session

SIZE = 450


@pytest.fixture(scope="module")
def small():
    """The sample source's two photos and the sample target, shrunk for speed."""
    shrink = lambda im: cv2.resize(im, (SIZE, SIZE), interpolation=cv2.INTER_AREA)  # noqa: E731
    return [shrink(samples.photo(samples.SOURCE)), shrink(samples.photo(samples.SOURCE, "smile")), shrink(samples.photo(samples.TARGET))]


@pytest.mark.parametrize("name", LANDMARKERS)
def test_the_python_api_takes_a_landmarker_by_name(small, name):
    result = clone(*small, method="global", landmarker=name)
    expected = shared(name).detect(small[2])
    assert result.landmarker == name
    assert np.abs(result.landmarks["target_neutral"][list(DLIB68.jaw)] - expected[list(DLIB68.jaw)]).max() < 1e-9


def test_the_python_api_takes_a_landmarker_object_and_names_it(small):
    assert clone(*small, method="global", landmarker=MeshDetector()).landmarker == "mesh"
    given = tuple(shared("dlib").detect(im) for im in small)
    assert clone(*small, method="global", landmarks=given).landmarker is None  # nothing was placed
    with pytest.raises(ExprCloneError, match=r"^landmarker: unknown landmarker 'hog'; choose one of: dlib, mesh$"):
        clone(*small, method="global", landmarker="hog")
    assert check_landmarker("dlib") == "dlib"


def test_the_command_line_records_the_landmarker(tmp_path):
    photos = [str(samples.path(samples.SOURCE)), str(samples.path(samples.SOURCE, "smile")), str(samples.path(samples.TARGET))]
    record = tmp_path / "r.json"
    command = [sys.executable, "-m", "exprclone", "clone", *photos, "-o", str(tmp_path / "r.png"), "--method", "global"]
    done = subprocess.run([*command, "--landmarker", "dlib", "--save-json", str(record)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    saved = json.loads(record.read_text())
    assert saved["landmarker"] == "dlib"
    expected = shared("dlib").detect(samples.photo(samples.TARGET))[list(DLIB68.jaw)]
    assert np.abs(np.array(saved["landmarks"]["target_neutral"])[list(DLIB68.jaw)] - expected).max() < 0.01
    bad = subprocess.run([*command, "--landmarker", "hog"], capture_output=True, text=True)
    assert bad.returncode == 2 and "--landmarker: invalid choice: 'hog'" in bad.stderr


@pytest.mark.parametrize("name", LANDMARKERS)
def test_a_batch_places_and_caches_with_its_landmarker(tmp_path, name):
    photos = [samples.path(samples.SOURCE), samples.path(samples.SOURCE, "smile"), samples.path(samples.TARGET)]
    manifest = tmp_path / "m.csv"
    manifest.write_text("source_neutral,source_expression,target_neutral,output\n" + ",".join(map(str, photos)) + ",out.png\n")
    outcomes = {}
    job.run(read_manifest(str(manifest)), Options(method="global", landmarker=name), job.Local(1), outcomes, cache=tmp_path / "c")
    assert [o.status for o in outcomes.values()] == ["done"]
    cached = sorted(p.name for p in (tmp_path / "c").iterdir())
    assert len(cached) == 3 and all(p.endswith(f"-{name}.json") for p in cached)
    expected = shared(name).detect(samples.photo(samples.TARGET))
    faces = [json.loads((tmp_path / "c" / p).read_text())["faces"] for p in cached]  # each photo's every face
    assert all(len(found) == 1 for found in faces) and any(np.allclose(found[0]["landmarks"], expected) for found in faces)


def test_a_live_session_tracks_with_its_landmarker():
    portrait = samples.photo(samples.TARGET)
    assert isinstance(Session(portrait, Options(lambda_k=0.0), 256).detector, Detector)  # the default
    mesh = Session(portrait, Options(lambda_k=0.0, landmarker="mesh"), 256).detector
    assert isinstance(mesh, MeshDetector) and mesh is not Session(portrait, Options(lambda_k=0.0, landmarker="mesh"), 256).detector
    with pytest.raises(ExprCloneError, match="^landmarker: unknown landmarker"):
        Session(portrait, Options(lambda_k=0.0, landmarker="hog"), 256)


@pytest.mark.parametrize(
    "command",
    [
        ["clone", "a.jpg", "b.jpg", "c.jpg", "-o", "out.png"],
        ["compare", "a.jpg", "b.jpg", "c.jpg", "-o", "out.png"],
        ["video", "c.jpg", "clip.mp4", "-o", "out.mp4"],
        ["batch", "rows.csv"],
        ["evaluate"],
    ],
)
def test_every_command_takes_the_landmarker(command):
    from exprclone.cli.inputs import options_of
    from exprclone.cli.main import build_parser

    assert options_of(build_parser().parse_args(command), Options).landmarker == "dlib"
    assert options_of(build_parser().parse_args([*command, "--landmarker", "mesh"]), Options).landmarker == "mesh"


def test_a_recorded_performance_is_tracked_by_its_landmarker():
    frames = list(read_frames(samples.clip()))[:25]
    recording = drive.prepare(samples.photo(samples.TARGET), None, lambda: iter(frames), 25.0, method="global", landmarker="mesh")
    assert np.array_equal(recording.track.points, tracking.track(frames, MeshDetector()).points)
    assert recording.track.found.all()
