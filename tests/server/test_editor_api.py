"""The expression editor over HTTP, on a real server: its controls, a photo prepared once and rendered as the
controls move, as the Python API renders it."""

import io

import numpy as np
import pytest
import serving
from PIL import Image
from serving import pixels

import exprclone
from exprclone import data as samples
from exprclone.drive.framing import resize_portrait
from exprclone.expressions.controls import CONTROLS
from exprclone.expressions.editor import Editor, request
from exprclone.io.images import load_image
from exprclone.landmarks.backends import default_detector

pytestmark = pytest.mark.slow  # servers, browsers, clusters or videos: pytest -m 'not slow' leaves these out

PHOTO = samples.path("003")


@pytest.fixture(scope="module")
def client():
    with serving.client("--workers", "1", "--max-edits", "2") as c:
        yield c


@pytest.fixture(scope="module")
def made(client):
    answer = client.post("/api/editor", files={"photo": (PHOTO.name, PHOTO.read_bytes())})
    assert answer.status_code == 201, answer.text
    yield answer.json()
    client.delete(f"/api/editor/{answer.json()['id']}")


def test_the_controls_are_listed_as_the_command_lists_them(client):
    listed = client.get("/api/editor/controls").json()["controls"]
    assert [c["name"] for c in listed] == [c.name for c in CONTROLS]
    assert all(c["made"] in ("learnt", "built") and c["sentence"] and c["scores"] for c in listed)


def test_a_render_at_full_size_is_the_apis_edit_bit_for_bit(client, made):
    assert (made["width"], made["height"], made["preview_width"], made["preview_height"]) == (1350, 1350, 512, 512)
    values = {"smile": 0.5, "brows_down": 0.75}
    full = client.post(made["render"], params={"preview": "false"}, data={k: str(v) for k, v in values.items()})
    assert full.headers["content-type"] == "image/png"
    assert np.array_equal(pixels(full), exprclone.edit(load_image(PHOTO), values).image)


def test_the_preview_is_the_edit_of_the_photo_at_512_pixels(client, made):
    """The preview: the photo at 512 pixels, its landmarks the full size's scaled, edited with the same values."""
    image = load_image(PHOTO)
    small, points = resize_portrait(image, default_detector().detect(image), 512)
    answer = client.post(made["render"], params={"format": "png"}, data={"mouth_open": "0.8"})
    expected = Editor.of(request(small, points)).render({"mouth_open": 0.8}).image
    assert np.array_equal(pixels(answer), expected)
    jpeg = client.post(made["render"], data={"mouth_open": "0.8"})
    assert jpeg.headers["content-type"] == "image/jpeg" and pixels(jpeg).shape == (512, 512, 3)


@pytest.mark.parametrize("field, value", [("smile", "1.5"), ("frown", "-0.2"), ("pucker", "lots")])
def test_a_value_out_of_range_is_refused(client, made, field, value):
    answer = client.post(made["render"], data={field: value})
    assert answer.status_code == 400 and answer.json()["error"].startswith(f"{field}: "), answer.text


def test_a_photo_without_a_face_is_named(client):
    blank = io.BytesIO()
    Image.new("RGB", (300, 300), (128, 128, 128)).save(blank, format="PNG")
    answer = client.post("/api/editor", files={"photo": ("blank.png", blank.getvalue())})
    assert answer.status_code == 422 and answer.json()["error"].startswith("photo: no face found")


def test_an_editor_is_forgotten_when_deleted(client):
    answer = client.post("/api/editor", files={"photo": (PHOTO.name, PHOTO.read_bytes())})
    render = answer.json()["render"]
    assert client.post(render, data={"smile": "1"}).status_code == 200
    assert client.delete(f"/api/editor/{answer.json()['id']}").status_code == 204
    assert client.post(render).status_code == 404 and client.delete(f"/api/editor/{answer.json()['id']}").status_code == 404


def test_the_editors_page_draws_a_slider_per_control_and_follows_them(client):
    """In a real browser: the page's sliders come from the server's list; choosing the sample photo shows it at its
    size, and a slider moved with the keyboard is rendered (the preview, then the full size to download)."""
    from browser import chromium

    with chromium() as page:
        page.goto(f"{client.base_url}/editor")
        page.wait_for_selector("#control-smile")
        assert page.eval_on_selector_all("#controls input[type=range]", "els => els.map(e => e.name)") == [c.name for c in CONTROLS]
        assert "learnt" in page.get_attribute("label[for=control-smile]", "title")
        page.click("#sample")
        rendered = "JSON.parse(document.querySelector('img#result').dataset.rendered || '{}')"
        page.wait_for_function(f"{rendered}.size === 'full'", timeout=60_000)
        assert page.evaluate("document.querySelector('img#result').naturalWidth") == 1350
        page.focus("#control-brows-up")
        for _ in range(4):
            page.keyboard.press("ArrowRight")
        page.wait_for_function(f"(r => r.size === 'full' && r.brows_up === '0.2')({rendered})", timeout=60_000)
        assert page.is_hidden("#error") and page.get_attribute("#download", "href").startswith("blob:")
        assert page.evaluate("window.previewTimes.length") >= 1
