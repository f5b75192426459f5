"""Edits: a clone prepared once on a real server and rendered again with other strengths (the sliders' API)."""

import cv2
import numpy as np
import pytest
import serving
from serving import pixels

import exprclone
from exprclone import data as samples
from exprclone.drive.framing import resize_portrait
from exprclone.io.images import load_image
from exprclone.landmarks.backends import default_detector
from exprclone.landmarks.layout import DLIB68
from exprclone.mouth import measure
from exprclone.server.runtime import edits as edits_module
from exprclone.server.runtime.edits import Edit, Edits, NoSuchEdit
from exprclone.server.runtime.limits import Busy

pytestmark = pytest.mark.slow  # servers, browsers, clusters or videos: pytest -m 'not slow' leaves these out

PHOTOS = {"source_neutral": samples.path("126"), "source_expression": samples.path("126", "smile"), "target_neutral": samples.path("003")}
MOUTH = list(DLIB68.regions["mouth"])


def files() -> dict:
    return {field: (path.name, path.read_bytes()) for field, path in PHOTOS.items()}


@pytest.fixture(scope="module")
def client():
    with serving.client("--workers", "1", "--max-edits", "2", "--max-edits-per-client", "2") as c:
        yield c


@pytest.fixture(scope="module")
def edit(client):
    made = client.post("/api/edits", files=files())
    assert made.status_code == 201, made.text
    yield made.json()
    client.delete(f"/api/edits/{made.json()['id']}")


def test_a_render_at_the_defaults_is_the_clone_bit_for_bit(client, edit):
    expected = exprclone.clone(*(load_image(p) for p in PHOTOS.values()))
    assert (edit["width"], edit["height"], edit["preview_width"]) == (1350, 1350, 512)
    full = client.post(edit["render"], params={"preview": "false"})
    assert full.headers["content-type"] == "image/png" and np.array_equal(pixels(full), expected.image)
    record = client.post(edit["render"], params={"preview": "false", "format": "json"}, data={"strength": "0.5"}).json()
    assert record["options"]["strength"] == 0.5 and record["lambda_k"] == expected.lambda_k == edit["lambda_k"]


def test_one_photo_sent_as_two_is_answered_with_a_warning(client, edit):
    """The same photo as the source's neutral and its expression: the edit is made, and its warnings say so (the page
    shows them above the result); the three different photos have none."""
    twice = {**files(), "source_expression": ("again.jpg", PHOTOS["source_neutral"].read_bytes())}
    made = client.post("/api/edits", files=twice)
    assert made.status_code == 201, made.text
    client.delete(f"/api/edits/{made.json()['id']}")
    said = "source_expression: the same photo as source_neutral, so there is no expression to clone; is one of them the wrong file?"
    assert made.json()["warnings"] == [said] and edit["warnings"] == []


def test_the_preview_follows_the_mouths_strength(client, edit):
    """Each step of the mouth's slider opens the preview's mouth more (measured on its landmarks), at 512 pixels; at 0 the
    mouth is the target's own, pixel for pixel, while the eyes still smile."""
    detect = default_detector().detect
    previews = [pixels(client.post(edit["render"], data={"strength_mouth": f"{s:g}"})) for s in np.linspace(0, 2, 5)]
    assert all(p.shape == (512, 512, 3) for p in previews)
    opening = [measure.opening(detect(p), DLIB68) for p in previews]
    assert np.all(np.diff(opening) > 0), opening
    target = load_image(PHOTOS["target_neutral"])
    still, _ = resize_portrait(target, None, 512)  # the preview's target
    held = pixels(client.post(edit["render"], data={"strength_mouth": "0"}, params={"format": "png"}))
    points = detect(target) * 512 / 1350  # the target's landmarks in the preview
    mask = np.zeros(still.shape[:2], np.uint8)
    cv2.fillConvexPoly(mask, cv2.convexHull(np.round(points[MOUTH]).astype(np.int32)), 1)
    assert np.array_equal(held[mask > 0], still[mask > 0])
    assert np.abs(held.astype(int) - still)[mask == 0].max() > 30  # the rest of the face does smile


@pytest.mark.parametrize(
    "form, params, status, message",
    [
        ({"strength_mouth": "3"}, {}, 400, "strength_mouth: must be a number from 0 to 2, got 3"),
        ({"only": "lips"}, {}, 400, "only: unknown region 'lips'"),
        ({}, {"preview": "maybe"}, 400, "preview: Input should be a valid boolean"),
        # the options fixed when the clone was prepared: said, not ignored
        ({"lambda": "2"}, {}, 400, "lambda: was fixed when the clone was prepared: prepare it again (POST /api/edits)"),
        ({"strength": "0.5", "method": "global"}, {}, 400, "method: was fixed when the clone was prepared"),
        ({"retarget": "false"}, {}, 400, "retarget: was fixed when the clone was prepared"),
    ],
)
def test_bad_renders_are_one_line_errors(client, edit, form, params, status, message):
    r = client.post(edit["render"], data=form, params=params)
    assert r.status_code == status and message in r.json()["error"] and "\n" not in r.json()["error"], r.text


@pytest.mark.parametrize("edit_id", ["0" * 32, "A" * 32, "x" * 40])
def test_unknown_edits_are_404(client, edit_id):
    r = client.post(f"/api/edits/{edit_id}/render")
    assert r.status_code == 404 and "no edit" in r.json()["error"]
    assert client.delete(f"/api/edits/{edit_id}").status_code == 404


def test_edits_are_bounded_and_a_deleted_one_frees_its_place(client, edit):
    second = client.post("/api/edits", data={"expression": "smile"}, files={"target_neutral": files()["target_neutral"]})
    assert second.status_code == 201, second.text
    third = client.post("/api/edits", data={"expression": "smile"}, files={"target_neutral": files()["target_neutral"]})
    assert third.status_code == 503 and int(third.headers["Retry-After"]) >= 1 and "2 edits are kept" in third.json()["error"]
    assert client.delete(f"/api/edits/{second.json()['id']}").status_code == 204
    assert client.post(second.json()["render"]).status_code == 404
    third = client.post("/api/edits", data={"expression": "smile"}, files={"target_neutral": files()["target_neutral"]})
    assert third.status_code == 201 and client.delete(f"/api/edits/{third.json()['id']}").status_code == 204


def test_an_edit_unused_for_its_time_to_live_expires(monkeypatch):
    """On a clock of the test's (no sleeping: a loaded machine cannot make it flaky)."""
    now = [1000.0]
    monkeypatch.setattr(edits_module.time, "time", lambda: now[0])
    edits = Edits(limit=1, ttl=10)
    kept = edits.add(Edit(None, None, {}, None))
    now[0] += 8
    edits.get(kept)  # a render starts its time again
    now[0] += 8
    assert edits.get(kept)  # 16 s after it was made, 8 after its last render
    with pytest.raises(Busy):
        edits.add(Edit(None, None, {}, None))  # the one place is taken
    now[0] += 10.5
    with pytest.raises(NoSuchEdit):
        edits.get(kept)
    assert edits.add(Edit(None, None, {}, None))  # its place is free
