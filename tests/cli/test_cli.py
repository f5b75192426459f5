"""The command: a real run, and every bad input ending in one line, exit 2, no output."""

import csv
import json
import os
import re
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest
from conftest import command, neutral_path, smile_path
from PIL import Image

import exprclone
import exprclone.expressions
from exprclone.evaluation.panels import BAND, CELL, HEIGHT
from exprclone.expressions.files import write

SN, SE, TN = str(neutral_path("001")), str(smile_path("001")), str(neutral_path("003"))


run = command  # in this process: the commands' own subprocesses (workers) aside, no test here needs one


def test_clone_writes_image_and_json(london, tmp_path):
    out, record = tmp_path / "out.png", tmp_path / "out.json"
    p = run("clone", SN, SE, TN, "-o", out, "--save-json", record, "--no-retarget")  # the paper's stages: a DB curve
    assert p.returncode == 0, p.stderr
    assert Image.open(out).size == Image.open(TN).size
    data = json.loads(record.read_text())
    assert data["method"] == "e+md" and len(data["landmarks"]["final"]) == 68
    assert len(data["db_curve"]) > 5 and data["lambda_k"] in [c["lambda_k"] for c in data["db_curve"]]
    for candidate in data["db_curve"]:  # Eq. 7, its terms as they came: DB = e^to_source + e^to_global
        assert candidate["db"] == pytest.approx(np.exp(candidate["to_source"]) + np.exp(candidate["to_global"]))
    assert sorted(os.listdir(tmp_path)) == ["out.json", "out.png"]  # no temporary files left
    assert run("clone", SN, SE, TN, "-o", out, "--save-json", record).returncode == 0  # the product's: nothing to choose
    data = json.loads(record.read_text())
    assert data["lambda_k"] == 0 and data["db_curve"] is None


def test_clone_with_given_landmarks_and_fixed_lambda(pair, tmp_path):
    _, landmarks = pair
    files = []
    for name, lm in zip(("sn", "se", "tn"), landmarks):
        files.append(tmp_path / f"{name}.json")
        files[-1].write_text(json.dumps({"landmarks": lm.tolist()}))
    out, record = tmp_path / "out.jpg", tmp_path / "out.json"
    p = run(
        "clone",
        SN,
        SE,
        TN,
        "-o",
        out,
        "--method",
        "local+eri",
        "--lambda",
        "3",
        "--save-json",
        record,
        "--source-neutral-landmarks",
        files[0],
        "--source-expression-landmarks",
        files[1],
        "--target-neutral-landmarks",
        files[2],
    )
    assert p.returncode == 0, p.stderr
    data = json.loads(record.read_text())
    assert np.allclose(data["landmarks"]["target_neutral"], landmarks[2], atol=1e-3)


def expect_error(tmp_path, args, needle):
    """Exit 2, one line on stderr naming ``needle``, no traceback and no output file."""
    out = tmp_path / "result.png"
    p = run("clone", *args, "-o", out) if "-o" not in args else run("clone", *args)
    assert p.returncode == 2, p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("exprclone: error: ") and str(needle) in lines[0], p.stderr
    assert "Traceback" not in p.stderr
    assert not out.exists()
    assert not [f for f in os.listdir(tmp_path) if f.startswith(".result")]


def test_missing_file(london, tmp_path):
    expect_error(tmp_path, [SN, tmp_path / "nope.jpg", TN], tmp_path / "nope.jpg")


def test_not_an_image(london, tmp_path):
    fake = tmp_path / "fake.jpg"
    fake.write_text("hello")
    expect_error(tmp_path, [SN, SE, fake], fake)


def test_no_face(london, tmp_path):
    blank = tmp_path / "wall.png"
    Image.fromarray(np.full((300, 400, 3), 200, np.uint8)).save(blank)
    expect_error(tmp_path, [blank, SE, TN], f"{blank}: no face found")


def test_landmark_file_with_wrong_count(pair, tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"landmarks": pair[1][2][:50].tolist()}))
    expect_error(tmp_path, [SN, SE, TN, "--target-neutral-landmarks", bad], bad)


def test_landmark_file_outside_the_image(pair, tmp_path):
    bad = tmp_path / "bad.json"
    lm = pair[1][2].copy()
    lm[10] = (5000, 20)
    bad.write_text(json.dumps({"landmarks": lm.tolist()}))
    expect_error(tmp_path, [SN, SE, TN, "--target-neutral-landmarks", bad], bad)


def test_output_is_an_input(london, tmp_path):
    copy = tmp_path / "target.jpg"
    copy.write_bytes(open(TN, "rb").read())
    before = copy.read_bytes()
    p = run("clone", SN, SE, copy, "-o", copy)
    assert p.returncode == 2 and "overwrite" in p.stderr and str(copy) in p.stderr
    assert copy.read_bytes() == before


@pytest.mark.parametrize("args,needle", [(["--method", "magic"], "invalid choice"), (["--lambda", "-1"], "--lambda")])
def test_bad_options(london, tmp_path, args, needle):
    p = run("clone", SN, SE, TN, "-o", tmp_path / "r.png", *args)
    assert p.returncode == 2 and needle in p.stderr
    assert not (tmp_path / "r.png").exists()


@pytest.mark.parametrize(
    "words, said, meant",
    [
        (["clone", SN, SE, TN, "-o", "r.png", "--strenght", "0.5"], "unrecognized arguments: --strenght 0.5", "--strength"),
        (["clone", SN, SE, TN, "--ouput", "r.png"], "unrecognized arguments: --ouput", "--output"),  # not "-o is required"
        (["clone", SN, SE, TN, "-o", "r.png", "--method", "e+mb"], "invalid choice: 'e+mb'", "e+md"),
        (["clne"], "invalid choice: 'clne'", "clone"),
        (["study", "serv"], "invalid choice: 'serv'", "serve"),
    ],
)
def test_a_mistyped_word_is_one_line_with_the_closest_and_the_commands_help(tmp_path, words, said, meant):
    p = run(*[str(tmp_path / w) if w == "r.png" else w for w in words])
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 2 and len(lines) == 1 and said in lines[0] and f"(did you mean {meant}?)" in lines[0], p.stderr
    helped = "exprclone --help" if words == ["clne"] else f"exprclone {words[0]} --help"
    assert lines[0].endswith(f"; see {helped}") and not list(tmp_path.iterdir())


def test_compare_draws_the_sheet(london, tmp_path):
    """Fig. 11's rows by the paper's stages, then the default's; with --no-retarget the paper's alone."""
    out = tmp_path / "panel.png"
    p = run("compare", SN, SE, TN, "-o", out)
    assert p.returncode == 0, p.stderr
    assert Image.open(out).size == (9 * CELL, BAND + 4 * HEIGHT) and "by the paper's stages, lambda_k=" in p.stdout
    p = run("compare", SN, SE, TN, "-o", out, "--no-retarget")
    assert p.returncode == 0 and Image.open(out).size == (9 * CELL, BAND + 3 * HEIGHT) and "default" not in p.stdout


def test_evaluate_on_two_pairs(london, tmp_path):
    """The summary a person reads by default: which method is best on each score, with intervals, in a screenful, and
    where the full tables are; they are in summary.md (after the same summary), and printed with --full, with what every
    sign of them means."""
    from exprclone.evaluation.digest import SCORES

    out = tmp_path / "report"
    p = run("evaluate", "--data", london, "--pairs", "2", "--methods", "global,e+md", "--out", out)
    assert p.returncode == 0, p.stderr
    rows = (out / "pairs.csv").read_text().splitlines()
    assert len(rows) == 1 + 2 * 4  # header, then (no change, real, global, e+md) per pair
    summary = (out / "summary.md").read_text()
    assert "| e+md |" in summary and "| no change |" in summary and (out / "gallery.jpg").is_file()
    assert "## Which method is best on what" in summary and summary.index("best on what") < summary.index("## All pairs")
    assert "| method | results judged | to the source's expression: mouth |" in summary  # the blendshape judge's table
    said = p.stdout.splitlines()
    assert len(said) <= 30 and max(len(line) for line in said) <= 120 and "|" not in p.stdout, p.stdout
    for score in SCORES:
        assert re.search(rf"^- {re.escape(score.name)} \((lower|higher) is better\): best (global|e\+md)", p.stdout, re.M), score.name
    assert f"{out / 'summary.md'} (or --full)" in p.stdout
    full = run("evaluate", "--data", london, "--pairs", "2", "--methods", "global,e+md", "--out", out, "--full")
    assert "| real | 2 | 0 | 0.0000 / 0.0000" in full.stdout and "Reading the tables: `a / b` is a mean / a median" in full.stdout
    assert "`-` where there is nothing to measure" in full.stdout and "Reading the tables" in summary
    scores = list(csv.DictReader(open(out / "blendshapes.csv")))
    assert len(scores) == 2 * 4 and float(scores[0]["mouthSmileLeft"]) >= 0 and len(scores[0]) == 3 + 52


def test_evaluate_rejects_an_unknown_method(london, tmp_path):
    p = run("evaluate", "--data", london, "--methods", "global,warp", "--out", tmp_path / "r")
    assert p.returncode == 2 and "warp" in p.stderr and not (tmp_path / "r").exists()


def test_start_up_stays_lean():
    """`import exprclone` and `exprclone --help` load neither numpy, OpenCV, SciPy nor dlib."""
    heavy = "{'numpy', 'cv2', 'scipy', 'dlib'}"
    code = f"import sys, exprclone, exprclone.cli; exprclone.cli.build_parser(); print(sorted({heavy} & set(sys.modules)))"
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert p.returncode == 0 and p.stdout.strip() == "[]", p.stdout + p.stderr
    assert callable(__import__("exprclone").clone)  # the pipeline is there when asked for


def test_the_core_loads_no_outer_layer():
    """The method (pipeline, drive) imports neither file formats (Pillow, PyAV) nor the server's or batch's libraries."""
    outer = "{'PIL', 'av', 'fastapi', 'uvicorn', 'dask', 'distributed', 'exprclone.io', 'exprclone.cli', 'exprclone.server'}"
    loaded = "{'.'.join(m.split('.')[:2]) if m.startswith('exprclone') else m.split('.')[0] for m in sys.modules}"
    code = f"import sys, exprclone.pipeline.clone, exprclone.drive; print(sorted({outer} & {loaded}))"
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert p.returncode == 0 and p.stdout.strip() == "[]", p.stdout + p.stderr


def test_clone_with_the_transfer_options(london, tmp_path):
    out, record = tmp_path / "out.png", tmp_path / "out.json"
    args = ("--global-warp", "rbf", "--image-warp", "tps", "--strength", "0", "--no-retarget", "--save-json", record)
    p = run("clone", SN, SE, TN, "-o", out, *args)
    assert p.returncode == 0, p.stderr
    assert "global warp rbf, image warp tps, strength 0, no retarget" in p.stdout
    assert np.abs(np.asarray(Image.open(out)).astype(int) - np.asarray(Image.open(TN))).max() <= 1  # strength 0: the target
    recorded = json.loads(record.read_text())["options"]
    regions = {"mouth": 0.0, "eyes": 0.0, "brows": 0.0}
    assert recorded == {
        **{"global_warp": "rbf", "image_warp": "tps", "strength": 0.0, "only": None, "retarget": False},
        **{"region_strengths": regions, "strength_shading": 1.0},
    }


def test_global_landmarks_equal_to_the_default_gi_give_the_default_image(pair, tmp_path):
    """Fig. 21's setting from the command line: the GI of the default clone, given as a file, gives the same image."""
    from exprclone.io.landmarks import write_landmarks

    images, landmarks = pair
    files = []
    for role, lm in zip(("source-neutral", "source-expression", "target-neutral"), landmarks):
        write_landmarks(tmp_path / f"{role}.json", lm)
        files += [f"--{role}-landmarks", tmp_path / f"{role}.json"]
    write_landmarks(tmp_path / "gi.json", exprclone.clone(*images, landmarks=landmarks).landmarks["global"])
    assert run("clone", SN, SE, TN, "-o", tmp_path / "default.png", *files).returncode == 0
    p = run("clone", SN, SE, TN, "-o", tmp_path / "given.png", *files, "--global-landmarks", tmp_path / "gi.json")
    assert p.returncode == 0 and "global landmarks given" in p.stdout, p.stderr
    assert np.array_equal(np.asarray(Image.open(tmp_path / "given.png")), np.asarray(Image.open(tmp_path / "default.png")))


def test_compare_draws_figure_19(london, tmp_path):
    out = tmp_path / "fig19.png"
    p = run("compare", SN, SE, TN, "-o", out, "--figure", "19")
    assert p.returncode == 0, p.stderr
    assert Image.open(out).size == (6 * CELL, HEIGHT) and "global warp rbf" in p.stdout


@pytest.mark.parametrize("figure, methods", [("16", 4), ("17", 3)])
def test_compare_draws_figures_16_and_17(london, tmp_path, figure, methods):
    """Song et al.'s method beside the paper's (Fig. 16), and the elastic model and E+MD on its global warp (Fig. 17):
    the target, the methods, the source, then E+MD's difference to Song et al.'s and the DB curve."""
    out = tmp_path / f"fig{figure}.png"
    p = run("compare", SN, SE, TN, "-o", out, "--figure", figure)
    assert p.returncode == 0, p.stderr
    assert Image.open(out).size == ((methods + 4) * CELL, HEIGHT) and f"Fig. {figure}, {methods} methods, lambda_k=" in p.stdout


def test_figure_17_shows_song_et_als_global_warp_alone(london, tmp_path):
    p = run("compare", SN, SE, TN, "-o", tmp_path / "f.png", "--figure", "17", "--global-warp", "rbf")
    assert p.returncode == 2 and "global_warp: Fig. 17 shows the methods on Song et al.'s global warp, vtc" in p.stderr, p.stderr
    assert not (tmp_path / "f.png").exists()


@pytest.mark.parametrize(
    "args,needle",
    [
        (["--strength", "3"], "--strength"),
        (["--strength", "much"], "--strength"),
        (["--only", "mouth,nose"], "unknown region 'nose'"),
        (["--global-warp", "affine"], "invalid choice"),
        (["--image-warp", "spline"], "invalid choice"),
        (["--global-warp", "rbf", "--global-landmarks", "gi.json"], "not allowed with"),
    ],
)
def test_bad_transfer_options(london, tmp_path, args, needle):
    p = run("clone", SN, SE, TN, "-o", tmp_path / "r.png", *args)
    assert p.returncode == 2 and needle in p.stderr, p.stderr
    assert not (tmp_path / "r.png").exists()


def test_a_global_landmark_file_with_the_wrong_count(pair, tmp_path):
    bad = tmp_path / "gi.json"
    bad.write_text(json.dumps({"landmarks": pair[1][2][:50].tolist()}))
    expect_error(tmp_path, [SN, SE, TN, "--global-landmarks", bad], f"{bad}: found 50 landmarks")


def test_evaluate_with_variants(london, tmp_path):
    out = tmp_path / "report"
    words = ("--pairs", "1", "--methods", "global,elastic", "--global-warps", "similarity,rbf", "--out", out, "--full")
    p = run("evaluate", "--data", london, *words)
    assert p.returncode == 0, p.stderr
    rows = (out / "pairs.csv").read_text().splitlines()
    assert len(rows) == 1 + 2 + 2 * 2  # header, the references, then two methods in two variants
    assert "| elastic [rbf] | 1 | 0 |" in p.stdout and "| global [rbf] - global | 1 |" in p.stdout
    assert "## Pair by pair" in (out / "summary.md").read_text() and "| elastic [rbf] - global [rbf] | 1 |" in p.stdout
    p = run("evaluate", "--data", london, "--global-warps", "affine", "--out", tmp_path / "r")
    assert p.returncode == 2 and "unknown global warp 'affine'" in p.stderr


@pytest.mark.parametrize(
    "kind, content, problem",
    [
        ("strip.png", None, "image is too narrow (32x40000 pixels; the long side may be at most 8 times the short one)"),
        (
            "same.json",
            json.dumps([[500, 500]] * 68),
            "not a face: the outer eye corners (points 36 and 45) are 0 pixels apart (at least 8)",
        ),
        ("count.tem", "1" * 5000 + "\n", "not a .tem template (the first line must be the point count, got '1111"),
    ],
)
def test_hostile_files_end_in_one_line_and_exit_2(tmp_path, kind, content, problem):
    """The server's hostile inputs (issue D1, D2) on the command line: a thin photo, broken landmark files."""
    path = tmp_path / kind
    if content is None:
        Image.new("RGB", (32, 40000)).save(path)
    else:
        path.write_text(content)
    args = [path, SE, TN] if content is None else [SN, SE, TN, "--target-neutral-landmarks", path]
    p = run("clone", *args, "-o", tmp_path / "out.png")
    assert p.returncode == 2 and p.stderr.startswith(f"exprclone: error: {path}: {problem}") and p.stderr.count("\n") == 1, p.stderr
    assert not (tmp_path / "out.png").exists()


def test_version_prints_the_version():
    done = run("--version")
    assert done.returncode == 0 and done.stdout.strip() == f"exprclone {exprclone.__version__}"


def test_expressions_lists_the_built_in_names_and_what_each_is():
    p = run("expressions")
    lines = [line.split(maxsplit=1) for line in p.stdout.splitlines()]
    assert p.returncode == 0 and [name for name, _ in lines] == list(exprclone.expressions.names())
    said = dict(lines)
    assert said["smile"].startswith("an open prototype smile") and said["smile-001"].startswith("person 001's own smile"), said


def test_clone_one_photo_with_a_built_in_expression(london, tmp_path):
    out, record = tmp_path / "out.png", tmp_path / "out.json"
    p = run("clone", TN, "--expression", "smile", "--strength", "0.7", "--only", "mouth", "-o", out, "--save-json", record)
    assert p.returncode == 0, p.stderr
    assert "expression smile" in p.stdout and "strength 0.7" in p.stdout and "only mouth" in p.stdout
    data = json.loads(record.read_text())
    assert data["inputs"]["target_neutral"] == TN and data["inputs"]["source_expression"] == "--expression smile (expression)"
    smile = exprclone.expressions.load("smile")
    assert np.allclose(data["landmarks"]["source_expression"], smile.expression.points, atol=1e-3)
    assert Image.open(out).size == Image.open(TN).size


@pytest.mark.parametrize(
    "args, needle",
    [
        ([SN, SE, TN, "--expression", "smile"], "--expression: give the target's photo alone"),
        ([SN, TN, "--expression", "smile"], "--expression: give the target's photo alone"),
        ([TN], "source_neutral: missing: give the source's neutral and expression photos"),
        ([SN, TN], "source_expression: missing"),
        ([TN, "--expression", "grin"], "--expression: unknown expression 'grin'; the built-in expressions are: angry, sad, smile"),
        ([TN, "--expression", "smile", "--source-neutral-landmarks", "x.json"], "--source-neutral-landmarks: not with --expression"),
    ],
)
def test_a_built_in_expression_with_the_wrong_photos_is_one_line(london, tmp_path, args, needle):
    expect_error(tmp_path, args, needle)


def test_compare_with_a_built_in_expression(london, tmp_path):
    out = tmp_path / "sheet.jpg"
    p = run("compare", TN, "--expression", "smile-126", "-o", out)
    assert p.returncode == 0, p.stderr
    assert Image.open(out).size[0] == 9 * CELL


def test_evaluate_scores_an_expression_only_on_people_it_was_not_made_from(london, tmp_path):
    p = run(
        "evaluate",
        "--data",
        london,
        "--pairs",
        "2",
        "--methods",
        "global",
        "--expression",
        "smile-126",
        "--out",
        tmp_path,
        "--landmarker",
        "mesh",
    )
    assert p.returncode == 0, p.stderr
    rows = list(csv.DictReader(open(tmp_path / "pairs.csv")))
    mine = [r for r in rows if r["method"] == "global [smile-126]"]
    assert sorted(r["target"] for r in mine) == ["001", "003"] and all(r["source"] == "smile-126" for r in mine)
    assert "## Built-in expressions against the individual sources" in (tmp_path / "summary.md").read_text()
    assert (tmp_path / "expressions.jpg").is_file()


def test_evaluate_refuses_an_expression_made_from_everyone(london, tmp_path):
    made = exprclone.expressions.load("smile-126")
    every = write(replace(made, name="everyone", people=("001", "003", "126")), tmp_path)
    p = run("evaluate", "--data", london, "--pairs", "2", "--methods", "global", "--expression", every, "--out", tmp_path / "report")
    assert p.returncode == 2 and "--expression: every person in" in p.stderr and "helped make everyone" in p.stderr


@pytest.mark.parametrize(
    "flag, value, expected",
    [
        ("--max-jobs", "0", "--max-jobs: expected at least 1, got 0"),
        ("--job-ttl", "nan", "--job-ttl: expected at least 1 s, got nan"),
        ("--max-megapixels", "-1", "--max-megapixels: expected at least 0.001 megapixels, got -1"),
        ("--max-live", "-1", "--max-live: expected at least 0, got -1"),
        ("--video-workers", "0", "--video-workers: expected at least 1, got 0"),
        ("--keep-alive", "0", "--keep-alive: expected at least 0.001 s, got 0"),
        ("--workers", "0", "--workers: expected at least 1, got 0"),
    ],
)
def test_serve_refuses_bad_bounds_before_it_starts(flag, value, expected):
    r = run("serve", "--port", "1", flag, value)
    assert r.returncode == 2 and r.stderr.strip() == f"exprclone: error: {expected}" and r.stdout == ""


@pytest.mark.parametrize("words", [("serve",), ("study", "serve", ".")])
def test_serving_without_the_server_packages_says_what_to_install(monkeypatch, words):
    """An install without its dependencies (``pip install --no-deps``) has no FastAPI: the commands that serve say so
    in one line."""
    monkeypatch.setitem(sys.modules, "fastapi", None)  # as if it were not installed
    r = run(*words)
    assert r.returncode == 2 and r.stderr.strip() == (
        "exprclone: error: serve: needs the web server's packages (fastapi is missing): pip install exprclone installs them"
    )


@pytest.mark.parametrize("command", ["clone", "batch"])
def test_an_expression_file_nested_too_deep_is_one_line(tmp_path, command):
    """An ``--expression`` file of 4,000 ``[``: refused before it is parsed, in one line (it was a 31-line traceback)."""
    deep = tmp_path / "deep.json"
    deep.write_text("[" * 4000)
    words = [TN, "-o", tmp_path / "x.png"] if command == "clone" else ["--targets", TN, "--out", tmp_path / "out"]
    p = run(command, *words, "--expression", deep)
    assert p.returncode == 2 and p.stderr.strip() == f"exprclone: error: {deep}: not JSON of this kind: nested 4000 deep (at most 16)", (
        p.stderr
    )


def test_evaluate_on_a_folder_of_ones_own(tmp_path):
    """neutral/NAME.EXT and expression/NAME.EXT (names of any length, PNG and JPEG mixed): scored as the London Set is;
    the report has no table of nan (no strong smile among these targets) and says so, nor a nan where global, the paired
    mouth error's baseline, was not run."""
    folder = tmp_path / "mine"
    for kind, smiling in (("neutral", False), ("expression", True)):
        (folder / kind).mkdir(parents=True)
        for name, person in (("anna", "126"), ("bertrand", "003"), ("chen", "001")):
            image = Image.open((smile_path if smiling else neutral_path)(person))
            image.save(folder / kind / f"{name}.{'png' if name == 'anna' else 'jpg'}")
    out = tmp_path / "report"
    p = run("evaluate", "--data", folder, "--pairs", "2", "--methods", "e+md", "--out", out)  # (no global to pair with either)
    assert p.returncode == 0, p.stderr
    summary = (out / "summary.md").read_text()
    rows = (out / "pairs.csv").read_text().splitlines()
    assert len(rows) == 1 + 2 * 3 and {r.split(",")[0] for r in rows[1:]} <= {"anna", "bertrand", "chen"}
    assert "nan" not in summary and "nan" not in p.stdout and "| e+md |" in summary


def test_evaluate_says_where_it_reads_from_when_the_folder_has_no_people(tmp_path):
    p = run("evaluate", "--data", tmp_path, "--out", tmp_path / "r")
    assert p.returncode == 2 and "neutral/NAME.jpg and expression/NAME.jpg" in p.stderr and len(p.stderr.strip().splitlines()) == 1


# --- the messages of issue 55: each one line, saying what a person can do -------------------------------------------


@pytest.mark.parametrize("words", [("serve",), ("study", "serve", ".")])
@pytest.mark.parametrize("port", ["99999", "0", "-1", "http"])
def test_a_port_out_of_range_is_one_line(words, port):
    """``--port 99999`` ended in the socket's 60-line traceback; now argparse's one line, before anything starts."""
    r = run(*words, "--port", port)
    used = "study serve" if words[0] == "study" else "serve"
    assert r.returncode == 2 and r.stdout == "" and "Traceback" not in r.stderr, r.stderr
    said = f"argument --port: expected a port number from 1 to 65535, got '{port}'; see exprclone {used} --help"
    assert r.stderr.strip() == f"exprclone: error: {said}"


def test_a_photo_too_small_for_a_face_says_so_with_the_least_size(london, tmp_path):
    """A 60x60 photo of a whole face: too small for the landmarker to find it, and said so with the size needed; the same
    photo at 160 pixels is cloned (so the message is about the size, not the face)."""
    from exprclone.pipeline.group import MIN_ACROSS

    whole = Image.open(TN)
    for side in (60, 160):
        whole.resize((side, side), Image.LANCZOS).save(tmp_path / f"{side}.png")
    expect_error(
        tmp_path,
        [tmp_path / "60.png", "--expression", "smile"],
        f"{tmp_path / '60.png'}: too small to find a face in (60x60 pixels; at least {MIN_ACROSS} on each side needed)",
    )
    assert run("clone", tmp_path / "160.png", "--expression", "smile", "-o", tmp_path / "out.png").returncode == 0


@pytest.mark.parametrize(
    "first, second, why",
    [
        (0, 1, "so there is no expression to clone"),
        (0, 2, "so the source's expression goes back onto its own face"),
        (1, 2, "so the target already wears the expression"),
    ],
)
def test_the_same_file_given_as_two_photos_is_warned_of(london, tmp_path, first, second, why):
    roles = ("source_neutral", "source_expression", "target_neutral")
    photos = [SN, SE, TN]
    photos[second] = photos[first]
    r = run("clone", *photos, "-o", tmp_path / "out.png")
    said = f"exprclone: warning: {roles[second]}: the same photo as {roles[first]}, {why}; is one of them the wrong file?"
    assert r.returncode == 0 and r.stderr.strip() == said, r.stderr


def test_three_different_photos_get_no_such_warning(london, tmp_path):
    r = run("clone", SN, SE, TN, "-o", tmp_path / "out.png")
    assert r.returncode == 0 and "the same photo" not in r.stderr, r.stderr


@pytest.mark.parametrize("command, listed", [("video", ".mp4, .mov or .mkv"), ("clone", ".png, .jpg, .jpeg, .bmp, .tif, .tiff or .webp")])
def test_an_unknown_output_type_lists_every_accepted_one(london, grid_clip, tmp_path, command, listed):
    inputs = [TN, grid_clip] if command == "video" else [SN, SE, TN]
    r = run(command, *inputs, "-o", tmp_path / "out.gif")
    assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
    assert f"unknown output format '.gif' (use {listed}" in r.stderr, r.stderr
