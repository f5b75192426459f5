"""How much jitter the live filter (tracking.OneEuro) removes, and how much lag it adds, on the GRID clips.

    python tools/live_filter.py [--data ../shared/data] [--settings 1.5,4 1,2 ...]

For every clip the tracker's raw landmarks are filtered as if they arrived live (causal,
at the clip's 25 fps). Jitter: :func:`exprclone.drive.tracking.jitter` of the mouth points,
filtered over raw. Lag: the shift (ms) that best aligns the filtered mouth opening with
the raw one (cross-correlation, in steps of a tenth of a frame, the signals interpolated).
The offline zero-phase filter of ``exprclone video`` is the peer (no lag by construction).
"""

import argparse

import numpy as np

from exprclone.data import sets as datasets
from exprclone.drive import tracking
from exprclone.io.video import probe, read_frames
from exprclone.landmarks.backends import default_detector
from exprclone.landmarks.layout import DLIB68
from exprclone.mouth import measure

MOUTH = DLIB68.mouth_outer + DLIB68.mouth_inner


def lag_ms(raw: np.ndarray, filtered: np.ndarray, fps: float) -> float:
    """The delay of ``filtered`` behind ``raw`` (ms) that maximises their correlation."""
    t = np.arange(len(raw))
    shifts = np.arange(0, 5, 0.1)
    scores = [np.corrcoef(raw[5:-5], np.interp(t[5:-5] + s, t, filtered))[0, 1] for s in shifts]
    return float(shifts[int(np.argmax(scores))] * 1000 / fps)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser)
    parser.add_argument("--settings", nargs="*", default=[f"{tracking.ONE_EURO_MIN_CUTOFF},{tracking.ONE_EURO_BETA}"])
    args = parser.parse_args()
    tracks = {}
    for clip in sorted((args.data / "grid").glob("*.mpg")):
        tracks[clip.stem] = tracking.track(read_frames(clip), default_detector()).points, float(probe(clip).fps)
    print("filter | jitter / raw (median, range) | lag ms (median, range) | opening correlation with raw (median)")
    print("---|---|---|---")
    rows = {"offline Savitzky-Golay (exprclone video)": lambda p, fps: tracking.smooth(p, fps)}
    for setting in args.settings:
        cutoff, beta = map(float, setting.split(","))

        def live(points, fps, cutoff=cutoff, beta=beta):
            f = tracking.OneEuro(cutoff, beta)
            return np.array([f(p, i / fps) for i, p in enumerate(points)])

        rows[f"1-euro, min_cutoff {cutoff:g} Hz, beta {beta:g}"] = live
    for name, smooth in rows.items():
        jitters, lags, correlations = [], [], []
        for raw, fps in tracks.values():
            filtered = smooth(raw, fps)
            jitters.append(tracking.jitter(filtered, MOUTH) / tracking.jitter(raw, MOUTH))
            opening = [np.array([measure.opening(p, DLIB68) for p in points]) for points in (raw, filtered)]
            lags.append(lag_ms(*opening, fps))
            correlations.append(np.corrcoef(*opening)[0, 1])
        jitter = f"{np.median(jitters):.2f} ({min(jitters):.2f}-{max(jitters):.2f})"
        lag = f"{np.median(lags):.0f} ({min(lags):.0f}-{max(lags):.0f})"
        print(f"{name} | {jitter} | {lag} | {np.median(correlations):.3f}")


if __name__ == "__main__":
    main()
