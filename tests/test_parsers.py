"""Property-based tests (Hypothesis) of every parser of user input: whatever comes in, the answer is a value that
passes the checks the core relies on, or one ExprCloneError on one line naming the input; never another exception.

Each test draws a fixed number of cases (``max_examples``), derandomized: the same cases on every run. For a longer
hunt, ``EXPRCLONE_FUZZ_SCALE=20`` draws twenty times as many, at random.
"""

import json
import os
import struct
import zlib

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import exprclone
from exprclone import data as samples
from exprclone.batch.manifest import COLUMNS, read_manifest
from exprclone.errors import ExprCloneError
from exprclone.io.images import MAX_ASPECT, MIN_SIDE, check_size, load_image
from exprclone.io.landmarks import parse_landmarks, read_tem
from exprclone.landmarks.layout import DLIB68
from exprclone.options import Framing, Options, from_json
from exprclone.pipeline.checks import check_face
from exprclone.roles import ROLES
from exprclone.server.runtime.protocol import FIELDS, Misuse, check_frame, parse_message

#: how many times the cases below to draw (1, in CI: the same cases on every run).
SCALE = int(os.environ.get("EXPRCLONE_FUZZ_SCALE", "1"))


def fuzz(examples: int):
    """Hypothesis's settings for these tests: ``examples`` cases (times SCALE), no time limit per case."""
    return settings(
        max_examples=examples * SCALE, derandomize=SCALE == 1, database=None, deadline=None, suppress_health_check=list(HealthCheck)
    )


SHAPE = (1350, 1350, 3)
REAL = read_tem(samples.template("003"))
#: JSON values of any shape, numbers of any size among them.
JSON = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=8),
    lambda inner: (
        st.lists(inner, max_size=5) | st.dictionaries(st.sampled_from(["landmarks", "x", "type"]) | st.text(max_size=4), inner, max_size=3)
    ),
    max_leaves=20,
)
COORDINATE = st.floats(allow_nan=True, allow_infinity=True) | st.integers(min_value=-(10**400), max_value=10**400) | st.floats(0, 1349)


def refused_in_one_line(call, subject: str):
    """``call()``'s value, or None when it raised an ExprCloneError about ``subject`` in one line."""
    try:
        return call()
    except ExprCloneError as e:
        assert e.subject == subject and "\n" not in str(e), str(e)
        return None


def assert_usable(points) -> None:
    """What a landmark parser lets through: 68 finite points in the image, a face the stages can measure."""
    assert points.shape == (68, 2) and np.isfinite(points).all()
    assert (points >= 0).all() and (points[:, 0] <= SHAPE[1] - 1).all() and (points[:, 1] <= SHAPE[0] - 1).all()
    check_face(points, DLIB68, "checked")


@fuzz(150)
@given(
    st.one_of(
        JSON.map(json.dumps),
        st.text(max_size=200),
        st.lists(st.lists(COORDINATE, min_size=2, max_size=2), min_size=66, max_size=70).map(str),
    )
)
def test_json_landmark_files(text):
    points = refused_in_one_line(lambda: parse_landmarks(text, ".json", SHAPE, name="f.json"), "f.json")
    if points is not None:
        assert_usable(points)


@st.composite
def tem_texts(draw):
    """A .tem template: its count line and point lines of the real template, some of them broken."""
    lines = ["189"] + [f"{x} {y}" for x, y in REAL] + ["0"]
    for _ in range(draw(st.integers(0, 4))):
        k = draw(st.integers(0, len(lines) - 1))
        lines[k] = draw(
            st.text(max_size=12) | st.from_regex(r"-?[0-9]{1,400}(\.[0-9]*)?([eE][+-]?[0-9]{1,3})? +[0-9e.+-]{1,8}", fullmatch=True)
        )
    if draw(st.booleans()):
        del lines[draw(st.integers(0, len(lines) - 1)) :]
    return "\n".join(lines)


@fuzz(150)
@given(tem_texts())
def test_tem_templates(text):
    points = refused_in_one_line(lambda: parse_landmarks(text, ".tem", SHAPE, name="f.tem"), "f.tem")
    if points is not None:
        assert_usable(points)


@fuzz(200)
@given(
    st.text(max_size=300)
    | st.lists(st.lists(st.text(max_size=12) | st.sampled_from(["a.jpg", "", " ", "x\0y"]), max_size=7), max_size=5).map(
        lambda rows: "\n".join(",".join(map(str, COLUMNS)) if k == 0 else ",".join(r) for k, r in enumerate([[]] + rows))
    )
)
def test_manifests(tmp_path_factory, text):
    path = tmp_path_factory.mktemp("manifest") / "m.csv"
    path.write_text(text, encoding="utf-8", errors="surrogatepass")
    rows = refused_in_one_line(lambda: read_manifest(str(path)), str(path))
    for row in rows or []:
        assert all(isinstance(p, str) and p and "\0" not in p for p in (*row.photos, row.output))


@st.composite
def messages(draw):
    """A live text message: any text, or a JSON object with the protocol's fields, each of any JSON value."""
    if draw(st.booleans()):
        return draw(st.text(max_size=60))
    fields = draw(st.dictionaries(st.sampled_from(list(FIELDS)), JSON, max_size=6))
    fields["type"] = draw(st.sampled_from(["start", "options", "neutral"]) | JSON)
    return json.dumps(fields)


@fuzz(200)
@given(messages())
def test_live_messages(text):
    """A message is refused as Misuse, or every option it carries is then refused (if at all) as ExprCloneError."""
    try:
        message = parse_message(text)
    except Misuse as e:
        assert "\n" not in str(e)
        return
    try:
        Options.from_json(message)
        from_json(Framing, message)
    except ExprCloneError as e:
        assert e.subject in FIELDS and "\n" not in str(e)


def png_header(width: int, height: int, body: bytes = b"") -> bytes:
    """A PNG that declares ``width`` x ``height`` (its IHDR chunk with a right CRC), with ``body`` as its data."""

    def chunk(kind: bytes, payload: bytes) -> bytes:
        return struct.pack(">I", len(payload)) + kind + payload + struct.pack(">I", zlib.crc32(kind + payload))

    ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", body) + chunk(b"IEND", b"")


SIDES = st.integers(0, 2**31 - 1) | st.integers(0, 300)


@pytest.mark.filterwarnings("ignore::PIL.Image.DecompressionBombWarning")  # Pillow's alarm before our bound refuses
@fuzz(300)
@given(width=SIDES, height=SIDES, body=st.binary(max_size=64))
def test_image_headers_are_checked_before_decoding(width, height, body):
    """Any size a PNG header declares: refused in one line by its size, or decoded (or refused as corrupt); never
    an exception of another kind, never pixels decoded beyond the bound."""
    image = refused_in_one_line(lambda: load_image(png_header(width, height, body), name="p.png", max_pixels=25_000_000), "p.png")
    if image is not None:
        assert image.shape == (height, width, 3)
    fits = MIN_SIDE <= min(width, height) and max(width, height) <= MAX_ASPECT * min(width, height) and width * height <= 25_000_000
    assert (refused_in_one_line(lambda: check_size(width, height, "p.png", 25_000_000) or True, "p.png") is True) == fits
    try:
        check_frame(b"\0\0\0\1" + png_header(width, height, body), 25_000_000)
    except Misuse as e:
        assert e.subject == "frame"
    else:
        assert fits


@fuzz(150)
@given(st.binary(max_size=300))
def test_any_bytes_as_an_image_or_a_frame(content):
    refused_in_one_line(lambda: load_image(content, name="any"), "any")
    with pytest.raises(Misuse):
        check_frame(content, 25_000_000)  # no image of at least 32 x 32 pixels fits in 300 bytes


@pytest.fixture(scope="module")
def small_faces(photo):
    """The sample triple (001 neutral and smile onto 003) at a quarter of its size, and its detected landmarks."""
    import cv2

    images = [
        cv2.resize(photo(*which)[0], None, fx=0.25, fy=0.25, interpolation=cv2.INTER_AREA)
        for which in (("001",), ("001", "smile"), ("003",))
    ]
    return images, [photo(*which)[1] * 0.25 for which in (("001",), ("001", "smile"), ("003",))]


@st.composite
def degenerate(draw, points):
    """A face's landmarks broken as a hand-made file may break them: points collapsed, squashed, scaled, moved, shuffled."""
    p = points.copy()
    centre = p.mean(0)
    kind = draw(st.sampled_from(["collapse", "squash", "scale", "move", "shuffle"]))
    chosen = draw(st.lists(st.integers(0, 67), min_size=1, max_size=68, unique=True))
    if kind == "collapse":
        p[chosen] = p[chosen[0]]
    elif kind == "squash":
        axis = draw(st.integers(0, 1))
        p[:, axis] = centre[axis] + (p[:, axis] - centre[axis]) * draw(st.floats(0, 0.3))
    elif kind == "scale":
        p = centre + (p - centre) * draw(st.floats(0.01, 1.5))
    elif kind == "move":
        p[chosen] += np.array(draw(st.lists(st.floats(-80, 80), min_size=2, max_size=2)))
    else:
        p[chosen] = p[np.random.default_rng(draw(st.integers(0, 100))).permutation(chosen)]
    return np.clip(p, 0, 337)


@pytest.mark.filterwarnings("ignore::exprclone.errors.ExprCloneWarning")  # broken faces look like other people
@fuzz(40)
@given(data=st.data(), role=st.integers(0, 2))
def test_clone_takes_what_the_checks_let_through(small_faces, data, role):
    """The clone on broken landmarks: refused by the checks at the door, or done with no other error (warnings aside)."""
    images, points = small_faces
    given = list(points)
    given[role] = data.draw(degenerate(points[role]))
    result = refused_in_one_line(lambda: exprclone.clone(*images, landmarks=tuple(given), lambda_k=1.0), ROLES[role])
    if result is not None:
        assert result.image.shape == images[2].shape and np.isfinite(result.landmarks["final"]).all()
