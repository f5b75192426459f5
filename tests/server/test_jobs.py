"""Video jobs' bookkeeping (:mod:`exprclone.server.runtime.jobs`): failed jobs give their place back, Retry-After agrees with
the message."""

import re
from concurrent.futures import Future

import pytest

from exprclone.errors import ExprCloneError
from exprclone.server.runtime.jobs import FAILED_KEPT, RETRY_RUNNING, Jobs
from exprclone.server.runtime.limits import Busy

pytestmark = pytest.mark.slow  # servers, browsers, clusters or videos: pytest -m 'not slow' leaves these out


def ended(result=None, error=None) -> Future:
    future = Future()
    future.set_result(result) if error is None else future.set_exception(error)
    return future


def test_a_failed_job_frees_its_place_and_its_files_but_keeps_its_error(tmp_path):
    jobs = Jobs(tmp_path, limit=2, ttl=3600)
    failed = jobs.create()
    failed.video.write_bytes(b"a driving video")
    jobs.start(failed, ended(error=ExprCloneError("driving_video", "no frame 500")))
    assert not failed.video.exists() and jobs.get(failed.id).state()["error"] == "driving_video: no frame 500"
    for _ in range(2):  # both places are free again
        jobs.start(jobs.create(), ended({"frames": 1}))


def test_retry_after_is_when_the_first_done_job_expires(tmp_path):
    jobs = Jobs(tmp_path, limit=2, ttl=600)
    for _ in range(2):
        jobs.start(jobs.create(), ended({"frames": 1}))
    with pytest.raises(Busy) as busy:
        jobs.create()
    said = int(re.search(r"try again in (\d+) s", str(busy.value)).group(1))
    assert busy.value.retry_after == said and 590 <= said <= 600


def test_retry_after_while_every_job_runs(tmp_path):
    jobs = Jobs(tmp_path, limit=1, ttl=600)
    jobs.start(jobs.create(), Future())  # queued, never ends
    with pytest.raises(Busy, match=f"try again in {RETRY_RUNNING} s") as busy:
        jobs.create()
    assert busy.value.retry_after == RETRY_RUNNING


def test_failed_jobs_kept_are_bounded(tmp_path):
    jobs = Jobs(tmp_path, limit=1, ttl=3600)
    made = []
    for _ in range(FAILED_KEPT + 5):
        made.append(jobs.create())
        jobs.start(made[-1], ended(error=ExprCloneError("driving_video", "broken")))
    jobs.expire()
    assert len(jobs._jobs) == FAILED_KEPT and made[-1].id in jobs._jobs and made[0].id not in jobs._jobs
