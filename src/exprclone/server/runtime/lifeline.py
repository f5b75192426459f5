"""The server's children and temporary files, tied to its life: a worker process stops when the server stops, however it
stops (SIGKILL too), and a folder left by a server that was killed is removed when the next one starts.

A child (a clone or video worker, a live session's host) watches its parent from a thread of its own
(:func:`watch_parent`) and exits once the parent is gone, whatever its main thread is doing. (Linux's
``PR_SET_PDEATHSIG`` would signal the child when the *thread* that started it ends, not the process: a live session's
host is started from its connection's short-lived thread.) A child stuck in a long C call exits when the call returns
the interpreter lock: within a clone's time at most.

The server's temporary folder (:func:`own_folder`) holds a lock file that the server keeps locked (``flock``) while it
lives; the kernel releases the lock when the process ends, however it ends. A server that starts removes the folders of
its kind, in the same temporary directory, whose lock it can take (:func:`sweep`): those of servers that are gone.
"""

from __future__ import annotations

import fcntl
import os
import shutil
import tempfile
import threading
import time
from pathlib import Path
from typing import IO

from .. import work

#: the start of a server's temporary folder's name.
PREFIX = "exprclone-serve-"
#: the lock file in it, held while its server lives.
LOCK = ".lock"
#: seconds between two looks of a child at its parent.
WATCH_SECONDS = 0.5
#: a child's exit status when its parent is gone.
ORPHANED = 70


def watch_parent(parent: int) -> None:
    """In a child of the process ``parent``: exit (:data:`ORPHANED`) as soon as that process is gone (see the module's notes)."""

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(WATCH_SECONDS)
        os._exit(ORPHANED)

    threading.Thread(target=watch, name="exprclone-lifeline", daemon=True).start()


def start_worker(parent: int) -> None:
    """A worker process's initializer: tied to the server ``parent`` (:func:`watch_parent`), its models loaded."""
    watch_parent(parent)
    work.load_models()


def own_folder() -> tuple[Path, IO[bytes]]:
    """A new temporary folder for this server, and its lock file, locked until the file is closed or the process ends.
    The folders of servers that are gone are swept first (:func:`sweep`)."""
    sweep()
    folder = Path(tempfile.mkdtemp(prefix=PREFIX))
    lock = (folder / f"{LOCK}-new").open("wb")
    fcntl.flock(lock, fcntl.LOCK_EX)
    os.rename(lock.name, folder / LOCK)  # (locked before another server can see it)
    return folder, lock


def sweep(directory: str | None = None) -> list[Path]:
    """Remove the folders of servers that are gone from ``directory`` (the temporary directory by default): each whose
    lock no live process holds. A folder without a lock file (one being made) is left. The folders removed."""
    removed = []
    for folder in Path(directory or tempfile.gettempdir()).glob(f"{PREFIX}*"):
        try:
            with (folder / LOCK).open("rb") as lock:
                fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
                shutil.rmtree(folder, ignore_errors=True)
                removed.append(folder)
        except OSError:  # held by a live server, no lock file, or not ours to open
            continue
    return removed
