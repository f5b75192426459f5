"""Studies for the tests: a manifest of the packaged samples, ``exprclone study make`` and ``study results`` on the command line."""

import csv
import json
import re
from pathlib import Path

from conftest import Completed, command

from exprclone import data as samples
from exprclone.methods import METHODS as ALL_METHODS

#: the methods of the tests' study, and its sets: (set name, source person, target person).
METHODS = ("global", "elastic+eri", "e+md")
SETS = (("Fig. A", "126", "003"), ("Fig. B", "001", "126"))
#: the photos' longest side in the tests' study, pixels (small: the tests are quick).
SIZE = 256
#: any method's name as a word of its own (not "local" in "localStorage"), in any case.
METHOD_NAME = re.compile("|".join(rf"(?<![\w+]){re.escape(m)}(?![\w+])" for m in sorted(ALL_METHODS, key=len, reverse=True)), re.I)


def study(*args) -> Completed:
    """``exprclone study ARGS``, in this process."""
    return command("study", *args)


def manifest(folder: Path, sets=SETS, header: str = "set,source_neutral,source_expression,target_neutral") -> Path:
    """A manifest in ``folder`` of ``sets``: (name, source, target) of sample people, or paths for the target."""
    lines = [header]
    for name, source, target in sets:
        target_path = samples.path(target) if target in samples.PEOPLE else target
        lines.append(",".join([name, str(samples.path(source)), str(samples.path(source, "smile")), str(target_path)]))
    path = folder / "manifest.csv"
    path.write_text("\n".join(lines) + "\n")
    return path


def make(folder: Path, *args, sets=SETS, methods=METHODS) -> Completed:
    """``exprclone study make`` of ``sets`` by ``methods`` into ``folder/study`` (small photos, one process)."""
    path = manifest(folder, sets)
    return study("make", path, "-o", folder / "study", "--methods", ",".join(methods), "--max-size", SIZE, "--jobs", 1, *args)


def key(folder: Path) -> dict[str, tuple[int, str]]:
    """Each result's id to its set and method, from the study's key."""
    sets = json.loads((folder / "key.json").read_text())["sets"]
    return {item: (k, method) for k, s in enumerate(sets) for item, method in s["items"].items()}


def results_csv(folder: Path, out: Path) -> list[dict]:
    """``exprclone study results --csv``'s rows."""
    p = study("results", folder, "--csv", out)
    assert p.returncode == 0, p.stderr
    with open(out, newline="") as f:
        return list(csv.DictReader(f))
