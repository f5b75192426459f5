"""exprclone batch on the sample photos: outputs, the report, bad rows, resuming, each photo detected once, Dask."""

import csv
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from conftest import command
from PIL import Image
from serving import interruptible

import exprclone
from exprclone import data as samples
from exprclone import expressions
from exprclone.batch import job
from exprclone.batch.manifest import read_manifest
from exprclone.io.images import load_image
from exprclone.landmarks import backends
from exprclone.options import Options
from exprclone.pipeline import clone

pytestmark = pytest.mark.slow  # servers, browsers, clusters or videos: pytest -m 'not slow' leaves these out

HEADER = "source_neutral,source_expression,target_neutral,output"


def run(*args, cwd=None):
    return command("batch", *args, cwd=cwd)


def manifest(folder: Path, rows: list[tuple], extra: str = "") -> Path:
    """A manifest in ``folder`` whose rows are (source, target, output[, method]) of sample people (or paths)."""
    lines = [HEADER + extra]
    for row in rows:
        source, target, output, *rest = row
        photos = [samples.path(source), samples.path(source, "smile"), samples.path(target) if len(target) == 3 else target]
        lines.append(",".join([*map(str, photos), output, *rest]))
    path = folder / "manifest.csv"
    path.write_text("\n".join(lines) + "\n")
    return path


def report(folder: Path) -> list[dict]:
    with open(folder / "report.csv", newline="") as f:
        return list(csv.DictReader(f))


def pixels(path) -> np.ndarray:
    return np.asarray(Image.open(path).convert("RGB"))


@pytest.fixture()
def blank(tmp_path) -> Path:
    path = tmp_path / "blank.png"
    Image.fromarray(np.full((300, 300, 3), 128, np.uint8)).save(path)
    return path


def test_a_manifest_with_bad_rows_is_done_and_reported(tmp_path, blank):
    rows = [
        ("126", "003", "a.png"),
        ("126", "001", "b.png", "global"),
        ("126", str(tmp_path / "gone.jpg"), "c.png"),
        ("126", str(blank), "d.png"),
    ]
    rows.append(("001", "003", "e.png", "warp"))
    p = run(manifest(tmp_path, rows, ",method"), "--jobs", "2")
    assert p.returncode == 1, p.stderr
    last = p.stdout.strip().splitlines()[-1]
    assert "5 rows: 2 done, 0 skipped" in last and "3 failed" in last and str(tmp_path / "report.csv") in last
    status = {r["output"]: (r["status"], r["error"]) for r in report(tmp_path)}
    assert status[str(tmp_path / "a.png")] == ("done", "")
    assert status[str(tmp_path / "c.png")][1].startswith(f"{tmp_path / 'gone.jpg'}: no such file")
    assert status[str(tmp_path / "d.png")][1].startswith(f"{blank}: no face found")
    assert status[str(tmp_path / "e.png")][1].startswith("method: unknown method 'warp'")
    images = [load_image(samples.path("126")), load_image(samples.path("126", "smile"))]
    expected = exprclone.clone(*images, load_image(samples.path("001")), method="global")
    assert np.array_equal(pixels(tmp_path / "b.png"), expected.image)  # the row's own method, as the Python API makes it
    assert sorted(os.listdir(tmp_path)) == ["a.png", "b.png", "blank.png", "manifest.csv", "report.csv"]


@pytest.mark.parametrize(
    "content, message",
    [
        ("source_neutral,target_neutral,output\na,b,c\n", "the manifest has no column source_expression"),
        (f"{HEADER}\na.jpg,b.jpg,c.jpg,out.png\nd.jpg,e.jpg,f.jpg,out.png\n", "rows 1 and 2 both write"),
        (f"{HEADER}\na.jpg,b.jpg,c.jpg,a.jpg\n", "row 1 would overwrite an input"),
        (f"{HEADER}\na.jpg,b.jpg,c.jpg,../escaped.png\n", "row 1's output '../escaped.png' is outside the output folder"),
        (f"{HEADER}\na.jpg,b.jpg,c.jpg,out.gif\n", "row 1's output 'out.gif' is no image file"),
    ],
)
def test_an_unusable_manifest_stops_before_any_work(tmp_path, content, message):
    (tmp_path / "m.csv").write_text(content)
    p = run(tmp_path / "m.csv")
    assert p.returncode == 2 and message in p.stderr and len(p.stderr.strip().splitlines()) == 1, p.stderr
    assert sorted(os.listdir(tmp_path)) == ["m.csv"]


def test_rows_done_are_skipped_and_overwrite_redoes_them(tmp_path):
    path = manifest(tmp_path, [("126", "003", "a.png"), ("126", "001", "b.png")])
    assert run(path, "--jobs", "1").returncode == 0
    first = (tmp_path / "a.png").stat().st_mtime_ns
    p = run(path, "--jobs", "1")
    assert p.returncode == 0 and "0 done, 2 skipped" in p.stdout
    assert {r["status"] for r in report(tmp_path)} == {"skipped"} and (tmp_path / "a.png").stat().st_mtime_ns == first
    p = run(path, "--jobs", "1", "--overwrite")
    assert "2 done, 0 skipped" in p.stdout


def test_one_expression_on_a_folder_of_portraits(tmp_path):
    p = run(
        "--source-neutral",
        samples.path("126"),
        "--source-expression",
        samples.path("126", "smile"),
        "--targets",
        str(samples.london() / "neutral_front" / "*.jpg"),
        "--out",
        tmp_path / "out",
    )
    assert p.returncode == 0, p.stderr
    assert sorted(os.listdir(tmp_path / "out")) == ["001_03.png", "003_03.png", "126_03.png", "report.csv"]


def test_the_transfer_options_reach_every_row(tmp_path):
    path = manifest(tmp_path, [("126", "003", "a.png"), ("126", "001", "b.png")])
    p = run(path, "--jobs", "1", "--method", "global", "--global-warp", "rbf", "--strength", "0.5", "--only", "mouth", "--no-retarget")
    assert p.returncode == 0, p.stderr
    source = [load_image(samples.path("126")), load_image(samples.path("126", "smile"))]
    for name, target in (("a.png", "003"), ("b.png", "001")):
        target_photo = load_image(samples.path(target))
        options = dict(global_warp="rbf", strength=0.5, only="mouth", retarget=False)
        expected = exprclone.clone(*source, target_photo, method="global", **options)
        plain = exprclone.clone(*source, target_photo, method="global")
        assert np.array_equal(pixels(tmp_path / name), expected.image) and not np.array_equal(expected.image, plain.image)
    p = run(path, "--strength", "3")
    assert p.returncode == 2 and "--strength" in p.stderr and "from 0 to 2" in p.stderr


class Counting:
    """Counts calls of a method of a class while it is patched in."""

    def __init__(self, monkeypatch, owner, name):
        self.calls = 0
        original = getattr(owner, name)

        def counted(*args, **kwargs):
            self.calls += 1
            return original(*args, **kwargs)

        monkeypatch.setattr(owner, name, counted)


def test_each_photo_is_detected_once_and_each_pair_of_faces_prepared_once(tmp_path, monkeypatch):
    """Six rows: one source, its expression (the same content under a second name too), two targets."""
    copy = tmp_path / "smile copy.jpg"
    copy.write_bytes(samples.path("126", "smile").read_bytes())
    rows = [("126", "003", f"{k}.png") for k in range(3)] + [("126", "001", f"{k + 3}.png") for k in range(3)]
    path = manifest(tmp_path, rows)
    path.write_text(path.read_text().replace(str(samples.path("126", "smile")), str(copy), 1))
    detections = Counting(monkeypatch, type(backends.default_detector()), "detect")
    preparations = Counting(monkeypatch, clone.Cloner, "__init__")
    outcomes = {}
    job.run(read_manifest(str(path)), Options(method="global"), job.Local(1), outcomes, cache=tmp_path / "cache")
    assert [outcomes[k].status for k in range(1, 7)] == ["done"] * 6
    assert detections.calls == 4  # source neutral, its smile (one content, two names), two targets
    assert preparations.calls == 2  # one Cloner per (source neutral, target)
    outcomes = {}
    job.run(read_manifest(str(path)), Options(method="global"), job.Local(1), outcomes, overwrite=True, cache=tmp_path / "cache")
    assert detections.calls == 4  # the cache kept them


def test_ctrl_c_leaves_whole_outputs_and_the_next_run_finishes(tmp_path):
    # 8 tasks of 4 rows: 2 workers hold at most 3 of them when Ctrl-C comes, so some rows are never started
    rows = [("126", target, f"{k}-{target}.png") for k in range(16) for target in ("003", "001")]
    path = manifest(tmp_path, rows)
    command = [sys.executable, "-m", "exprclone", "batch", str(path), "--jobs", "2"]
    process = subprocess.Popen(command, stderr=subprocess.PIPE, text=True, preexec_fn=interruptible)
    deadline = time.time() + 120
    while time.time() < deadline and not any(p.suffix == ".png" and not p.name.startswith(".") for p in tmp_path.iterdir()):
        time.sleep(0.05)
    process.send_signal(signal.SIGINT)
    _, err = process.communicate(timeout=120)
    assert process.returncode == 130 and "interrupted" in err, err
    finished = [p for p in tmp_path.iterdir() if p.suffix == ".png"]
    assert 1 <= len(finished) < len(rows) and not any(p.name.startswith(".") for p in tmp_path.iterdir())  # no temporary file left
    for p in finished:
        assert pixels(p).shape == (1350, 1350, 3)  # whole
    again = run(path, "--jobs", "2")
    assert again.returncode == 0 and f"{len(rows) - len(finished)} done, {len(finished)} skipped" in again.stdout, again.stdout


def test_dask_cluster_gives_the_same_outputs(tmp_path):
    from distributed import LocalCluster

    rows = [("126", "003", "a.png"), ("001", "126", "b.png"), ("126", str(tmp_path / "gone.jpg"), "c.png")]
    local, remote = tmp_path / "local", tmp_path / "dask"
    for folder in (local, remote):
        folder.mkdir()
        manifest(folder, rows)
    assert run(local / "manifest.csv", "--jobs", "1").returncode == 1
    with LocalCluster(n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None) as cluster:
        p = run(remote / "manifest.csv", "--scheduler", cluster.scheduler_address)
    assert p.returncode == 1 and "2 done, 0 skipped (output already there), 1 failed" in p.stdout, p.stdout + p.stderr
    for name in ("a.png", "b.png"):
        assert np.array_equal(pixels(local / name), pixels(remote / name))
    assert [r["status"] for r in report(remote)] == ["done", "done", "failed"]


def test_a_scheduler_that_cannot_be_reached_is_one_line(tmp_path):
    p = run(manifest(tmp_path, [("126", "003", "a.png")]), "--scheduler", "no-port-here")
    assert p.returncode == 2 and p.stderr.startswith("exprclone: error: --scheduler: cannot reach a Dask scheduler at no-port-here")
    assert len(p.stderr.strip().splitlines()) == 1


def test_a_built_in_expression_on_a_folder_of_portraits(tmp_path):
    """With --expression the expression's own landmarks are used (a composite's are not detected): the Python API's image."""
    p = run("--expression", "smile", "--targets", samples.london() / "neutral_front" / "003_03.jpg", "--out", tmp_path, "--strength", "0.8")
    assert p.returncode == 0, p.stderr
    assert report(tmp_path)[0]["source_expression"] == str(samples.folder().resolve() / "expressions" / "smile-expression.jpg")
    expected = expressions.clone(load_image(samples.path("003")), "smile", strength=0.8)
    assert np.array_equal(pixels(tmp_path / "003_03.png"), expected.image)


@pytest.mark.parametrize(
    "args, message",
    [
        (["--expression", "smile"], "--expression: goes with --targets"),
        (["--expression", "smile", "--targets", "x", "--source-neutral", "a.jpg"], "--expression: goes with --targets, instead of"),
        (["--expression", "grin", "--targets", "x", "--out", "o"], "--expression: unknown expression 'grin'"),
    ],
)
def test_a_built_in_expression_in_the_wrong_company_is_one_line(tmp_path, args, message):
    p = run(*args, cwd=tmp_path)
    assert p.returncode == 2 and p.stderr.startswith(f"exprclone: error: {message}") and len(p.stderr.strip().splitlines()) == 1


def test_rows_whose_source_photos_look_swapped_are_warned_in_the_report(tmp_path):
    """The role check clone makes (exprclone.pipeline.role_check) on each row: the clone is made, the report says what looked wrong."""
    swapped = [samples.path("126", "smile"), samples.path("126"), samples.path("003"), "swapped.png"]
    right = [samples.path("126"), samples.path("126", "smile"), samples.path("003"), "right.png"]
    path = tmp_path / "manifest.csv"
    path.write_text("\n".join([HEADER, ",".join(map(str, swapped)), ",".join(map(str, right))]) + "\n")
    p = run(path, "--method", "global")
    assert p.returncode == 0, p.stderr
    assert "exprclone: warning: 1 rows' source photos look wrong (swapped, or two people): see the report" in p.stderr
    warned = {Path(r["output"]).name: (r["status"], r["warnings"]) for r in report(tmp_path)}
    assert warned["right.png"] == ("done", "")
    assert warned["swapped.png"][0] == "done" and "are the source's two photos swapped?" in warned["swapped.png"][1]
    assert (tmp_path / "swapped.png").exists()


def test_the_report_names_the_paths_given_not_where_their_links_lead(tmp_path):
    """Photos reached through a link (a folder of links to a shared data set) are reported by the paths the manifest
    gives, made absolute, not by the files the links lead to."""
    links = tmp_path / "photos"
    links.mkdir()
    for name, path in (("sn.jpg", samples.path("126")), ("se.jpg", samples.path("126", "smile")), ("tn.jpg", samples.path("003"))):
        (links / name).symlink_to(path)
    (tmp_path / "manifest.csv").write_text(f"{HEADER}\nphotos/sn.jpg,photos/se.jpg,photos/tn.jpg,sub/../a.png\n")
    p = run(tmp_path / "manifest.csv", "--method", "global")
    assert p.returncode == 0, p.stderr
    (row,) = report(tmp_path)
    assert [row[r] for r in ("source_neutral", "source_expression", "target_neutral")] == [
        str(links / n) for n in ("sn.jpg", "se.jpg", "tn.jpg")
    ]
    assert row["output"] == str(tmp_path / "a.png") and (tmp_path / "a.png").is_file()


def test_a_group_photo_in_a_manifest_has_the_faces_of_its_row_cloned(tmp_path):
    """Every face of a group target, or those of the row's own ``faces`` cell; a portrait's ``faces`` asking for a
    second face fails its row alone."""
    from exprclone.evaluation.groups import make
    from exprclone.io.images import save_image

    image, _ = make(samples.london(), samples.PEOPLE, (110, 170, 250), (760, 800), seed=4)
    save_image(tmp_path / "group.png", image)
    rows = [
        ("126", str(tmp_path / "group.png"), "all.png", ""),
        ("126", str(tmp_path / "group.png"), "two.png", "2"),
        ("126", "003", "x.png", "2"),
    ]
    p = run(manifest(tmp_path, rows, ",faces"), "--jobs", "1", "--cache", tmp_path / "cache")
    assert p.returncode == 1, p.stderr
    assert [r["status"] for r in report(tmp_path)] == ["done", "done", "failed"], report(tmp_path)
    assert report(tmp_path)[2]["error"].endswith("faces: no face 2: the photo shows 1 face (exprclone faces numbers them)")
    sources = (load_image(samples.path("126")), load_image(samples.path("126", "smile")))
    for name, faces in (("all.png", "all"), ("two.png", (2,))):
        assert np.array_equal(pixels(tmp_path / name), exprclone.clone(*sources, image, faces=faces).image)
