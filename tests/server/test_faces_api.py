"""A group photo over HTTP: its faces listed (``POST /api/faces``), every face or those chosen (the ``faces`` field)
cloned by ``/api/clone`` as the Python API clones them, and sliders over a group."""

import dataclasses
import io

import httpx
import numpy as np
import pytest
from PIL import Image
from serving import Server

import exprclone.expressions
from exprclone import data as samples
from exprclone.evaluation.groups import make

pytestmark = pytest.mark.slow  # servers, browsers, clusters or videos: pytest -m 'not slow' leaves these out


@pytest.fixture(scope="module")
def group_photo():
    """The three packaged people in one photo, as a PNG's bytes and as pixels."""
    image, _ = make(samples.london(), samples.PEOPLE, (110, 170, 250), (760, 800), seed=4)
    out = io.BytesIO()
    Image.fromarray(image).save(out, "PNG")
    return out.getvalue(), image


@pytest.fixture(scope="module")
def client():
    running = Server("--workers", "1")
    with httpx.Client(base_url=running.url, timeout=120) as c:
        yield c
    running.stop()


def pixels(answer: httpx.Response) -> np.ndarray:
    assert answer.status_code == 200, answer.text
    return np.asarray(Image.open(io.BytesIO(answer.content)).convert("RGB"))


def test_the_faces_of_a_photo_in_reading_order(client, group_photo):
    found = client.post("/api/faces", files={"photo": ("g.png", group_photo[0])}).json()
    assert (found["width"], found["height"]) == (760, 800)
    assert [f["number"] for f in found["faces"]] == [1, 2, 3] and all(f["problem"] == "" for f in found["faces"])
    assert found["faces"][1]["box"][0] < found["faces"][2]["box"][0] and all(len(f["box"]) == 4 for f in found["faces"])
    one = client.post("/api/faces", files={"photo": ("p.jpg", samples.path("003").read_bytes())}).json()
    assert len(one["faces"]) == 1


def test_clone_gives_the_faces_chosen_as_python_does(client, group_photo):
    content, image = group_photo
    r = client.post("/api/clone", files={"target_neutral": ("g.png", content)}, data={"expression": "smile", "faces": "1,3"})
    expected = exprclone.expressions.clone(image, "smile", faces=(1, 3))
    assert np.array_equal(pixels(r), expected.image)
    record = client.post(
        "/api/clone?format=json", files={"target_neutral": ("g.png", content)}, data={"expression": "smile", "faces": "2"}
    ).json()
    assert [f["problem"] for f in record["faces"]] == ["not chosen", "", "not chosen"]


def test_a_face_the_photo_has_not_is_refused(client, group_photo):
    r = client.post("/api/clone", files={"target_neutral": ("g.png", group_photo[0])}, data={"expression": "smile", "faces": "4"})
    assert r.status_code == 400 and r.json()["error"].startswith("faces: no face 4: the photo shows 3 faces")
    r = client.post("/api/clone", files={"target_neutral": ("g.png", group_photo[0])}, data={"expression": "smile", "faces": "two"})
    assert r.status_code in (400, 422) and "faces" in r.text


def test_sliders_over_a_group_render_its_own_size(client, group_photo):
    made = client.post("/api/edits", files={"target_neutral": ("g.png", group_photo[0])}, data={"expression": "smile"})
    assert made.status_code == 201, made.text
    edit = made.json()
    assert (edit["width"], edit["preview_width"], edit["lambda_k"]) == (760, 760, None)
    half = pixels(client.post(edit["render"], data={"strength": "0.5"}, params={"format": "png"}))
    assert np.array_equal(half, exprclone.expressions.clone(group_photo[1], "smile", strength=0.5).image)


def test_more_faces_than_the_server_clones_are_refused_before_any_is_cloned(group_photo):
    """``serve --max-faces``: a request that chooses more faces of its photo (all, by default) is refused once they are
    found, before any is cloned; the same photo with fewer chosen is cloned (in a worker's function, as the server runs
    it)."""
    from exprclone.errors import ExprCloneError
    from exprclone.io.inputs import Source
    from exprclone.options import Options
    from exprclone.roles import TARGET_NEUTRAL
    from exprclone.server import work

    photos = (None, None, Source(TARGET_NEUTRAL, group_photo[0]))
    request = work.CloneRequest(photos, (None, None, None), Options(), None, None, "11", frozenset(), "smile", max_faces=2)
    expected = f"faces: 3 faces of {TARGET_NEUTRAL} chosen; this server clones at most 2: choose some by number"
    with pytest.raises(ExprCloneError, match=f"^{expected}"):
        work.clone(request)
    encoded, record = work.clone(dataclasses.replace(request, options=Options(faces=(1, 3))))
    assert [f["problem"] for f in record["faces"]] == ["", "not chosen", ""]
