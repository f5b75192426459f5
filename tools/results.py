"""The documentation's results pages, generated from ``exprclone evaluate`` and the benchmarks.

    python tools/results.py evaluate [EVALUATE ARGS...]   # runs exprclone evaluate, keeps its report
    python tools/results.py bench NAME [BENCHMARK ARGS...] # runs benchmarks/NAME.py, keeps what it prints
    python tools/results.py render                         # the pages from what was kept

``evaluate`` and ``bench`` run their command (in this interpreter, from the repository's
root), keep its output under ``docs/results/data/`` with what the pages put at their top
(the command, the data, the date, exprclone's version, the machine, how long it took), and
render the pages. ``render`` writes ``docs/results/evaluation.rst``, ``docs/results/speed.rst``
and the figure ``docs/results/data/evaluate/scores.png`` from the kept files alone: the
documentation's build reads them and runs nothing.

Example (the run behind the published pages)::

    python tools/results.py evaluate --data ../shared/data/london --pairs 300 --jobs 2 --global-warps similarity,rbf
    python tools/results.py bench run --repeat 5 --quick
    python tools/results.py bench video --repeat 3
"""

from __future__ import annotations

import argparse
import csv
import datetime
import json
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PAGES = ROOT / "docs" / "results"
KEPT = PAGES / "data"
#: the report files of ``exprclone evaluate`` kept for the pages.
REPORT_FILES = ("pairs.csv", "summary.md", "gallery.jpg")


def _meta(command: list[str], data: str, seconds: float) -> dict:
    """What a results page states at its top about the run that made it."""
    from exprclone import __version__

    return {
        "command": " ".join(command),
        "data": data,
        "date": datetime.date.today().isoformat(),
        "version": __version__,
        "machine": f"{os.cpu_count()} cores, {platform.machine()}, Python {platform.python_version()}",
        "seconds": round(seconds, 1),
    }


def _run(command: list[str], **kwargs) -> tuple[subprocess.CompletedProcess, float]:
    """Run ``command`` from the repository's root with this interpreter's exprclone; stop if it fails."""
    start = time.perf_counter()
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")])}
    done = subprocess.run(command, cwd=ROOT, env=env, text=True, **kwargs)
    if done.returncode:
        sys.exit(f"results: {' '.join(command)} failed with status {done.returncode}")
    return done, time.perf_counter() - start


def _option(args: list[str], name: str, default: str) -> str:
    return args[args.index(name) + 1] if name in args[:-1] else default


def collect_evaluate(args: list[str]) -> None:
    """Run ``exprclone evaluate ARGS`` into a temporary folder; keep its report and the run's facts."""
    with tempfile.TemporaryDirectory() as tmp:
        command = ["exprclone", "evaluate", *args, "--out", tmp]
        _, seconds = _run([sys.executable, "-m", "exprclone", *command[1:]])
        out = KEPT / "evaluate"
        shutil.rmtree(out, ignore_errors=True)
        out.mkdir(parents=True)
        for name in REPORT_FILES:
            if (Path(tmp) / name).exists():
                shutil.copy2(Path(tmp) / name, out / name)
    meta = _meta(["exprclone", "evaluate", *args], _option(args, "--data", "the samples shipped in exprclone.data"), seconds)
    (out / "meta.json").write_text(json.dumps(meta, indent=1) + "\n")


def collect_bench(name: str, args: list[str]) -> None:
    """Run ``benchmarks/NAME.py ARGS``; keep what it prints and the run's facts."""
    script = ROOT / "benchmarks" / f"{name}.py"
    if not script.exists():
        sys.exit(f"results: no benchmark {name!r} in benchmarks/")
    done, seconds = _run([sys.executable, str(script), *args], stdout=subprocess.PIPE)
    out = KEPT / "bench"
    out.mkdir(parents=True, exist_ok=True)
    (out / f"{name}.txt").write_text(done.stdout)
    meta = _meta(["python", f"benchmarks/{name}.py", *args], _option(args, "--data", "../shared/data"), seconds)
    (out / f"{name}.json").write_text(json.dumps(meta, indent=1) + "\n")
