"""Progress bars (exprclone.io.progress): redrawn in place on a terminal, a few whole lines in a file or a pipe."""

import io
import subprocess
import sys

from exprclone import data as samples
from exprclone.io.progress import LINES, Bar


class Terminal(io.StringIO):
    """A text stream that says it is a terminal."""

    def isatty(self) -> bool:
        return True


def test_off_a_terminal_a_long_job_writes_a_line_a_tenth_not_a_carriage_return_a_step():
    out = io.StringIO()
    bar = Bar(out, 1000, "pairs")
    for done in range(1, 1001):
        bar.update(done, "0.1 s each")
    lines = out.getvalue().splitlines()
    assert "\r" not in out.getvalue() and len(lines) == LINES
    assert [line.split()[1] for line in lines] == [f"{100 * k}/1000" for k in range(1, LINES + 1)]


def test_on_a_terminal_the_bar_is_redrawn_in_place_and_ends_its_line():
    out = Terminal()
    bar = Bar(out, 5, "frames", every=0)
    for done in range(1, 6):
        bar.update(done)
    assert out.getvalue().count("\r") == 5 and out.getvalue().endswith("5/5 frames\n") and out.getvalue().count("\n") == 1


def test_a_video_written_with_its_progress_to_a_file_logs_a_few_lines(tmp_path):
    """``exprclone video`` with stderr to a file: the 75 frames' progress in at most LINES lines, no carriage return."""
    log = tmp_path / "stderr.txt"
    portrait, clip = samples.path(samples.TARGET), samples.clip()
    command = [sys.executable, "-m", "exprclone", "video", str(portrait), str(clip), "-o", str(tmp_path / "out.mp4")]
    with open(log, "w") as stderr:
        subprocess.run(command + ["--size", "128", "--method", "global", "--no-mouth"], stderr=stderr, check=True)
    text = log.read_text()
    frames = [line for line in text.splitlines() if " frames" in line and line.startswith("[")]
    assert "\r" not in text and 1 <= len(frames) <= LINES and frames[-1].split()[1] == "75/75"
