"""An option added in one place, its declaration (:mod:`exprclone.options`), reaches the command line, the HTTP API's
schema, the options' answer and the page, with nothing else changed: a copy of the package with one more field."""

import shutil
import subprocess
import sys
from pathlib import Path

import httpx
import pytest
from browser import chromium
from serving import Server

import exprclone

pytestmark = pytest.mark.slow  # servers, browsers, clusters or videos: pytest -m 'not slow' leaves these out

#: the field added, before the last one of Options (its layout), as a developer would write it.
ADDED = """    sparkle: float = option(
        0.0,
        strength_spec(
            "how much sparkle to add to the eyes (an option of the tests)",
            Page("Sparkle", "How much the eyes sparkle.", "strengths", step=0.1),
        ),
    )
"""


@pytest.fixture(scope="module")
def package(tmp_path_factory):
    """A folder holding a copy of the package with :data:`ADDED` in its options, and its environment for Python."""
    folder = tmp_path_factory.mktemp("added")
    shutil.copytree(Path(exprclone.__file__).parent, folder / "exprclone", ignore=shutil.ignore_patterns("__pycache__"))
    declared = folder / "exprclone" / "options" / "clone_options.py"
    anchor = "    layout: Layout | None = option("
    assert declared.read_text().count(anchor) == 1
    declared.write_text(declared.read_text().replace(anchor, ADDED + anchor))
    env = {"PYTHONPATH": str(folder)}
    found = subprocess.run([sys.executable, "-c", "import exprclone; print(exprclone.__file__)"], capture_output=True, text=True, env=env)
    assert found.stdout.startswith(str(folder)), found
    return env


def test_the_command_line_offers_it(package):
    said = subprocess.run([sys.executable, "-m", "exprclone", "clone", "--help"], capture_output=True, text=True, env=package)
    assert said.returncode == 0 and "--sparkle S" in said.stdout and "how much sparkle to add" in said.stdout


def test_the_schema_the_answer_and_the_page_offer_it(package):
    server = Server("--workers", "1", env=package)
    try:
        schema = httpx.get(f"{server.url}/openapi.json").json()
        body = schema["components"]["schemas"]["Body_clone_api_clone_post"]["properties"]
        assert body["sparkle"]["maximum"] == 2 and body["sparkle"]["description"].startswith("how much sparkle")
        described = {o["key"]: o for o in httpx.get(f"{server.url}/api/options").json()["options"]}
        assert described["sparkle"]["page"]["label"] == "Sparkle" and described["sparkle"]["default"] == 0
        with chromium() as page:
            page.goto(server.url)
            page.wait_for_selector("#strengths input#sparkle")
            assert page.text_content("label[for=sparkle]") == "Sparkle" and page.input_value("#sparkle") == "0"
            page.fill("#sparkle", "0.5")
            form = "async () => { const f = new FormData(); await addOptions(f, ['Options']); return Object.fromEntries(f); }"
            sent = page.evaluate(form)
            assert sent["sparkle"] == "0.5" and sent["strength"] == "1"  # a clone's form carries it
    finally:
        server.stop()
