"""The peak memory of a running server's processes (the web process and its workers), read from Linux's /proc.

:func:`peak_growth` resets each process's peak resident size (``clear_refs``), runs a step, and
gives how far the largest peak rose over its process's size before: what that one step cost.
"""

import contextlib
from pathlib import Path


def tree(pid: int) -> list[int]:
    """``pid`` and every process below it."""
    found, todo = [], [pid]
    while todo:
        p = todo.pop()
        found.append(p)
        for task in Path(f"/proc/{p}/task").glob("*"):
            with contextlib.suppress(OSError):
                todo += [int(c) for c in (task / "children").read_text().split()]
    return found


def _status(pid: int, field: str) -> int:
    """A size field of /proc/PID/status (VmRSS, VmHWM), in bytes; 0 for a process that has gone."""
    with contextlib.suppress(OSError):
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith(field + ":"):
                return int(line.split()[1]) * 1024
    return 0


def peak_growth(pid: int, step) -> tuple[int, object]:
    """Run ``step()``; the largest rise of one process's peak resident size over its size before, in bytes, and what step gave."""
    processes = tree(pid)
    before = {}
    for p in processes:
        with contextlib.suppress(OSError):
            Path(f"/proc/{p}/clear_refs").write_text("5")  # the peak (VmHWM) starts again from the current size
        before[p] = _status(p, "VmRSS")
    answer = step()
    return max(_status(p, "VmHWM") - before[p] for p in processes), answer
