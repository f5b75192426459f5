"""exprclone video benchmark: frames per second driving a 512x512 portrait from a GRID clip.

    python benchmarks/video.py [--data ../shared/data] [--clip bbaf2n] [--repeat 5]

Prints medians over --repeat passes of the clip (75 frames, 360x288, 25 fps), after one
warm-up pass, in milliseconds per frame and frames per second:
  * decoding the clip (the floor of any pass over it), and encoding 512x512 H.264;
  * landmarks: our tracker against the peer, dlib's detector plus shape predictor on
    every frame;
  * rendering (landmarks known, lambda_k fixed): global, elastic (no detail steps),
    elastic+eri and e+md in turn, so the differences show what each stage costs;
  * e+md's detail steps each alone, on every frame's own geometry: the ERI, the MD mask
    with Eq. (9), the mouth interior;
  * the whole ``exprclone video`` job in-process (three decoding passes, tracking,
    lambda_k chosen once, rendering, encoding with sound) for elastic and for e+md in turn (both
    see the same load), their ratio, and how much more than elastic's the e+md job may take at
    :data:`TARGET` of elastic's fps.
"""

from __future__ import annotations

import argparse
import io
import os
import tempfile
import warnings
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

from run import interleaved_ms, median_ms

from exprclone import cli, drive
from exprclone.data import sets as datasets
from exprclone.drive import tracking
from exprclone.drive.framing import resize_portrait
from exprclone.io.images import load_image
from exprclone.io.video import probe, read_frames, write_video
from exprclone.landmarks.backends import default_detector
from exprclone.methods import lookup
from exprclone.pipeline.cloner import Cloner

SIZE = 512
#: the speed target of the video job: e+md at this share of elastic's fps.
TARGET = 0.85
OUT = os.path.join(tempfile.gettempdir(), "exprclone-bench.mp4")


def per_frame(rows: dict[str, float], frames: int) -> None:
    for name, ms in rows.items():
        print(f"  {name:55s} {ms / frames:7.1f} ms/frame {1000 * frames / ms:7.1f} fps")


def detail_steps(cloner: Cloner, frames: list, points, lambda_k: float, repeat: int) -> dict[str, float]:
    """e+md's detail steps (:meth:`Cloner.details`) each alone over the frames, on every frame's own FI and ERI."""
    method = lookup(("e+md",))[0]
    inputs = []
    transfer = cloner.transfer
    for frame, p in zip(frames, points):
        prepared = cloner.changed(lambda_k=lambda_k).prepare(frame, p, ("e+md",))
        rendered = cloner.fi(prepared.shapes["elastic"].points, transfer)
        inputs.append((prepared, rendered, cloner.ratio(rendered, prepared.photo, transfer)))
    landmarks = cloner.faces.mesh.n_landmarks  # the final landmarks lead the control points

    def details(mouth: bool) -> None:
        for prepared, rendered, ratio in inputs:
            cloner.details(method, prepared.expression, rendered.image, rendered.control[:landmarks], ratio, mouth, transfer)

    steps = {
        "ERI (the three photos on its grid, its tests)": median_ms(
            lambda: [cloner.ratio(r, p.photo, transfer) for p, r, _ in inputs], repeat
        ),
        "MD mask and Eq. (9)": median_ms(lambda: details(False), repeat),
        "MD mask, Eq. (9) and the mouth interior": median_ms(lambda: details(True), repeat),
    }
    steps["  of which the mouth interior"] = steps["MD mask, Eq. (9) and the mouth interior"] - steps["MD mask and Eq. (9)"]
    return steps


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser)
    parser.add_argument("--clip", default="bbaf2n")
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    data = Path(args.data)
    clip = str(data / "grid" / f"{args.clip}.mpg")
    portrait_path = data / "london/neutral_front/003_03.jpg"
    portrait = resize_portrait(load_image(portrait_path), None, SIZE)[0]
    frames = list(read_frames(clip))
    n = len(frames)
    detector = default_detector()
    print(f"exprclone video benchmark: {os.cpu_count()} cores, {args.clip} ({n} frames), {SIZE}x{SIZE} output, median of {args.repeat}")

    fps = probe(clip).fps
    recording = drive.prepare(portrait, None, lambda: read_frames(clip), float(fps), method="e+md")
    lam = recording.driver.lambda_k
    rendered = [f.image for f in recording.frames(frames)]

    print("\ninput and output")
    per_frame(
        {
            "decode the clip": median_ms(lambda: sum(1 for _ in read_frames(clip)), args.repeat),
            f"encode {SIZE}x{SIZE} H.264": median_ms(lambda: write_video(OUT, iter(rendered), fps), args.repeat),
        },
        n,
    )

    print("\nlandmarks of every frame")
    detect = median_ms(lambda: [detector.fit(f, detector.faces(f)[0]) for f in frames], args.repeat)
    follow = median_ms(lambda: tracking.track(frames, detector), args.repeat)
    per_frame({"tracker (detect once, follow, check every 5 frames)": follow, "peer: detector + predictor on every frame": detect}, n)
    print(f"  tracker is {detect / follow:.1f}x faster than detecting every frame")

    print(f"\nrendering, landmarks known, lambda_k fixed ({lam:g}), in turn")
    cloner = recording.driver.cloner
    drivers = {method: drive.Driver(cloner.changed(method=method)) for method in ("global", "elastic", "elastic+eri", "e+md")}
    render = interleaved_ms({m: lambda d=d: sum(1 for _ in d.frames(frames, recording.points)) for m, d in drivers.items()}, args.repeat)
    per_frame(render, n)
    detail = (render["e+md"] - render["elastic"]) / n
    print(f"  the e+md detail steps (ERI, MD, mouth) cost {detail:.1f} ms/frame")

    print("\ne+md's detail steps each alone, landmarks known")
    per_frame(detail_steps(recording.driver.cloner, frames, recording.points, lam, args.repeat), n)

    print("\nthe whole `exprclone video` job (decode three times, track, choose lambda_k, render, encode with sound), in turn")
    jobs = {}
    for method in ("elastic", "e+md"):
        argv = ["video", str(portrait_path), clip, "-o", OUT, "--size", str(SIZE), "--method", method]

        def job(argv=argv):
            with redirect_stdout(io.StringIO()), redirect_stderr(io.StringIO()), warnings.catch_warnings():
                assert cli.main(argv) == 0

        jobs[f"exprclone video --method {method}"] = job
    times = interleaved_ms(jobs, args.repeat)
    per_frame(times, n)
    elastic, emd = (times[f"exprclone video --method {m}"] / n for m in ("elastic", "e+md"))
    print(f"  e+md runs at {elastic / emd:.2f}x the fps of elastic, taking {emd - elastic:.1f} ms/frame more")
    print(f"  at {TARGET}x it would take at most {elastic / TARGET - elastic:.1f} ms/frame more (its detail steps: {detail:.1f})")
    os.unlink(OUT)


if __name__ == "__main__":
    main()
