"""exprclone video benchmark: frames per second driving a 512x512 portrait from a GRID clip.

    python benchmarks/video.py [--data ../shared/data] [--clip bbaf2n] [--repeat 5]

Prints medians over --repeat passes of the clip (75 frames, 360x288, 25 fps), after one
warm-up pass, in milliseconds per frame and frames per second:
  * decoding the clip (the floor of any pass over it), and encoding 512x512 H.264;
  * landmarks: our tracker against the peer, dlib's detector plus shape predictor on
    every frame;
  * rendering (landmarks known, lambda_k fixed): global, elastic (no detail steps),
    elastic+eri and e+md, so the differences show what each stage costs;
  * the whole ``exprclone video`` job in-process (three decoding passes, tracking,
    lambda_k chosen once, rendering, encoding with sound) for elastic and for e+md.
"""

from __future__ import annotations

import argparse
import io
import os
import tempfile
import warnings
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

from run import median_ms

from exprclone import cli, drive, tracking
from exprclone.io.frames import resize_portrait
from exprclone.io.images import load_image
from exprclone.io.video import probe, read_frames, write_video
from exprclone.models import default_detector

SIZE = 512
OUT = os.path.join(tempfile.gettempdir(), "exprclone-bench.mp4")


def per_frame(rows: dict[str, float], frames: int) -> None:
    for name, ms in rows.items():
        print(f"  {name:55s} {ms / frames:7.1f} ms/frame {1000 * frames / ms:7.1f} fps")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", default=os.environ.get("EXPRCLONE_DATA", "../shared/data"))
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

    print(f"\nrendering, landmarks known, lambda_k fixed ({lam:g})")
    render = {}
    for method in ("global", "elastic", "elastic+eri", "e+md"):
        d = drive.Driver(recording.driver.cloner, method, lam)
        render[method] = median_ms(lambda d=d: sum(1 for _ in d.frames(frames, recording.points)), args.repeat)
    per_frame(render, n)
    print(f"  the e+md detail steps (ERI, MD, mouth) cost {(render['e+md'] - render['elastic']) / n:.1f} ms/frame")

    print("\nthe whole `exprclone video` job (decode three times, track, choose lambda_k, render, encode with sound)")
    jobs = {}
    for method in ("elastic", "e+md"):
        argv = ["video", str(portrait_path), clip, "-o", OUT, "--size", str(SIZE), "--method", method]

        def job(argv=argv):
            with redirect_stdout(io.StringIO()), redirect_stderr(io.StringIO()), warnings.catch_warnings():
                assert cli.main(argv) == 0

        jobs[f"exprclone video --method {method}"] = median_ms(job, args.repeat)
    per_frame(jobs, n)
    os.unlink(OUT)


if __name__ == "__main__":
    main()
