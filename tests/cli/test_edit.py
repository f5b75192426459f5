"""``exprclone edit``: the controls listed, one photo edited, and every bad input one line, exit 2, no output."""

import json
import os

import numpy as np
import pytest
from conftest import command, neutral_path
from PIL import Image

from exprclone.expressions.controls import CONTROLS
from exprclone.expressions.editor import Editor, request
from exprclone.io.images import load_image
from exprclone.options import Options

PHOTO = str(neutral_path("003"))


def test_the_list_names_each_control_and_how_it_was_made():
    p = command("edit", "--list")
    lines = p.stdout.splitlines()
    assert p.returncode == 0 and [line.split()[0] for line in lines] == [c.name for c in CONTROLS]
    for line, control in zip(lines, CONTROLS):
        assert control.sentence in line and f"({control.made}: {control.source})" in line


def test_an_edit_is_the_editors_image(tmp_path):
    out = tmp_path / "out.png"
    p = command("edit", PHOTO, "-o", out, "--set", "smile=0.6,brows_up=1", "--set", "wink_left=0.5")
    assert p.returncode == 0, p.stderr
    assert p.stdout.strip() == f"{out}: smile 0.6, brows up 1, wink left 0.5"
    expected = Editor.of(request(load_image(PHOTO))).render({"smile": 0.6, "brows_up": 1.0, "wink_left": 0.5})
    assert np.array_equal(np.asarray(Image.open(out).convert("RGB")), expected.image)


def test_given_landmarks_and_options_are_used(tmp_path, photo):
    image, points = photo("003")
    marks, out = tmp_path / "marks.json", tmp_path / "out.png"
    moved = points + (0.0, 3.0)  # the face's landmarks said 3 pixels lower: the edit moves those
    marks.write_text(json.dumps(moved.tolist()))
    p = command("edit", PHOTO, "-o", out, "--landmarks", marks, "--set", "mouth_open=1", "--image-warp", "tps", "--no-mouth")
    assert p.returncode == 0, p.stderr
    expected = Editor.of(request(image, moved, Options(image_warp="tps", mouth=False))).render({"mouth_open": 1.0})
    assert np.array_equal(np.asarray(Image.open(out).convert("RGB")), expected.image)


@pytest.mark.parametrize(
    "args, said",
    [
        (["--set", "grin=1"], "grin: unknown control"),
        (["--set", "smile=1.2"], "smile: must be a number from 0 to 1"),
        (["--set", "smile"], "smile: must be a number from 0 to 1"),
        (["--landmarks", "missing.json"], "missing.json"),
    ],
)
def test_a_bad_input_is_one_line_and_leaves_no_output(tmp_path, args, said):
    out = tmp_path / "out.png"
    p = command("edit", PHOTO, "-o", out, *args, cwd=tmp_path)
    assert p.returncode == 2 and p.stderr.count("\n") == 1 and said in p.stderr, p.stderr
    assert os.listdir(tmp_path) == []


def test_a_photo_without_a_face_is_named(tmp_path):
    blank, out = tmp_path / "blank.png", tmp_path / "out.png"
    Image.new("RGB", (300, 300), (128, 128, 128)).save(blank)
    p = command("edit", blank, "-o", out, "--set", "smile=1")
    assert p.returncode == 2 and p.stderr.startswith(f"exprclone: error: {blank}: no face found") and not out.exists()


def test_an_edit_needs_a_photo_and_an_output():
    p = command("edit", PHOTO)
    assert p.returncode == 2 and "give a photo and -o OUT" in p.stderr
