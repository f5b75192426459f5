"""A plain ``exprclone serve`` under faults (issue 53): a video worker killed during a job, every worker killed during a
request, the server itself killed with SIGKILL. After each, the next valid request is served (the pools heal), the
readiness probe tells the truth meanwhile, and nothing is left behind: no process, no temporary folder (a killed
server's is swept by the next one). The cluster's faults are in ``test_cluster_faults.py``."""

import os
import signal
import time
from concurrent.futures import ThreadPoolExecutor

import httpx
import psutil
import pytest
from serving import Server

from exprclone import data as samples
from exprclone.server.runtime.lifeline import PREFIX
from exprclone.server.runtime.pools import WorkerLost

pytestmark = pytest.mark.slow  # servers, browsers, clusters or videos: pytest -m 'not slow' leaves these out

PHOTOS = {"source_neutral": samples.path("126"), "source_expression": samples.path("126", "smile"), "target_neutral": samples.path("003")}
VIDEO = {"portrait": ("p.jpg", samples.path("003").read_bytes()), "driving_video": ("c.mp4", samples.clip().read_bytes())}
#: seconds within which a fault must be healed: a new worker started, its models loaded, on a busy machine.
HEALED = 60


def workers(pid: int) -> list[psutil.Process]:
    """The server's worker processes (clone, video, live): its children started by multiprocessing's spawn."""
    return [p for p in psutil.Process(pid).children() if "spawn_main" in " ".join(p.cmdline())]


def gone(processes: list[psutil.Process], seconds: float) -> bool:
    """Whether every process of ``processes`` has ended within ``seconds`` (a zombie has ended: only its entry is left)."""
    deadline = time.time() + seconds
    while time.time() < deadline:
        if not [p for p in processes if p.is_running() and p.status() != psutil.STATUS_ZOMBIE]:
            return True
        time.sleep(0.1)
    return False


def until(condition, seconds: float = HEALED, every: float = 0.1):
    """``condition()`` once it is true, polled for at most ``seconds``."""
    deadline = time.time() + seconds
    while not (found := condition()):
        assert time.time() < deadline, f"not within {seconds} s"
        time.sleep(every)
    return found


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    """A server with one clone worker and one video worker, in a temporary directory of its own; at the end, stopped by
    Ctrl-C, it leaves no process, no folder and no traceback."""
    folder = tmp_path_factory.mktemp("tmp")
    running = Server("--workers", "1", "--max-live", "0", "--max-jobs-per-client", "4", env={"TMPDIR": str(folder)})
    yield running
    children = psutil.Process(running.process.pid).children(recursive=True)
    _, err = running.stop()
    assert gone(children, 10) and not list(folder.glob(f"{PREFIX}*")) and "Traceback" not in err, err[-3000:]


def test_a_video_worker_killed_fails_its_job_alone_and_the_next_job_runs(server):
    """The worker dies (as the out-of-memory killer would end it) while it renders a job; the job queued behind it was
    waiting, not running: it runs on the worker started in the dead one's place."""
    with httpx.Client(base_url=server.url, timeout=120) as client:
        first, second = (client.post("/api/video", files=VIDEO, data={"size": "256"}).json() for _ in range(2))
        until(lambda: client.get(first["status"]).json()["state"] == "running")
        (running,) = [p for p in workers(server.process.pid) if any(first["id"] in f.path for f in p.open_files())]
        running.send_signal(signal.SIGKILL)
        failed = until(lambda: (s := client.get(first["status"]).json())["state"] in ("failed", "done") and s)
        assert failed["state"] == "failed" and failed["error"] == str(WorkerLost("this job")), failed
        assert client.get(first["result"]).status_code == 409
        done = until(lambda: (s := client.get(second["status"]).json())["state"] in ("failed", "done") and s)
        assert done["state"] == "done" and done["info"]["frames"] == 75, done
        assert until(lambda: client.get("/api/health/ready").status_code == 200)


def test_every_worker_killed_fails_the_request_at_work_and_the_next_is_served(server):
    """Every worker killed while one runs a compare sheet: that request alone is answered 503 (try again), the readiness
    probe says no clone worker is ready until one is, and the next request is served by the workers started again."""
    files = {field: (path.name, path.read_bytes()) for field, path in PHOTOS.items()}
    pid = server.process.pid
    with ThreadPoolExecutor(1) as pool:
        before = {p.pid: p.cpu_times().user for p in workers(pid)}
        asked = pool.submit(httpx.post, f"{server.url}/api/compare", files=files, timeout=120)
        until(lambda: any(p.cpu_times().user > before.get(p.pid, 0) + 0.3 for p in workers(pid)), every=0.02)  # at work
        killed = workers(pid)
        for process in killed:
            process.send_signal(signal.SIGKILL)
        r = asked.result()
    assert r.status_code == 503 and r.json() == {"error": str(WorkerLost())} and r.headers["Retry-After"] == str(WorkerLost().retry_after)
    assert gone(killed, 10)
    ready = httpx.get(f"{server.url}/api/health/ready")
    assert ready.status_code == 200 or (ready.status_code == 503 and "no clone worker is ready" in ready.json()["error"]), ready.text
    again = httpx.post(f"{server.url}/api/landmarks", files={"photo": files["target_neutral"]}, timeout=HEALED)
    assert again.status_code == 200, again.text
    assert until(lambda: httpx.get(f"{server.url}/api/health/ready").status_code == 200)


def test_a_server_killed_leaves_no_process_and_its_folder_is_swept_at_the_next_start(tmp_path):
    """SIGKILL gives the server no time to stop anything: its workers and live host see it gone and end, and the next
    server started with the same temporary directory removes the folder it left."""
    killed = Server("--workers", "1", "--max-live", "1", env={"TMPDIR": str(tmp_path)})
    children = psutil.Process(killed.process.pid).children(recursive=True)
    (left,) = tmp_path.glob(f"{PREFIX}*")
    assert len(workers(killed.process.pid)) == 2  # a clone worker and a live session's host
    os.kill(killed.process.pid, signal.SIGKILL)
    killed.process.wait()
    killed.stop()
    assert gone(children, 15), [(p.pid, p.cmdline()) for p in children if p.is_running()]
    assert left.exists()
    again = Server("--workers", "1", "--max-live", "0", env={"TMPDIR": str(tmp_path)})
    try:
        assert not left.exists() and len(list(tmp_path.glob(f"{PREFIX}*"))) == 1
    finally:
        again.stop()
    assert not list(tmp_path.glob(f"{PREFIX}*"))
