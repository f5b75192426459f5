"""Progress of long jobs (evaluate, video, batch): a text bar redrawn in place on a terminal, a line now and then in a log.

A job takes ``progress(total, what)`` (:data:`Progress`), which makes a display with
``update(done, note)``: :class:`Bar` on the command line, :class:`Quiet` when nobody
watches. On a terminal the bar is redrawn in place (a carriage return, at most every
``every`` seconds); written to a file or a pipe, where a carriage return would leave
one line per step in the log, it writes a whole line each time another tenth of the job
is done (:data:`LINES`), or after :data:`LINE_SECONDS` without one, and at the end.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Protocol, TextIO

#: characters of the bar itself.
WIDTH = 30
#: off a terminal, a line each time another 1/LINES of the job is done ...
LINES = 10
#: ... or after this many seconds without a line, whichever comes first.
LINE_SECONDS = 30.0


class Display(Protocol):
    """What a job tells of its progress: ``done`` of the total are done, with an optional note (a rate)."""

    def update(self, done: int, note: str = "") -> None: ...


#: what a job takes to show its progress: ``progress(total, what)`` makes a :class:`Display` of ``total`` things (``what``).
Progress = Callable[[int, str], Display]


class Bar:
    """``[####......] done/total what note`` on ``stream``: redrawn in place on a terminal, a line now and then elsewhere.

    Parameters
    ----------
    stream : text stream or None
        Where to draw (nothing if None).
    total : int
    what : str
        What is counted ("frames", "pairs").
    every : float
        On a terminal, the least time between redraws, in seconds; the last step is always drawn.

    Examples
    --------
    Off a terminal (here a string), a line at each tenth of the job, not one per step:

    >>> import io
    >>> out = io.StringIO()
    >>> bar = Bar(out, 40, "frames")
    >>> for done in range(1, 41):
    ...     bar.update(done, "25.0 fps")
    >>> lines = out.getvalue().splitlines()
    >>> len(lines), "\\r" in out.getvalue(), lines[-1]
    (10, False, '[##############################] 40/40 frames 25.0 fps')
    """

    def __init__(self, stream: TextIO | None, total: int, what: str, every: float = 0.25) -> None:
        self.stream, self.total, self.what, self.every = stream, total, what, every
        self.start = self._drawn = time.perf_counter()
        self.terminal = stream is not None and stream.isatty()
        self._lines = 0

    @property
    def elapsed(self) -> float:
        """Seconds since the bar was made."""
        return time.perf_counter() - self.start

    def update(self, done: int, note: str = "") -> None:
        """Show that ``done`` of ``total`` are done; a newline once all are."""
        if self.stream is None:
            return
        now = time.perf_counter()
        lines = done * LINES // max(self.total, 1)
        if self.terminal:
            due = now - self._drawn >= self.every
        else:
            due = lines > self._lines or now - self._drawn >= LINE_SECONDS
        if not due and done < self.total:
            return
        self._drawn, self._lines = now, lines
        filled = int(WIDTH * done / max(self.total, 1))
        text = f"[{'#' * filled}{'.' * (WIDTH - filled)}] {done}/{self.total} {self.what}" + (f" {note}" if note else "")
        if self.terminal:
            self.stream.write("\r" + text + ("\n" if done >= self.total else ""))
        else:
            self.stream.write(text + "\n")
        self.stream.flush()


class Quiet:
    """A progress display that shows nothing."""

    def __init__(self, total: int = 0, what: str = "") -> None:
        pass

    def update(self, done: int, note: str = "") -> None:
        pass
