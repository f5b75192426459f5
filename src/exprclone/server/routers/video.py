"""Video jobs: a portrait driven by a video of the source person (``POST /api/video``), followed at
``/api/jobs/{id}`` and fetched as an MP4 once done; the jobs run where the server's work runs
(:mod:`exprclone.server.runtime`: its own video workers, or a Dask cluster)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

from fastapi import APIRouter, File, UploadFile
from fastapi.responses import FileResponse, Response

from ...io.video import Limits
from .. import work
from ..answers import MP4, JobMade, JobState
from ..openapi import errors
from ..runtime.clients import Client
from ..runtime.jobs import JobNotDone
from ..runtime.state import Server
from .uploads import DrivingForm, FramingForm, JobId, Photo, VideoOptions, read_upload

router = APIRouter(tags=["video"])


@router.post("/api/video", status_code=202, responses=errors(400, 401, 413, 422, 429, 503))
async def video(
    server: Server,
    client: Client,
    portrait: Photo,
    driving_video: Annotated[UploadFile, File(description="a video of the source person (any format FFmpeg reads)")],
    asked: VideoOptions,
    driving: DrivingForm,
    framing: FramingForm,
) -> JobMade:
    """Start a video job: ``202 {"id", "status", "result"}``; follow it at ``/api/jobs/{id}``.

    The options are those of ``exprclone video``, by the same names (``lambda`` for ``--lambda``)."""
    options = asked.options
    photo = await read_upload(portrait, "portrait")
    # a portrait without a face fails now, not in the job
    await server.run(client, work.landmarks, photo, server.settings.max_pixels, options.landmarker)
    limits = Limits(server.settings.max_pixels, server.settings.max_video_seconds)  # its frames bounded as photos are
    request = work.VideoRequest(photo, options, driving.options, framing.options, limits)
    job_id = await server.backend.submit_video(client, request, driving_video.file)
    return JobMade(id=job_id, status=f"/api/jobs/{job_id}", result=f"/api/jobs/{job_id}/result")


@router.get("/api/jobs/{job_id}", responses=errors(404, 503))
async def job_state(server: Server, job_id: JobId) -> JobState:
    """A job's ``state`` (queued, running, done, failed), ``progress`` (0 to 1), ``error`` and, once done, ``info``."""
    return JobState(**await server.backend.video_state(job_id))


@router.get("/api/jobs/{job_id}/result", responses={200: {"content": {"video/mp4": {}}}, **errors(404, 409, 503)})
async def job_result(server: Server, job_id: JobId) -> Response:
    """The job's MP4 once it is done; 409 with ``{"error"}`` before."""
    state = await server.backend.video_state(job_id)
    if state["state"] != "done":
        raise JobNotDone(f"job {job_id}: {state['state']}" + (f" ({state['error']})" if state["error"] else ""))
    result = await server.backend.video_result(job_id)
    if isinstance(result, Path):
        return FileResponse(result, media_type="video/mp4", filename=MP4)
    return Response(result, media_type="video/mp4", headers={"Content-Disposition": f'attachment; filename="{MP4}"'})
