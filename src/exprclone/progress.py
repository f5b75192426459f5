"""Progress displays for long jobs (evaluate, video, batch): a one-line text bar redrawn in place, or nothing.

A job takes ``progress(total, what)``, which makes a display with ``update(done, note)``:
:class:`Bar` on the command line, :class:`Quiet` when nobody watches.
"""

from __future__ import annotations

import time
from typing import TextIO

#: characters of the bar itself.
WIDTH = 30


class Bar:
    """``[####......] done/total what note`` on ``stream``, redrawn at most every ``every`` seconds.

    Parameters
    ----------
    stream : text stream or None
        Where to draw (nothing if None).
    total : int
    what : str
        What is counted ("frames", "pairs").
    every : float
        Least time between redraws, in seconds; the last step is always drawn.

    Examples
    --------
    >>> import io
    >>> out = io.StringIO()
    >>> bar = Bar(out, 4, "frames", every=0)
    >>> bar.update(3, "25.0 fps")
    >>> out.getvalue()
    '\\r[######################........] 3/4 frames 25.0 fps'
    """

    def __init__(self, stream: TextIO | None, total: int, what: str, every: float = 0.25) -> None:
        self.stream, self.total, self.what, self.every = stream, total, what, every
        self.start = self._drawn = time.perf_counter()

    @property
    def elapsed(self) -> float:
        """Seconds since the bar was made."""
        return time.perf_counter() - self.start

    def update(self, done: int, note: str = "") -> None:
        """Show that ``done`` of ``total`` are done; a newline once all are."""
        now = time.perf_counter()
        if self.stream is None or (done < self.total and now - self._drawn < self.every):
            return
        self._drawn = now
        filled = int(WIDTH * done / max(self.total, 1))
        self.stream.write(f"\r[{'#' * filled}{'.' * (WIDTH - filled)}] {done}/{self.total} {self.what}" + (f" {note}" if note else ""))
        if done >= self.total:
            self.stream.write("\n")
        self.stream.flush()


class Quiet:
    """A progress display that shows nothing."""

    def __init__(self, total: int = 0, what: str = "") -> None:
        pass

    def update(self, done: int, note: str = "") -> None:
        pass
