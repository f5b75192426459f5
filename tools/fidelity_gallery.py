"""Before and after retargeting and the ERI's gate (issue 17): the worst pairs by identity, and the ERI's artifacts.

    python tools/fidelity_gallery.py --scores BEFORE/pairs.csv [--before-ref 9950aa4] [--data ../shared/data] [-o docs/_static/fidelity.jpg]

"Before" is e+md as commit ``--before-ref`` made it (the paper's global and local stages,
the ERI without its gate), run from a ``git archive`` of that commit's ``src`` in a
temporary folder; "after" is e+md of the working tree (its defaults: retargeting and the
gate). The pairs:

- the ``--worst`` (10) whose e+md result was least like the target (dlib's identity
  distance) in ``--scores``, the ``pairs.csv`` of an ``exprclone evaluate`` run of the
  before commit;
- every London person's smile onto the next person (a ring over the 72: every source's two
  photos once), each checked for ratios on material swaps
  (:func:`exprclone.evaluation.scores.material_swaps`: where the source's photos differ in
  luma by a factor of 2 or more, which no shading does). A table of the ring is printed;
  the ``--artifacts`` (4) pairs whose ERI departed most from 1 there before are drawn.

Each row: source smile, target neutral, before, after, the target's real smile, and the
ERI before and after (grey: 1; dark: 0.7; light: 1.4).
"""

import argparse
import csv
import os
import subprocess
import sys
import tempfile
import types
from pathlib import Path

import cv2
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
#: a ratio this far from 1 on a material swap is an artifact (a fifth of the ERI's clamp).
ARTIFACT = 0.05
THUMB = 150
#: the sheet's JPEG quality: 13 rows stay under 400 KB.
JPEG_QUALITY = 80


def photo(data: Path, face: str, smiling: bool = False) -> np.ndarray:
    """A London photo: ``neutral_front/ID_03.jpg`` or ``smiling_front/ID_08.jpg``."""
    from exprclone.io.images import load_image

    return load_image(data / ("smiling_front" if smiling else "neutral_front") / f"{face}_{'08' if smiling else '03'}.jpg")


def render(data: Path, pairs: list[tuple[str, str]], out: Path) -> None:
    """e+md of each pair with the code importable as ``exprclone`` (its defaults): image, ERI, landmarks, in ``out``."""
    import exprclone

    for a, b in pairs:
        photos = (photo(data, a), photo(data, a, True), photo(data, b))
        r = exprclone.clone(*photos, method="e+md")
        marks = {f"lm_{k}": v for k, v in r.landmarks.items()}
        np.savez_compressed(out / f"{a}-{b}.npz", image=r.image, eri=r.eri.astype(np.float16), **marks)
        print(f"{a} -> {b}", file=sys.stderr)


def render_before(ref: str, data: Path, pairs: list[tuple[str, str]], out: Path) -> None:
    """:func:`render` with the code of commit ``ref`` (its ``src`` unpacked in a temporary folder)."""
    with tempfile.TemporaryDirectory() as tmp:
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", ref, "src"], check=True, capture_output=True).stdout
        subprocess.run(["tar", "-x", "-C", tmp], input=archive, check=True)
        env = dict(os.environ, PYTHONPATH=str(Path(tmp) / "src"))
        listed = ",".join(f"{a}:{b}" for a, b in pairs)
        subprocess.run([sys.executable, __file__, "--render", str(out), "--data", str(data), "--pairs", listed], check=True, env=env)


def load(folder: Path, pair: tuple[str, str]) -> types.SimpleNamespace:
    """A rendered pair as a result-like object: ``image``, ``eri``, ``landmarks``."""
    saved = np.load(folder / f"{pair[0]}-{pair[1]}.npz")
    marks = {k[3:]: saved[k] for k in saved.files if k.startswith("lm_")}
    return types.SimpleNamespace(image=saved["image"], eri=saved["eri"].astype(np.float32), landmarks=marks)


def on_swaps(result, data: Path, pair: tuple[str, str]) -> tuple[float, int]:
    """The largest departure of the ERI from 1 where the source's photos swap material, and how many pixels swap."""
    from exprclone.evaluation.scores import material_swaps
    from exprclone.landmarks.layout import DLIB68

    swaps = material_swaps(result, photo(data, pair[0]), photo(data, pair[0], True), DLIB68)
    return (float(np.abs(result.eri[swaps] - 1).max()) if swaps.any() else 0.0), int(swaps.sum())


def thumb(image: np.ndarray, landmarks: np.ndarray) -> np.ndarray:
    """The face of ``image`` (square, around ``landmarks``), :data:`THUMB` pixels wide."""
    from exprclone.evaluation.figures import face_box

    return cv2.resize(image[face_box(landmarks, image.shape)], (THUMB, THUMB), interpolation=cv2.INTER_AREA)


def eri_view(result) -> np.ndarray:
    """The ERI as grey: 0.7 black, 1 mid-grey, 1.4 white (log scale)."""
    grey = np.clip(128 + 127 * np.log(result.eri) / np.log(1.4), 0, 255).astype(np.uint8)
    return thumb(cv2.cvtColor(grey, cv2.COLOR_GRAY2RGB), result.landmarks["final"])


def row(data: Path, pair: tuple[str, str], before, after, note: str) -> np.ndarray:
    """One pair: a caption line, then source smile, target, before, after, real smile, ERI before and after."""
    from exprclone.landmarks.backends import default_detector

    a, b = pair
    smile, target, real = photo(data, a, True), photo(data, b), photo(data, b, True)
    cells = [thumb(smile, after.landmarks["source_expression"]), thumb(target, after.landmarks["target_neutral"])]
    cells += [thumb(before.image, before.landmarks["final"]), thumb(after.image, after.landmarks["final"])]
    cells += [thumb(real, default_detector().detect(real)), eri_view(before), eri_view(after)]
    caption = np.full((22, THUMB * len(cells), 3), 255, np.uint8)
    cv2.putText(caption, f"{a} onto {b}: {note}", (4, 16), cv2.FONT_HERSHEY_SIMPLEX, 0.45, (0, 0, 0), 1, cv2.LINE_AA)
    return np.vstack([caption, np.hstack(cells)])


def identity(image: np.ndarray, target: np.ndarray) -> float:
    """dlib's face-descriptor distance of ``image`` to the ``target`` photo, both detected afresh (as ``exprclone evaluate`` scores it)."""
    from exprclone.landmarks.backends import default_detector
    from exprclone.pipeline.role_check import descriptor, identity_distance

    return identity_distance(*(descriptor(im, default_detector().detect(im)) for im in (image, target)))


def worst_pairs(scores: Path, n: int) -> list[tuple[str, str]]:
    """The ``n`` pairs whose e+md result is farthest from its target by identity in an evaluate report's ``pairs.csv``."""
    with open(scores) as f:
        rows = [r for r in csv.DictReader(f) if r["method"] == "e+md" and not r["failed"] and not r.get("variant")]
    return [(r["source"], r["target"]) for r in sorted(rows, key=lambda r: -float(r["identity"]))[:n]]


def ring_table(data: Path, ring: list[tuple[str, str]], before: Path, after: Path) -> list[tuple[float, tuple[str, str]]]:
    """Print, for every pair of the ring, the ERI's largest departure from 1 on material swaps before and after; return
    the pairs with their departure before."""
    found = []
    print("| source onto target | swapped pixels before / after | largest abs(ERI - 1) there, before | after |")
    print("|---|---|---|---|")
    for pair in ring:
        (worst_before, n_before), (worst_after, n_after) = (on_swaps(load(folder, pair), data, pair) for folder in (before, after))
        print(f"| {pair[0]} onto {pair[1]} | {n_before} / {n_after} | {worst_before:.3f} | {worst_after:.3f} |")
        found.append((worst_before, worst_after, pair))
    artifacts = sum(b > ARTIFACT for b, _, _ in found), sum(a > ARTIFACT for _, a, _ in found)
    print(f"pairs with abs(ERI - 1) > {ARTIFACT} on a material swap: {artifacts[0]} of {len(ring)} before, {artifacts[1]} after;")
    print(f"largest after: {max(a for _, a, _ in found):.3f}")
    return [(b, pair) for b, _, pair in found]


def render_main() -> None:
    """The before commit's process (:func:`render_before`): :func:`render` with its own package, nothing newer imported."""
    parser = argparse.ArgumentParser()
    for name in ("--render", "--data", "--pairs"):
        parser.add_argument(name, required=True)
    args = parser.parse_args()
    render(Path(args.data), [tuple(p.split(":")) for p in args.pairs.split(",")], Path(args.render))


def main() -> None:
    from exprclone.data import sets as datasets  # here: render_main's process runs this file on an older package

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser, "london", holds="the London Set folder")
    parser.add_argument("--scores", type=Path, help="pairs.csv of an evaluate run of the before commit")
    parser.add_argument("--before-ref", default="9950aa4")
    parser.add_argument("--worst", type=int, default=10)
    parser.add_argument("--artifacts", type=int, default=4)
    parser.add_argument("--ring", type=int, default=0, help="only the first N people's smiles of the ring (default: all)")
    parser.add_argument("--work", type=Path, help="keep the rendered pairs here (default: a temporary folder)")
    parser.add_argument("-o", "--output", default="docs/_static/fidelity.jpg")
    args = parser.parse_args()
    people = sorted(p.name[:3] for p in (args.data / "neutral_front").glob("*_03.jpg"))
    ring = [(people[i], people[(i + 1) % len(people)]) for i in range(args.ring or len(people))]
    worst = worst_pairs(args.scores, args.worst)
    every = list(dict.fromkeys(worst + ring))
    with tempfile.TemporaryDirectory() as tmp:
        work = args.work or Path(tmp)
        before, after = work / "before", work / "after"
        for folder in (before, after):
            folder.mkdir(parents=True, exist_ok=True)
        render_before(args.before_ref, args.data, every, before)
        render(args.data, every, after)
        departures = ring_table(args.data, ring, before, after)
        shown = [p for d, p in sorted(departures, reverse=True)[: args.artifacts] if d > ARTIFACT]
        rows = [draw(args.data, pair, load(before, pair), load(after, pair), pair in worst) for pair in worst + shown]
    from PIL import Image

    Image.fromarray(np.vstack([header(rows[0].shape[1])] + rows)).save(args.output, quality=JPEG_QUALITY)
    print(f"{args.output}: {len(worst)} worst by identity, {len(shown)} with ERI artifacts")


def draw(data: Path, pair: tuple[str, str], before, after, worst: bool) -> np.ndarray:
    """A pair's :func:`row`, its caption saying why it is shown and its identity distances before and after."""
    ids = [identity(r.image, photo(data, pair[1])) for r in (before, after)]
    kind = "worst by identity" if worst else "ERI on a material swap"
    return row(data, pair, before, after, f"{kind}; identity {ids[0]:.3f} before, {ids[1]:.3f} after")


def header(width: int) -> np.ndarray:
    """The columns' names."""
    out = np.full((22, width, 3), 255, np.uint8)
    names = ("source smile", "target", "before", "after", "target's smile", "ERI before", "ERI after")
    for k, name in enumerate(names):
        cv2.putText(out, name, (k * THUMB + 4, 16), cv2.FONT_HERSHEY_SIMPLEX, 0.45, (0, 0, 0), 1, cv2.LINE_AA)
    return out


if __name__ == "__main__":
    render_main() if "--render" in sys.argv else main()
