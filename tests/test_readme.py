"""The README's Python snippets run as written (each in a fresh folder), so that they cannot rot."""

import re
from pathlib import Path

import pytest

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
