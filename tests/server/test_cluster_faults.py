"""The cluster's door and its faults (issue 53): a Dask scheduler and worker started with TLS certificates made by the
recipe the documentation ships (``deploy/certificates.sh``), and a replica (``exprclone serve --scheduler tls://...``)
on them. A client without a certificate of the cluster's authority cannot connect; the replica serves. Every worker
lost, then the scheduler lost and started again (with a worker, as an orchestrator would): meanwhile the replica
answers each request 503 saying why, within a bounded time, and its readiness probe says it; then it serves again.
Nothing is left behind: the replica stops with no process of its own left."""

import contextlib
import os
import signal
import socket
import ssl
import subprocess
import sys
import time
from pathlib import Path

import httpx
import psutil
import pytest
from serving import Server, free_port

from exprclone import data as samples

pytestmark = pytest.mark.slow  # servers, browsers, clusters or videos: pytest -m 'not slow' leaves these out

#: the recipe of docs/howto/deploy.rst, as shipped.
RECIPE = Path(__file__).resolve().parents[2] / "deploy" / "certificates.sh"
#: the replica's --worker-wait.
WORKER_WAIT = 3
#: seconds within which the cluster's faults are healed (a worker started, its models loaded, the replica reconnected).
HEALED = 90
PHOTO = {"photo": ("p.jpg", samples.path("003").read_bytes())}


def make_certificates(folder: Path) -> Path:
    """The recipe run into ``folder`` (with the openssl command alone, as on a fresh machine)."""
    subprocess.run(["sh", str(RECIPE), str(folder)], check=True, capture_output=True)
    return folder


class Cluster:
    """A Dask scheduler on a free port of 127.0.0.1 and its workers, each a ``dask`` command started as the docs start
    it, with TLS, in a process group of its own (stopped by that group: its nanny and worker processes with it)."""

    def __init__(self, certificates: Path, logs: Path) -> None:
        self.certificates, self.logs = certificates, logs
        self.port = free_port()
        self.address = f"tls://127.0.0.1:{self.port}"
        self.started: list[subprocess.Popen] = []

    def _dask(self, role: str, *args: str) -> subprocess.Popen:
        c = self.certificates
        tls = ("--tls-ca-file", str(c / "ca.pem"), "--tls-cert", str(c / f"{role}.pem"), "--tls-key", str(c / f"{role}.key"))
        log = (self.logs / f"{role}-{len(self.started)}.log").open("w")
        command = [sys.executable, "-m", "dask", role, *args, "--no-dashboard", *tls]
        self.started.append(subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT, start_new_session=True))
        return self.started[-1]

    def start_scheduler(self) -> subprocess.Popen:
        process = self._dask("scheduler", "--protocol", "tls", "--host", "127.0.0.1", "--port", str(self.port))
        deadline = time.time() + 60
        while True:  # its port open
            try:
                socket.create_connection(("127.0.0.1", self.port), timeout=1).close()
                return process
            except OSError:
                assert time.time() < deadline and process.poll() is None, "the scheduler did not start"
                time.sleep(0.1)

    def start_worker(self) -> subprocess.Popen:
        return self._dask("worker", self.address, "--nworkers", "1", "--nthreads", "1")

    @staticmethod
    def kill(process: subprocess.Popen) -> None:
        """SIGKILL to the command's process group (its own, made at its start), as a machine that dies would end it."""
        with contextlib.suppress(ProcessLookupError):  # (none of the group is left)
            os.killpg(process.pid, signal.SIGKILL)
        process.wait()

    def stop(self) -> None:
        for process in self.started:
            self.kill(process)


@pytest.fixture(scope="module")
def certificates(tmp_path_factory):
    return make_certificates(tmp_path_factory.mktemp("certificates"))


@pytest.fixture(scope="module")
def cluster(certificates, tmp_path_factory):
    running = Cluster(certificates, tmp_path_factory.mktemp("dask"))
    try:
        running.scheduler = running.start_scheduler()
        running.worker = running.start_worker()
        yield running
    finally:
        running.stop()


@pytest.fixture(scope="module")
def replica(cluster, certificates):
    """``exprclone serve`` on the cluster with the replica's certificate; ready once the worker has joined. At the end,
    no process of its own is left and its log holds no traceback."""
    c = certificates
    tls = ("--tls-ca-file", str(c / "ca.pem"), "--tls-cert", str(c / "replica.pem"), "--tls-key", str(c / "replica.key"))
    running = Server("--scheduler", cluster.address, *tls, "--worker-wait", str(WORKER_WAIT), "--workers", "1", "--max-live", "0")
    try:
        ready(running.url)
        yield running.url
    finally:
        children = psutil.Process(running.process.pid).children(recursive=True)
        _, err = running.stop()
    assert not [p for p in children if p.is_running() and p.status() != psutil.STATUS_ZOMBIE]
    assert "Traceback" not in err, err[-3000:]


def ready(url: str, seconds: float = HEALED) -> None:
    """Wait for the replica's readiness probe to say ready."""
    deadline = time.time() + seconds
    while (answer := httpx.get(f"{url}/api/health/ready", timeout=10)).status_code != 200:
        assert time.time() < deadline, answer.text
        time.sleep(0.2)


def refused(answer: httpx.Response, said: str) -> None:
    """A 503 that says why (``said``), and when to come back."""
    assert answer.status_code == 503 and said in answer.json()["error"], answer.text
    assert int(answer.headers["Retry-After"]) >= 1


def test_a_client_without_a_certificate_of_the_clusters_authority_cannot_connect(cluster, certificates, tmp_path):
    from distributed import Client
    from distributed.security import Security

    def security(folder: Path) -> Security:
        return Security(tls_ca_file=str(certificates / "ca.pem"), tls_client_cert=str(folder / "replica.pem"),
                        tls_client_key=str(folder / "replica.key"), require_encryption=True)  # fmt: skip

    with pytest.raises((OSError, TypeError)):  # no certificate: Dask will not even try TLS without one
        Client(cluster.address, timeout=5)
    with pytest.raises(OSError):  # plain TCP to the TLS port
        Client(cluster.address.replace("tls://", "tcp://"), timeout=5)
    with pytest.raises(OSError):  # a certificate of another authority (the recipe run again elsewhere)
        Client(cluster.address, security=security(make_certificates(tmp_path / "other")), timeout=5)
    context = ssl.create_default_context(cafile=str(certificates / "ca.pem"))  # TLS with the CA, but no certificate of its own
    context.check_hostname = False
    with pytest.raises((ssl.SSLError, ConnectionError)):
        with context.wrap_socket(socket.create_connection(("127.0.0.1", cluster.port), timeout=10)) as tls:
            tls.sendall(b"\0" * 8)
            assert tls.recv(1), "the scheduler answered a client without a certificate"
    with Client(cluster.address, security=security(certificates), timeout=10) as client:  # the replica's: let in
        assert client.submit(sum, [1, 2]).result() == 3


def test_the_replica_serves_over_tls(replica):
    r = httpx.post(f"{replica}/api/landmarks", files=PHOTO, timeout=60)
    assert r.status_code == 200 and len(r.json()["landmarks"]) == 68, r.text


def test_every_worker_lost_a_request_waits_a_bounded_time_then_is_told_why(cluster, replica):
    cluster.kill(cluster.worker)
    start = time.time()
    refused(httpx.post(f"{replica}/api/landmarks", files=PHOTO, timeout=60), "the cluster has no worker")
    assert WORKER_WAIT <= time.time() - start < WORKER_WAIT + 10
    refused(httpx.get(f"{replica}/api/health/ready"), "not ready: the cluster has no worker")
    cluster.worker = cluster.start_worker()
    ready(replica)
    assert httpx.post(f"{replica}/api/landmarks", files=PHOTO, timeout=60).status_code == 200


def test_the_scheduler_lost_then_started_again(cluster, replica):
    """The scheduler killed: every request is answered 503 at once, saying the scheduler is lost; started again on its
    address (with a worker: the old one ended with the scheduler), the replica joins it and serves."""
    cluster.kill(cluster.scheduler)
    deadline = time.time() + 10
    while (answer := httpx.post(f"{replica}/api/landmarks", files=PHOTO, timeout=30)).status_code == 200:
        assert time.time() < deadline, "the replica did not see its scheduler go"
        time.sleep(0.2)
    refused(answer, "the server lost its cluster's scheduler")
    refused(httpx.get(f"{replica}/api/health/ready"), "not ready: the server lost its cluster's scheduler")
    cluster.scheduler = cluster.start_scheduler()
    cluster.worker = cluster.start_worker()
    ready(replica)
    assert httpx.post(f"{replica}/api/landmarks", files=PHOTO, timeout=60).status_code == 200
