"""The faces of a group photo on the command line: listed and drawn (``exprclone faces``), chosen (``--faces``), and a
number the photo has not refused in one line."""

import json

import numpy as np
import pytest
from conftest import command, neutral_path, smile_path

from exprclone import data as samples
from exprclone.evaluation.groups import make
from exprclone.io.images import load_image, save_image


@pytest.fixture(scope="module")
def group_photo(tmp_path_factory):
    """The three packaged people in one photo (PNG): one behind, two in front."""
    path = tmp_path_factory.mktemp("group") / "group.png"
    image, _ = make(samples.london(), samples.PEOPLE, (110, 170, 250), (760, 800), seed=4)
    save_image(path, image)
    return path


def test_faces_lists_each_face_in_reading_order_and_draws_them(group_photo, tmp_path):
    preview = tmp_path / "preview.png"
    p = command("faces", group_photo, "--preview", preview)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert lines[0] == f"{group_photo}: 3 faces" and [line.split()[0] for line in lines[1:]] == ["1", "2", "3"]
    lefts = [int(line.split()[2].split(",")[0]) for line in lines[1:]]
    assert lefts[1] < lefts[2]  # the front row from the left, after the one behind
    drawn, photo = load_image(preview), load_image(group_photo)
    changed = np.abs(drawn.astype(int) - photo).max(2) > 0
    assert 0 < changed.mean() < 0.05  # the outlines and numbers alone


def test_one_face_is_listed_alone():
    p = command("faces", neutral_path("003"))
    assert p.returncode == 0 and p.stdout.splitlines()[0].endswith(": 1 face") and len(p.stdout.splitlines()) == 2


def test_clone_gives_the_chosen_faces_the_expression(group_photo, tmp_path):
    out, record = tmp_path / "out.png", tmp_path / "out.json"
    p = command("clone", group_photo, "--expression", "smile", "-o", out, "--faces", "1,3", "--save-json", record)
    assert p.returncode == 0, p.stderr
    assert p.stdout.strip() == f"{out}: e+md, expression smile, faces 1,3 of 3"
    faces = json.loads(record.read_text())["faces"]
    assert [f["problem"] for f in faces] == ["", "not chosen", ""] and faces[1]["landmarks"] is None
    x0, y0, x1, y1 = faces[0]["region"]
    assert all(x0 <= x <= x1 and y0 <= y <= y1 for x, y in faces[0]["landmarks"]["final"])  # in the photo's pixels
    photo, cloned = load_image(group_photo), load_image(out)
    box = [round(v) for v in faces[1]["box"]]
    assert np.array_equal(cloned[box[1] : box[3], box[0] : box[2]], photo[box[1] : box[3], box[0] : box[2]])


def test_the_three_photos_clone_the_source_pair_onto_each_face(group_photo, tmp_path):
    out = tmp_path / "out.png"
    p = command("clone", neutral_path("126"), smile_path("126"), group_photo, "-o", out, "--faces", "largest")
    assert p.returncode == 0, p.stderr
    assert p.stdout.strip().endswith(", face 3 of 3")


def test_a_face_the_photo_has_not_is_one_line_and_no_output(group_photo, tmp_path):
    out = tmp_path / "out.png"
    p = command("clone", group_photo, "--expression", "smile", "-o", out, "--faces", "2,7")
    assert p.returncode == 2 and not out.exists()
    assert p.stderr.strip() == "exprclone: error: faces: no face 7: the photo shows 3 faces (exprclone faces numbers them)"
    p = command("clone", group_photo, "--expression", "smile", "-o", out, "--faces", "first")
    assert p.returncode == 2 and "argument --faces: must be all, largest or face numbers from 1" in p.stderr


def test_compare_shows_one_face_of_a_group(group_photo, tmp_path):
    out = tmp_path / "sheet.png"
    p = command("compare", group_photo, "--expression", "smile", "-o", out, "--faces", "2")
    assert p.returncode == 0, p.stderr
    assert load_image(out).shape[1] > 1000
