"""exprclone study make: each set cloned by every method under random names, the key apart; bad input leaves nothing."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from serving import interruptible
from studies import METHOD_NAME, METHODS, SETS, SIZE, key, manifest, study

import exprclone
from exprclone.batch import job
from exprclone.errors import ExprCloneError
from exprclone.io.images import load_image
from exprclone.options import Options
from exprclone.study.folder import ID, read_key, read_study
from exprclone.study.make import make as make_study

pytestmark = pytest.mark.slow  # servers, browsers, clusters or videos: pytest -m 'not slow' leaves these out


def test_each_set_has_every_method_under_names_that_tell_nothing(made_study):
    public = (made_study / "study.json").read_text()
    assert not METHOD_NAME.search(public)
    assert sorted(os.listdir(made_study)) == ["images", "key.json", "study.json"]
    names = os.listdir(made_study / "images")
    assert all(ID.fullmatch(n.removesuffix(".png")) for n in names) and not any(METHOD_NAME.search(n) for n in names)
    listed = read_study(made_study)
    assert len(names) == len(listed.images()) == 5 + len(SETS) * len(METHODS)  # 3 people's neutral photos, 2 smiles, the results
    by_id = key(made_study)
    for k, s in enumerate(listed.sets):
        assert sorted(by_id[i] for i in s.items) == sorted((k, m) for m in METHODS)
        assert list(s.items) == sorted(s.items)  # by id, not in the methods' order
    assert read_key(made_study).names == tuple(name for name, _, _ in SETS)
    for s in listed.sets:  # a result's file size says nothing of its method: a set's results are files of one size
        assert len({(made_study / "images" / f"{i}.png").stat().st_size for i in s.items}) == 1


def test_the_key_names_the_method_that_made_each_result(made_study):
    """Each result is the clone its method gives from the study's own (resized) photos, as the Python API makes it."""
    first = read_study(made_study).sets[0]
    photos = [
        load_image(made_study / "images" / f"{first.photos[role]}.png")
        for role in ("source_neutral", "source_expression", "target_neutral")
    ]
    assert max(photos[2].shape[:2]) == SIZE
    expected = exprclone.clone_methods(*photos, methods=METHODS)
    for item in first.items:
        method = key(made_study)[item][1]
        assert np.array_equal(np.asarray(Image.open(made_study / "images" / f"{item}.png")), expected[method].image), method


@pytest.mark.parametrize(
    "content, message",
    [
        ("source_neutral,target_neutral\na.jpg,b.jpg\n", "the manifest has no column source_expression"),
        ("source_neutral,source_expression,target_neutral\na.jpg,,b.jpg\n", "row 1 has no source_expression"),
        ("source_neutral,source_expression,target_neutral\n", "no rows: a study needs at least one set"),
        (
            "set,source_neutral,source_expression,target_neutral\nx,a.jpg,b.jpg,c.jpg\nx,d.jpg,e.jpg,f.jpg\n",
            "rows 1 and 2 both name the set 'x'",
        ),
        ("source_neutral,source_expression,target_neutral\nnone.jpg,b.jpg,c.jpg\n", "none.jpg: no such file"),
        ("source_neutral,source_expression,target_neutral,lambda\na.jpg,b.jpg,c.jpg,-1\n", "row 1: lambda: "),
    ],
)
def test_an_unusable_manifest_is_one_line_and_leaves_nothing(tmp_path, content, message):
    (tmp_path / "m.csv").write_text(content)
    p = study("make", tmp_path / "m.csv", "-o", tmp_path / "study")
    assert p.returncode == 2 and message in p.stderr and len(p.stderr.strip().splitlines()) == 1, p.stderr
    assert sorted(os.listdir(tmp_path)) == ["m.csv"]


def make_here(folder: Path, sets, **options) -> None:
    """``study make`` in this process (its detector already loaded by the tests before), one method, one worker."""
    make_study(str(manifest(folder, sets)), folder / "study", ("global",), Options(), job.Local(1), max_size=SIZE, **options)


def test_a_photo_without_a_face_stops_the_study_naming_it(tmp_path):
    blank = tmp_path / "blank.png"
    Image.fromarray(np.full((300, 300, 3), 128, np.uint8)).save(blank)
    with pytest.raises(ExprCloneError) as e:
        make_here(tmp_path, [("one", "126", "003"), ("two", "126", str(blank))])
    assert str(e.value).startswith(f"{tmp_path / 'manifest.csv'}: set 'two', method global: {blank}: no face found")
    assert sorted(os.listdir(tmp_path)) == ["blank.png", "manifest.csv"]  # nothing half made


def test_a_study_is_replaced_only_when_asked_and_another_folder_never(study_folder):
    folder = study_folder.parent
    (study_folder / "ratings").mkdir()
    before = (study_folder / "study.json").read_text()
    p = study("make", manifest(folder), "-o", study_folder)
    assert p.returncode == 2 and "a study is there already; --overwrite replaces it" in p.stderr, p.stderr
    assert (study_folder / "study.json").read_text() == before and (study_folder / "ratings").is_dir()
    make_here(folder, [("one", "126", "003")], overwrite=True)
    assert len(read_study(study_folder).sets) == 1 and not (study_folder / "ratings").exists()
    assert sorted(os.listdir(study_folder)) == ["images", "key.json", "study.json"]
    assert sorted(os.listdir(folder)) == ["manifest.csv", "study"]
    (folder / "other").mkdir()
    (folder / "other" / "notes.txt").write_text("mine")
    p = study("make", manifest(folder), "-o", folder / "other", "--overwrite")
    assert p.returncode == 2 and "exists and is not a study folder" in p.stderr and (folder / "other" / "notes.txt").exists()


@pytest.mark.parametrize(
    "args, message",
    [
        (("--methods", "e+md,warp"), "unknown method 'warp'"),
        (("--max-size", "20"), "--max-size: expected at least 128 pixels"),
        (("--jobs", "0"), "--jobs"),
    ],
)
def test_bad_options_are_refused_before_any_work(tmp_path, args, message):
    p = study("make", manifest(tmp_path), "-o", tmp_path / "study", *args)
    assert p.returncode == 2 and message in p.stderr.strip().splitlines()[-1], p.stderr
    assert not (tmp_path / "study").exists()


def test_ctrl_c_leaves_nothing(tmp_path):
    sets = [(f"{s}-{t}", s, t) for s in ("001", "003", "126") for t in ("001", "003", "126") if s != t]  # 6 sets by 7 methods
    command = [sys.executable, "-m", "exprclone", "study", "make", str(manifest(tmp_path, sets)), "-o", str(tmp_path / "study")]
    command = [*command, "--max-size", str(SIZE), "--jobs", "1"]
    process = subprocess.Popen(command, stderr=subprocess.PIPE, text=True, preexec_fn=interruptible)
    deadline, photos = time.time() + 120, 3 + 3  # each person's two photos: more images than these are results
    while time.time() < deadline and sum(len(list(p.glob("images/*.png"))) for p in tmp_path.glob(".study.partial-*")) <= photos:
        time.sleep(0.05)
    process.send_signal(signal.SIGINT)
    _, err = process.communicate(timeout=120)
    assert process.returncode == 130 and "interrupted; no output written" in err, err
    assert sorted(os.listdir(tmp_path)) == ["manifest.csv"]
