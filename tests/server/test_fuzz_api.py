"""A schema-driven fuzz of the whole HTTP API (Schemathesis, from the server's own OpenAPI) against a real server.

Every operation gets :data:`EXAMPLES` requests that follow its schema and :data:`EXAMPLES` that break it
(wrong types, missing fields), drawn reproducibly (``derandomize``: the same cases on every run). What
is checked (:func:`check`): no 5xx, every answer as the schema says it (its status declared, its media type, its
body: Schemathesis's own checks, :data:`CONFORMS`), and every JSON error an ``error`` string on one line. The
server's log must hold no traceback.

Drawn so, an upload is never a real photo or video, and clone, compare and video were fuzzed on their
400 paths alone: a second run gives the operations that take files real ones (the samples, made small),
their other fields drawn from the schema, so that the work itself runs on what a client may ask.
"""

import httpx
import pytest
import schemathesis
from hypothesis import HealthCheck, given, settings
from hypothesis.errors import Unsatisfiable
from schemathesis import GenerationMode
from schemathesis.checks import content_type_conformance, not_a_server_error, response_schema_conformance, status_code_conformance
from serving import Server

from exprclone import data as samples

pytestmark = pytest.mark.slow  # servers, browsers, clusters or videos: pytest -m 'not slow' leaves these out

#: requests per operation and generation mode.
EXAMPLES = 25
#: no network or disk between runs: the same cases every time.
FUZZ = settings(
    max_examples=EXAMPLES,
    derandomize=True,
    database=None,
    deadline=None,
    suppress_health_check=list(HealthCheck),
)


#: what each answer is checked for: Schemathesis's checks that it is as the schema says.
CONFORMS = [not_a_server_error, status_code_conformance, content_type_conformance, response_schema_conformance]


@pytest.fixture(scope="module")
def server():
    running = Server("--workers", "1", "--max-edits-per-client", "8", "--max-jobs-per-client", "8")  # (one client's cases)
    yield running.url
    _, err = running.stop()
    assert "Traceback" not in err, err[-3000:]


def check(case, response) -> None:
    """No server error, the answer as the schema says (:data:`CONFORMS`); a JSON error answer is ``{"error": "<one line>"}``."""
    assert response.status_code < 500, (response.status_code, response.text[:500])
    case.validate_response(response, checks=CONFORMS)
    kind = " ".join(response.headers.get("content-type", []))  # Schemathesis keeps each header's values as a list
    if response.status_code >= 400 and kind.startswith("application/json"):
        error = response.json().get("error")
        assert isinstance(error, str) and error and "\n" not in error, response.text[:500]


def test_every_operation_answers_without_a_server_error(server):
    schema = schemathesis.openapi.from_url(f"{server}/openapi.json")
    tried: dict[str, int] = {}
    for result in schema.get_all_operations():
        operation = result.ok()
        for mode in (GenerationMode.POSITIVE, GenerationMode.NEGATIVE):

            @FUZZ
            @given(case=operation.as_strategy(generation_mode=mode))
            def fuzz(case):
                check(case, case.call(base_url=server, timeout=60))
                tried[operation.label] = tried.get(operation.label, 0) + 1

            try:
                fuzz()
            except Unsatisfiable:  # no parameter to break (GET /api/health)
                assert mode is GenerationMode.NEGATIVE, operation.label
    print(f"\nschemathesis: {sum(tried.values())} requests over {len(tried)} operations: {tried}")
    assert len(tried) >= 8 and httpx.get(f"{server}/api/health").status_code == 200


#: requests per operation that takes files, with real photos and a real video.
REAL_EXAMPLES = 6


def small(path, side: int = 400) -> bytes:
    """A sample photo, its longest side ``side`` pixels, as JPEG (so that each clone takes a moment)."""
    import io

    from PIL import Image

    image = Image.open(path)
    image.thumbnail((side, side))
    out = io.BytesIO()
    image.convert("RGB").save(out, "JPEG", quality=90)
    return out.getvalue()


#: the files a case's form gets instead of what Schemathesis drew, by field; the landmark files and a built-in expression
#: are left out, so that the clone runs on the photos, and the faces chosen (numbers the schema cannot know: a number
#: beyond the photo's faces is rightly a 400).
REAL = {
    "source_neutral": small(samples.path(samples.SOURCE)),
    "source_expression": small(samples.path(samples.SOURCE, "smile")),
    "target_neutral": small(samples.path(samples.TARGET)),
    "portrait": small(samples.path(samples.TARGET)),
    "photo": small(samples.path(samples.TARGET)),
    "driving_video": samples.clip().read_bytes(),
}
DROPPED = ("expression", "faces", "source_neutral_landmarks", "source_expression_landmarks", "target_neutral_landmarks", "global_landmarks")


def fields(raw: dict, path: str) -> set[str]:
    """The form fields a POST to ``path`` takes (multipart, or URL-encoded when it takes no file), from the OpenAPI document
    ``raw``."""
    (media,) = raw["paths"][path]["post"]["requestBody"]["content"].values()
    body = media["schema"]["$ref"]
    return set(raw["components"]["schemas"][body.rsplit("/", 1)[1]]["properties"])


def test_the_operations_that_take_files_run_on_real_ones(server):
    schema = schemathesis.openapi.from_url(f"{server}/openapi.json")
    raw = httpx.get(f"{server}/openapi.json").json()
    answered: dict[str, list[int]] = {}
    refused: list[str] = []
    for result in schema.get_all_operations():
        operation = result.ok()
        if operation.method.upper() != "POST" or not operation.path.startswith("/api/"):
            continue

        @settings(FUZZ, max_examples=REAL_EXAMPLES)
        @given(case=operation.as_strategy(generation_mode=GenerationMode.POSITIVE))
        def real(case):
            if not isinstance(case.body, dict):
                return
            takes = fields(raw, operation.path)
            case.body = {k: v for k, v in case.body.items() if k not in DROPPED} | {k: REAL[k] for k in REAL if k in takes}
            response = case.call(base_url=server, timeout=120)
            check(case, response)
            answered.setdefault(operation.label, []).append(response.status_code)
            if response.status_code >= 300:
                refused.append(f"{operation.label} {response.status_code} {response.text[:200]} ({sorted(case.body)})")

        real()
    print(f"\nschemathesis with real files: {answered}")
    for label in ("POST /api/clone", "POST /api/compare", "POST /api/video", "POST /api/landmarks"):
        assert answered.get(label) and all(status < 300 for status in answered[label]), (label, answered, refused)
