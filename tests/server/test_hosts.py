"""Live sessions rendered in host processes (``exprclone.server.runtime.hosts``): what a session here renders, frame for frame."""

import itertools

import numpy as np
import pytest

from exprclone import data as samples
from exprclone.errors import ExprCloneError
from exprclone.io.images import load_image
from exprclone.io.video import read_frames
from exprclone.options import Options
from exprclone.server.runtime.hosts import Hosts
from exprclone.server.session import Session, encode_jpeg

pytestmark = pytest.mark.slow  # servers, browsers, clusters or videos: pytest -m 'not slow' leaves these out


@pytest.fixture(scope="module")
def hosts():
    hosts = Hosts(1)
    yield hosts
    hosts.close()


def test_a_host_renders_the_frames_of_a_session_here_with_its_landmarker(hosts):
    portrait = samples.path(samples.TARGET).read_bytes()
    frames = [encode_jpeg(frame) for frame in itertools.islice(read_frames(samples.clip()), 0, 30, 6)]
    answers = {}
    for landmarker in ("dlib", "mesh"):
        options = Options(lambda_k=0.0, strength=0.8, landmarker=landmarker)
        remote, here = hosts.session(portrait, None, options, 256), Session(load_image(portrait), options, 256)
        assert remote.portrait.shape == here.portrait.shape
        for session in (remote, here):
            session.recapture(now=True)  # the first frame is the neutral face
        answers[landmarker] = [remote.process(frame, k / 25) for k, frame in enumerate(frames)]
        assert answers[landmarker] == [here.process(frame, k / 25) for k, frame in enumerate(frames)]
        assert all(status["face"] for _, status in answers[landmarker])
        remote.close()  # the host goes back for the next session
    assert answers["dlib"] != answers["mesh"]  # the landmarker reached the host: its tracking differs


def test_a_session_that_cannot_start_raises_here_and_frees_its_host(hosts):
    with pytest.raises(ExprCloneError, match="^portrait: "):
        hosts.session(b"not an image", None, Options(), 256)
    blank = encode_jpeg(np.full((300, 300, 3), 128, np.uint8))
    with pytest.raises(ExprCloneError, match="^portrait: no face found"):
        hosts.session(blank, None, Options(), 256)
    assert len(hosts._idle) == 1 and hosts._idle[0].process.is_alive()
