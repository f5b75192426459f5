"""The HTTP API's own documentation: the error answers in the OpenAPI schema, and /docs and /redoc working offline."""

import json
import re
from urllib.parse import urlsplit

import pytest
from browser import chromium
from serving import Server

from exprclone import __version__
from exprclone.server.app import create_app

pytestmark = pytest.mark.slow  # servers, browsers, clusters or videos: pytest -m 'not slow' leaves these out

#: milliseconds a documentation page may take to render the schema.
RENDER_TIMEOUT = 30_000


def test_the_schema_lists_the_error_answers_of_clone():
    schema = create_app().openapi()
    answers = schema["paths"]["/api/clone"]["post"]["responses"]
    for status in ("400", "413", "422", "503"):
        assert answers[status]["content"]["application/json"]["schema"] == {"$ref": "#/components/schemas/ErrorAnswer"}
    assert schema["components"]["schemas"]["ErrorAnswer"]["required"] == ["error"]


def test_every_error_status_of_the_schema_has_the_error_model_and_none_is_fastapis_default():
    schema = create_app().openapi()
    for path, operations in schema["paths"].items():
        for method, operation in operations.items():
            errors = {status: answer for status, answer in operation["responses"].items() if status >= "400"}
            if method == "post":
                assert {"400", "413"} <= set(errors), path  # every upload may be refused as bad or too large
            for status, answer in errors.items():
                assert answer["content"]["application/json"]["schema"]["$ref"].endswith("/ErrorAnswer"), (path, status)
    assert "HTTPValidationError" not in str(schema)


def test_the_schema_reads_as_markdown_and_its_examples_are_real():
    """No Sphinx role (``:mod:`...```) nor reST's double backquotes in a description; health's example is its answer."""
    schema = create_app().openapi()
    text = json.dumps(schema)
    assert not re.search(r":[a-z]+:`", text) and "``" not in text
    answer = schema["paths"]["/api/health"]["get"]["responses"]["200"]["content"]["application/json"]["schema"]["$ref"]
    health = schema["components"]["schemas"][answer.rsplit("/", 1)[1]]
    assert health["examples"] == [{"status": "ok", "version": __version__}] and health["required"] == ["status", "version"]


@pytest.fixture(scope="module")
def server():
    running = Server("--workers", "1")
    yield running.url
    running.stop()


@pytest.mark.parametrize("page_path, rendered", [("/docs", ".opblock"), ("/redoc", "[data-section-id]")])
def test_the_documentation_pages_render_with_no_request_to_another_host(server, page_path, rendered):
    """Every request the page asks for goes to the server (ReDoc's footer logo too: its script is the server's copy)."""
    with chromium() as page:
        sent = []
        page.on("request", lambda request: sent.append(request.url))
        answer = page.goto(server + page_path)
        page.wait_for_selector(rendered, timeout=RENDER_TIMEOUT)
        page.wait_for_load_state("networkidle")
        assert "/api/clone" in page.content()
    assert "default-src 'self'" in answer.headers["content-security-policy"]
    hosts = {urlsplit(url).netloc for url in sent if not url.startswith(("data:", "blob:"))}
    assert hosts == {urlsplit(server).netloc}, sent
