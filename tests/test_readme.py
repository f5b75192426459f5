"""The README's Python snippets run as written (each in a fresh folder), so that they cannot rot; its first command
installs what every command it shows needs."""

import json
import os
import re
import signal
import subprocess
import sys
import time
from importlib import metadata
from pathlib import Path

import httpx
import pytest
from packaging.requirements import Requirement

from exprclone.testing.servers import free_port, interruptible

README = Path(__file__).resolve().parents[1] / "README.md"
SNIPPETS = re.findall(r"^```python\n(.*?)^```", README.read_text(), re.S | re.M)


def test_the_readme_has_python_snippets():
    assert len(SNIPPETS) >= 2


@pytest.mark.parametrize("number", range(len(SNIPPETS)))
def test_a_readme_snippet_runs(number, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    exec(compile(SNIPPETS[number], f"README.md, Python snippet {number + 1}", "exec"), {"__name__": "__readme__"})


@pytest.mark.slow
def test_the_demo_writes_what_it_says_and_the_readme_commands_keep_it(tmp_path):
    """The README's first command (``exprclone demo -o out``) writes each file it lists, each readable; the README's
    command lines write into ``out/`` only files the demo does not (they overwrote its clone.png)."""
    from conftest import command

    from exprclone.io.images import load_image
    from exprclone.io.video import probe

    p = command("demo", "-o", tmp_path)
    listed = [line.split(": ", 1)[0] for line in p.stdout.splitlines() if line.startswith(str(tmp_path))]
    assert p.returncode == 0 and sorted(Path(f).name for f in listed) == sorted(f.name for f in tmp_path.iterdir()), p.stdout
    for name in ("clone.png", "smile.png", "compare.jpg"):
        assert load_image(tmp_path / name).shape[2] == 3
    assert probe(str(tmp_path / "video.mp4")).frames > 10
    assert re.search(r"exprclone demo -o (\S+)", README.read_text())[1] == "out"
    written = re.findall(r" -o out/(\S+)", README.read_text())
    assert written and not set(written) & {f.name for f in tmp_path.iterdir()}, written


def canonical(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def first_install() -> tuple[str, ...]:
    """The extras the README's first command installs exprclone with (``pip install .`` none, ``'.[server]'`` one)."""
    first = re.search(r"^```\n(.*?)^```", README.read_text(), re.S | re.M)[1]
    words = re.search(r"pip install (?:-e )?'?\.(?:\[([\w,]+)\])?'?(?:\s|$)", first)
    assert words, f"the README's first command installs no exprclone from its checkout: {first}"
    return tuple(words[1].split(",")) if words[1] else ()


def installed_with(extras: tuple[str, ...]) -> set[str]:
    """Every distribution ``pip install 'exprclone[extras]'`` brings: exprclone's requirements with those extras
    (as its installed metadata declares them), and theirs, to the end."""
    found, todo = set(), [("exprclone", extras)]
    while todo:
        name, asked = todo.pop()
        if (canonical(name), asked) in found:
            continue
        found.add((canonical(name), asked))
        for text in metadata.requires(name) or []:
            needed = Requirement(text)
            if needed.marker is None or any(needed.marker.evaluate({"extra": e}) for e in asked or ("",)):
                todo.append((needed.name, tuple(sorted(needed.extras))))
    return {name for name, _ in found}


#: ``exprclone serve`` in a Python that can import no distribution but those of ``sys.argv[1]`` (JSON), and the standard
#: library: as on a fresh machine where only the README's first command has installed anything.
FRESH = """
import importlib.abc, importlib.metadata, json, re, sys
allowed = set(json.loads(sys.argv[1]))
owners = importlib.metadata.packages_distributions()
class NotInstalled(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path, target=None):
        top = name.partition(".")[0]
        found = {re.sub(r"[-_.]+", "-", d).lower() for d in owners.get(top, ())}
        if top not in sys.stdlib_module_names and found and not found & allowed:
            raise ModuleNotFoundError(f"No module named {top!r} (not installed by the README)", name=top)
        return None
sys.meta_path.insert(0, NotInstalled())
from exprclone.cli.main import main
sys.exit(main(sys.argv[2:]))
"""


@pytest.mark.slow
def test_the_readmes_first_command_installs_what_serve_needs(tmp_path):
    """``exprclone serve`` after the README's first command alone: in a Python that imports only the distributions that
    command installs, the server starts, answers its health route, its page and options, and takes a live WebSocket
    (uvicorn without the websockets package would refuse it)."""
    import websockets.sync.client

    allowed = installed_with(first_install())
    assert {"fastapi", "uvicorn", "websockets", "python-multipart"} <= allowed, sorted(allowed)
    port = free_port()
    words = ["serve", "--port", str(port), "--workers", "1", "--video-workers", "1"]
    with open(tmp_path / "err", "w+") as err:
        server = subprocess.Popen(
            [sys.executable, "-c", FRESH, json.dumps(sorted(allowed)), *words], stderr=err, stdout=err, preexec_fn=interruptible
        )
        try:
            deadline, answer = time.time() + 90, None
            while time.time() < deadline and server.poll() is None and answer is None:
                try:
                    answer = httpx.get(f"http://127.0.0.1:{port}/api/health", timeout=1)
                except httpx.TransportError:
                    time.sleep(0.2)
            err.seek(0)
            assert answer is not None and answer.json()["status"] == "ok", err.read()
            for path in ("/", "/api/options", "/docs"):
                assert httpx.get(f"http://127.0.0.1:{port}{path}").status_code == 200, path
            with websockets.sync.client.connect(f"ws://127.0.0.1:{port}/api/live", open_timeout=10) as live:
                live.send(json.dumps({"type": "nonsense"}))
                assert json.loads(live.recv(timeout=10))["type"] == "error"
        finally:
            if server.poll() is None:
                os.kill(server.pid, signal.SIGINT)
            server.wait(timeout=30)
