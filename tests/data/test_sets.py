"""The full data sets' folder as the tools and benchmarks take it (:mod:`exprclone.data.sets`)."""

import argparse
from pathlib import Path

import pytest

from exprclone.data import sets


def test_the_folder_is_the_environments_else_beside_the_checkout(monkeypatch, tmp_path):
    monkeypatch.setenv("EXPRCLONE_DATA", str(tmp_path))
    assert sets.default("london") == tmp_path / "london"
    monkeypatch.delenv("EXPRCLONE_DATA")
    assert sets.default() == Path(__file__).resolve().parents[3] / "shared" / "data"  # where the tests find them


def test_data_that_is_no_folder_is_refused_in_one_line(tmp_path):
    parser = argparse.ArgumentParser()
    sets.add_argument(parser, "london")
    assert parser.parse_args(["--data", str(tmp_path)]).data == tmp_path
    with pytest.raises(argparse.ArgumentTypeError, match="no such folder"):
        sets.folder(str(tmp_path / "missing"))
