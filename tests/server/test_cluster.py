"""``exprclone serve --scheduler``: two servers on one Dask cluster of worker processes share its work and its jobs;
a worker lost during a job fails the job, and the bound on jobs holds across the servers."""

import asyncio
import io
import os
import signal
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor

import dask
import httpx
import numpy as np
import pytest
from PIL import Image
from serving import Server, nginx

import exprclone
from exprclone import data as samples
from exprclone.io.images import load_image
from exprclone.io.inputs import Source
from exprclone.io.video import probe
from exprclone.server.runtime.pools import RETRY_LOST, WorkerLost
from exprclone.server.runtime.shared_jobs import key_of

pytestmark = pytest.mark.slow  # servers, browsers, clusters or videos: pytest -m 'not slow' leaves these out

PHOTOS = {"source_neutral": samples.path("126"), "source_expression": samples.path("126", "smile"), "target_neutral": samples.path("003")}
#: a video job's files: the sample portrait and GRID clip (75 frames).
VIDEO = {"portrait": ("p.jpg", samples.path("003").read_bytes()), "driving_video": ("c.mp4", samples.clip().read_bytes())}
#: the jobs the servers keep at once, together.
MAX_JOBS = 2


@pytest.fixture(scope="module")
def cluster():
    """A Dask cluster of two worker processes, one thread each, on which a task whose worker is lost is not run again
    (Dask's default runs it again, on up to 3 workers in all)."""
    from distributed import Client, LocalCluster

    with dask.config.set({"distributed.scheduler.allowed-failures": 0}):
        with LocalCluster(n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None) as running:
            with Client(running) as client:
                yield running, client


@pytest.fixture(scope="module")
def servers(cluster):
    """Two servers (A and B) on the cluster, as two replicas behind a proxy would be: their URLs."""
    running, _ = cluster
    bounds = ("--max-jobs", str(MAX_JOBS), "--max-jobs-per-client", str(MAX_JOBS))  # (the tests are one client)
    flags = ("--scheduler", running.scheduler_address, *bounds, "--max-live", "0", "--workers", "2")
    started = [Server(*flags)]
    try:
        started.append(Server(*flags))
        yield started[0].url, started[1].url
    finally:
        said = [server.stop() for server in started]
    assert not any("Traceback" in err for _, err in said), said


def follow(url: str, job_id: str, seconds: float = 120) -> dict:
    """A job's state, polled at ``url`` until it ends."""
    deadline = time.time() + seconds
    while time.time() < deadline:
        state = httpx.get(f"{url}/api/jobs/{job_id}", timeout=30).json()
        if state["state"] in ("done", "failed"):
            return state
        time.sleep(0.2)
    raise AssertionError(f"job {job_id} still {state['state']} after {seconds} s")


@pytest.fixture(scope="module")
def done_job(servers):
    """A video job submitted to A, and its state once it is done, as B answers it."""
    a, b = servers
    r = httpx.post(f"{a}/api/video", files=VIDEO, data={"size": "128", "method": "elastic"}, timeout=120)
    assert r.status_code == 202, r.text
    job = r.json()
    return job, follow(b, job["id"])


def kill_worker_running(cluster, part: str, seconds: float = 60) -> None:
    """Kill the worker process that runs a task whose key holds ``part``, as soon as one does (its nanny starts another)."""
    running, client = cluster
    deadline = time.time() + seconds
    while not (at := [w for w, keys in client.processing().items() if any(part in str(key) for key in keys)]):
        assert time.time() < deadline, f"no task {part} ran"
        time.sleep(0.02)
    (pid,) = [nanny.process.process.pid for nanny in running.workers.values() if nanny.worker_address == at[0]]
    os.kill(pid, signal.SIGKILL)


def test_a_clone_through_one_server_is_the_python_apis(servers):
    a, _ = servers
    r = httpx.post(f"{a}/api/clone", files={field: (path.name, path.read_bytes()) for field, path in PHOTOS.items()}, timeout=120)
    assert r.status_code == 200 and r.headers["content-type"] == "image/png", r.text
    expected = exprclone.clone(*[load_image(p) for p in PHOTOS.values()], method="e+md")
    assert np.array_equal(np.asarray(Image.open(io.BytesIO(r.content)).convert("RGB")), expected.image)


def test_a_video_job_submitted_to_one_server_is_fetched_from_the_other(cluster, servers, done_job):
    """And the scheduler (whose names its dashboard and any of its clients see) holds the job under its id's digest,
    never its id: the state and the MP4 are read with the id alone."""
    a, b = servers
    job, state = done_job
    _, client = cluster
    names = [str(name) for name in client.list_datasets()]
    names += [str(key) for key in client.run_on_scheduler(lambda dask_scheduler: list(dask_scheduler.tasks))]
    assert any(key_of(job["id"]) in name for name in names) and not any(job["id"] in name for name in names)
    assert state["state"] == "done" and state["progress"] == 1.0 and state["info"]["frames"] == 75, state
    assert httpx.get(f"{a}/api/jobs/{job['id']}").json() == state  # both answer the same
    r = httpx.get(f"{b}{job['result']}", timeout=60)
    assert r.status_code == 200 and r.headers["content-type"] == "video/mp4"
    with tempfile.NamedTemporaryFile(suffix=".mp4") as out:
        out.write(r.content)
        out.flush()
        assert (probe(out.name).frames, probe(out.name).height) == (75, 128)


def test_a_lost_worker_fails_its_job_and_the_bound_holds_across_servers(cluster, servers, done_job):
    a, b = servers
    r = httpx.post(f"{b}/api/video", files=VIDEO, data={"size": "512", "side_by_side": "true"}, timeout=120)
    assert r.status_code == 202, r.text
    job = r.json()
    refused = httpx.post(f"{a}/api/video", files=VIDEO, timeout=120)  # A counts B's jobs: the one done, this one
    assert refused.status_code == 503 and refused.json()["error"].startswith(f"{MAX_JOBS} video jobs are queued, running or kept")
    assert int(refused.headers["Retry-After"]) > 0
    kill_worker_running(cluster, key_of(job["id"]))
    state = follow(a, job["id"])
    assert state["state"] == "failed" and state["error"] == str(WorkerLost("this job", "1 tries on the cluster")), state
    assert httpx.get(f"{b}{job['result']}").status_code == 409
    again = httpx.post(f"{a}/api/video", files=VIDEO, data={"size": "128", "method": "global"}, timeout=120)
    assert again.status_code == 202, again.text  # the failed job gave its place back


def test_a_lost_worker_fails_its_request_and_the_next_one_is_answered(cluster, servers):
    a, _ = servers
    files = {field: (path.name, path.read_bytes()) for field, path in PHOTOS.items()}
    with ThreadPoolExecutor(1) as pool:
        asked = pool.submit(httpx.post, f"{a}/api/compare", files=files, timeout=120)
        kill_worker_running(cluster, "compare-")
        r = asked.result()
    assert r.status_code == 503 and r.json() == {"error": str(WorkerLost(detail="1 tries on the cluster"))}, r.text
    assert r.headers["Retry-After"] == str(RETRY_LOST)
    assert httpx.post(f"{a}/api/landmarks", files={"photo": files["target_neutral"]}, timeout=120).status_code == 200


def test_every_worker_loads_the_models_once_as_it_joins(cluster, servers):
    """The servers' worker plugin, registered by each, set up once on each worker (and on each that joins later: after
    the tests above, the ones started in place of those killed)."""
    _, client = cluster

    def loaded(dask_worker) -> tuple[bool, int]:
        from exprclone.geometry.eigenface import default_eigenfaces

        return "exprclone-models" in dask_worker.plugins, default_eigenfaces.cache_info().currsize

    assert set(client.run(loaded).values()) == {(True, 1)}


def test_behind_the_shipped_proxy_any_server_answers_a_job_and_one_a_clients_edits_and_editors(servers, done_job, tmp_path):
    job, state = done_job
    with nginx(tmp_path, [int(url.rsplit(":", 1)[1]) for url in servers]) as proxy:
        for _ in range(2):  # the proxy sends them to each server in turn
            assert httpx.get(f"{proxy}{job['status']}", timeout=30).json() == state
            assert httpx.get(f"{proxy}{job['result']}", timeout=60).headers["content-type"] == "video/mp4"
        photos = {field: (path.name, path.read_bytes()) for field, path in PHOTOS.items()}
        made = httpx.post(f"{proxy}/api/edits", files=photos, timeout=120)
        assert made.status_code == 201, made.text
        for strength in ("0.25", "0.5", "0.75", "1.25"):  # each to the server that prepared it
            r = httpx.post(f"{proxy}{made.json()['render']}", data={"strength": strength}, timeout=60)
            assert r.status_code == 200 and r.headers["content-type"] == "image/jpeg", r.text
        photo = PHOTOS["target_neutral"]
        made = httpx.post(f"{proxy}/api/editor", files={"photo": (photo.name, photo.read_bytes())}, timeout=120)
        assert made.status_code == 201, made.text
        for smile in ("0.25", "0.5", "0.75", "1"):  # the expression editor's photo too
            r = httpx.post(f"{proxy}{made.json()['render']}", data={"smile": smile}, timeout=60)
            assert r.status_code == 200 and r.headers["content-type"] == "image/jpeg", r.text


def test_a_job_expires_with_its_names_on_the_scheduler(cluster):
    """A done job is kept ``ttl`` seconds, then removed by the next listing: its dataset and its two Variables."""
    from exprclone.cluster import connect_async
    from exprclone.io.video import Limits
    from exprclone.options import Driving, Framing, Options
    from exprclone.server import work
    from exprclone.server.runtime.shared_jobs import SharedJobs

    running, client = cluster
    limits = Limits(25_000_000, 120)
    portrait = Source("portrait", VIDEO["portrait"][1])
    request = work.VideoRequest(portrait, Options(method="global"), Driving(), Framing(size=128), limits)

    async def scenario() -> tuple[str, dict, dict]:
        remote = await connect_async(running.scheduler_address)
        jobs = SharedJobs(remote, limit=8, ttl=1)
        try:
            job_id = await jobs.submit("a client", request, samples.clip().read_bytes(), work.probe_video(str(samples.clip()), limits))
            while "ended" not in (report := (await jobs.reports())[key_of(job_id)]):
                await asyncio.sleep(0.1)
            await asyncio.sleep(1.5)
            return job_id, report, await jobs.reports()
        finally:
            jobs.close()
            await remote.close()

    job_id, report, after = asyncio.run(scenario())
    assert report["info"]["frames"] == 75 and report["client"] == "a client" and key_of(job_id) not in after
    names = client.run_on_scheduler(lambda dask_scheduler: list(dask_scheduler.extensions["variables"].variables))
    assert not [name for name in [*names, *client.list_datasets()] if key_of(job_id) in str(name)]


def test_a_scheduler_that_cannot_be_reached_is_one_line():
    p = subprocess.run([sys.executable, "-m", "exprclone", "serve", "--scheduler", "no-port-here"], capture_output=True, text=True)
    assert p.returncode == 2 and p.stderr.startswith("exprclone: error: --scheduler: cannot reach a Dask scheduler at no-port-here")
    assert len(p.stderr.strip().splitlines()) == 1
