"""exprclone benchmarks: medians per stage, per method, against peers, and with image size.

    python benchmarks/run.py [--data ../shared/data] [--repeat 7] [--quick] [--targets]

Prints, for the sample photos at 512x512 and at their full 1350x1350:
  * the median time of each stage (landmark detection of one photo, global, local,
    elastic for one lambda_k and for all candidates, the lambda search of the paper's stages
    with E+MD's image at GI it carries to the candidates, one mesh warp, the ERI, the MD mask);
  * the median time of each method end to end, with landmarks known, and of e+md with
    landmark detection on all three photos included;
  * e+md against global end to end, the two run in turn (both see the same load: the
    ratio of the two is what the speed targets are stated in);
  * Song et al.'s method against global warping + ERI, and each method of Fig. 11 on the
    VTC global warp against the same method on the paper's similarity, all in turn (issue
    54's targets: at most 50 ms more at 1350, landmarks known);
  * at 1350x1350, issue 52's speed targets on the package's sample smile of 126 onto 003 (its
    teeth show: e+md pastes the mouth's interior): one ``cv2.remap`` of the target photo (maps
    precomputed), a global and an e+md clone with landmarks known, all in turn, through
    ``exprclone.clone`` and through a ``Cloner`` made for each clone (the stages under
    ``clone``'s role check), and the two ratios against their targets: global within 6x
    the remap, e+md within 3x global; beside them, e+md on a closed-mouth smile (no paste),
    and each clone's CPU time with the least wall-clock time it fits in on the machine's
    cores (``--targets``: these alone);
  * our piecewise-affine warp against scikit-image's PiecewiseAffineTransform + warp on
    the same points and image, and against a bare cv2.remap with precomputed maps (the
    floor for any warp; measured in turn with ours, so both see the same load), as
    ratios measured in the same run;
  * the thin-plate-spline warp (``--image-warp tps``) against the mesh warp on the same
    control points, each alone and the two in turn (the target: within 2x of the mesh
    warp at 1350), and the global method with either;
  * how e+md's time grows with image size (256, 512, 1024, 2048);
  * peak memory of one e+md clone at full size (a child process's max RSS), and the
    start-up time of the ``exprclone`` command, with a whole ``exprclone clone`` of the
    package's samples (start, models, landmarks, role check, clone, file written).
Timings are wall-clock medians over --repeat runs after one warm-up run.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import cv2
import numpy as np

from exprclone import METHODS, clone, clone_methods
from exprclone.data import SOURCE, TARGET
from exprclone.data import path as sample_path
from exprclone.data import photo as sample_photo
from exprclone.data import sets as datasets
from exprclone.details import muscle
from exprclone.geometry import db_metric, eigenface, elastic, global_warp, local_warp, vtc
from exprclone.geometry.eigenface import default_eigenfaces
from exprclone.imaging import piecewise, tps
from exprclone.imaging.warpers import tps_refine
from exprclone.io.images import load_image
from exprclone.landmarks.backends import default_detector
from exprclone.landmarks.layout import DLIB68
from exprclone.methods import FIG11
from exprclone.pipeline import render
from exprclone.pipeline import stages as stages_
from exprclone.pipeline.request import Request, pair


def median_ms(fn, repeat: int) -> float:
    fn()
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return 1000 * statistics.median(times)


def interleaved_ms(fns: dict, repeat: int) -> dict[str, float]:
    """Median times of several functions run in turn, so that all see the same load."""
    return interleaved(fns, repeat)[0]


def interleaved(fns: dict, repeat: int) -> tuple[dict[str, float], dict[str, float]]:
    """:func:`interleaved_ms`, and the median CPU time of each (``time.process_time``: every thread of the process)."""
    for fn in fns.values():
        fn()
    wall: dict[str, list[float]] = {name: [] for name in fns}
    cpu: dict[str, list[float]] = {name: [] for name in fns}
    for _ in range(repeat):
        for name, fn in fns.items():
            t, c = time.perf_counter(), time.process_time()
            fn()
            wall[name].append(time.perf_counter() - t)
            cpu[name].append(time.process_time() - c)
    walls, cpus = ({name: 1000 * statistics.median(t) for name, t in times.items()} for times in (wall, cpu))
    return walls, cpus


def photos(data: Path, size: int) -> tuple[list[np.ndarray], list[np.ndarray]]:
    london = data / "london"
    paths = [london / "neutral_front/001_03.jpg", london / "smiling_front/001_08.jpg", london / "neutral_front/003_03.jpg"]
    images = [load_image(p) for p in paths]
    if size != images[0].shape[0]:
        images = [cv2.resize(im, (size, size), interpolation=cv2.INTER_AREA if size < im.shape[0] else cv2.INTER_CUBIC) for im in images]
    return images, [default_detector().detect(im) for im in images]


def stages(images, lms, repeat: int) -> dict[str, float]:
    """Each stage as clone runs it: the shape stages and the details on a Cloner's prepared faces, the paper's stages
    (``retarget=False``: with the default's, LI is GI and the lambda search does not run)."""
    sn_img, se_img, tn_img = images
    sn, se, tn = lms
    cloner = pair(Request.of(sn_img, None, tn_img, landmarks=(sn, None, tn), retarget=False))
    prepared = cloner.prepare(se_img, se, ("e+md",))
    expression, shapes, faces = prepared.expression, prepared.shapes, cloner.faces
    gl, lo, nb = shapes["global"].points, shapes["local"].points, faces.neighbours
    mesh, lambdas = faces.mesh, np.array(db_metric.LAMBDAS)
    rendered = render.fi(faces, *render.geometry(faces, shapes["elastic"].points, cloner.transfer), "mesh")
    dst = mesh.control_points(gl)
    centres, radii = muscle.areas(gl, DLIB68)
    h = np.ones(len(centres))
    before = {name: shapes[name] for name in ("global", "local")}
    cands = list(elastic.elastic_landmarks(gl, lo, nb, lambdas, db_metric.CANDIDATE_PASSES))
    source_crop = eigenface.crop(se_img, se, DLIB68, eigenface.FEATURE_SIZE)
    synthesis = render.synthesis(faces, expression, "mesh", lambda: prepared.photo)
    at_gl = db_metric.Synthesized.of(*synthesis(gl), DLIB68, mesh.n_landmarks)
    faces.ratio_faces  # the neutral faces prepared, once per pair
    return {
        "landmark detection (1 photo)": median_ms(lambda: default_detector().detect(tn_img), repeat),
        "mesh": median_ms(lambda: piecewise.build_mesh(tn, tn_img.shape, DLIB68), repeat),
        "global (landmarks)": median_ms(lambda: global_warp.global_landmarks(sn, se, tn, DLIB68), repeat),
        "global RBF (landmarks, Jacobians included)": median_ms(lambda: global_warp.rbf_landmarks(sn, se, tn, DLIB68), repeat),
        "global VTC (landmarks, tents factorised included)": median_ms(
            lambda: vtc.vtc_landmarks(sn, se, tn, DLIB68, vtc.Tents.of(tn, nb)), repeat
        ),
        "local (landmarks)": median_ms(lambda: local_warp.local_landmarks(gl, se, DLIB68), repeat),
        "elastic (1 lambda)": median_ms(lambda: elastic.elastic_landmarks(gl, lo, nb, 1.0), repeat),
        "elastic (13 lambdas at once, every pass)": median_ms(lambda: elastic.elastic_landmarks(gl, lo, nb, lambdas), repeat),
        "lambda search (13 candidates + DB + the chosen solved)": median_ms(
            lambda: stages_.elastic_stage(faces, cloner.options, expression, before, synthesis), repeat
        ),
        "  of which E+MD's image at GI (the candidates' source)": median_ms(lambda: synthesis(gl), repeat),
        "  of which DB on given candidates": median_ms(
            lambda: db_metric.choose_lambda(at_gl, mesh, cands, lambdas, source_crop, default_eigenfaces(), DLIB68), repeat
        ),
        "warp (full image)": median_ms(lambda: piecewise.warp(tn_img, mesh.points, dst, mesh.triangles), repeat),
        "ERI (both source photos warped on its grid)": median_ms(
            lambda: render.ratio(faces, rendered.control, prepared.photo, cloner.transfer, "mesh"), repeat
        ),
        "mesh image (the ERI's on the shared mesh, warped onto FI)": median_ms(
            lambda: render.ratio(faces, rendered.control, prepared.photo, cloner.transfer, "mesh", kind="mesh"), repeat
        ),
        "MD mask (Eqs. 10-11)": median_ms(
            lambda: muscle.importance_mask(tn_img.shape[:2], centres, radii, h, muscle.mask_step(radii)), repeat
        ),
    }


def methods(images, lms, repeat: int) -> dict[str, float]:
    out = {m: median_ms(lambda m=m: clone(*images, method=m, landmarks=lms), repeat) for m in METHODS}
    out[f"all {len(METHODS)} methods (clone_methods)"] = median_ms(lambda: clone_methods(*images, landmarks=lms), repeat)
    for warp in ("rbf", "vtc"):
        out[f"e+md, --global-warp {warp}"] = median_ms(lambda w=warp: clone(*images, method="e+md", landmarks=lms, global_warp=w), repeat)
    out["e+md, --image-warp tps"] = median_ms(lambda: clone(*images, method="e+md", landmarks=lms, image_warp="tps"), repeat)
    out["global, --image-warp tps (against global: the warp's cost)"] = median_ms(
        lambda: clone(*images, method="global", landmarks=lms, image_warp="tps"), repeat
    )
    out["e+md with landmark detection"] = median_ms(lambda: clone(*images, method="e+md"), repeat)
    return out


def against_global(images, lms, repeat: int) -> dict[str, float]:
    """e+md and global end to end (landmarks known) in turn, 3x as many runs: the methods' medians above are taken one
    method after the other, and this machine's load drifts between them."""
    return interleaved_ms({m: lambda m=m: clone(*images, method=m, landmarks=lms) for m in ("global", "e+md")}, 3 * repeat)


#: what each row of :func:`song_against_peers` is measured against (issue 54's targets: at most 50 ms more).
PEERS = {"song": "global+eri", **{f"{m}, --global-warp vtc": m for m in FIG11}}


def song_against_peers(images, lms, repeat: int) -> dict[str, float]:
    """Song et al.'s method, the methods of Fig. 11 and each of them on the VTC global warp, end to end (landmarks
    known), all in turn so that all see the same load."""
    fns = {m: lambda m=m: clone(*images, method=m, landmarks=lms) for m in (*FIG11, "song")}
    fns |= {f"{m}, --global-warp vtc": lambda m=m: clone(*images, method=m, landmarks=lms, global_warp="vtc") for m in FIG11}
    return interleaved_ms(fns, 2 * repeat)


def show_against(title: str, rows: dict[str, float], peers: dict[str, str]) -> None:
    """Each row of ``peers`` with its time and its difference to its peer's."""
    print(f"\n{title}")
    for name, peer in peers.items():
        print(f"  {name:60s} {rows[name]:9.1f} ms  ({rows[name] - rows[peer]:+.1f} ms against {peer}, {rows[peer]:.1f} ms)")


#: issue 52's speed targets: a global clone within this many remaps of the photo, e+md within this many global clones.
GLOBAL_IN_REMAPS, EMD_IN_GLOBALS = 6.0, 3.0


def teeth_photos() -> tuple[list[np.ndarray], list[np.ndarray]]:
    """The package's sample smile of 126 (it shows teeth: e+md pastes its mouth's interior, every stage runs) and the
    neutral photos of 126 and 003, at 1350x1350, with their landmarks."""
    return sample_photos("126", "003")


def sample_photos(source: str, target: str) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """The package's neutral and smiling photos of ``source`` and the neutral photo of ``target``, with their landmarks."""
    images = [sample_photo(source), sample_photo(source, "smile"), sample_photo(target)]
    return images, [default_detector().detect(im) for im in images]


#: the closed-mouth smile the speed targets show beside the teeth of :func:`teeth_photos`: 001's, onto 003 (no paste).
CLOSED = "e+md (clone), 001's closed-mouth smile"


def speed_targets(images, lms, repeat: int) -> tuple[dict[str, float], dict[str, float]]:
    """One remap of the target photo, and global and e+md clones with landmarks known (through ``clone``, and through a
    new ``Cloner`` each: what lies under ``clone``'s role check), in turn, 3x as many runs: the targets are ratios; and
    an e+md clone of a closed-mouth smile (:data:`CLOSED`: no paste, and nothing measured for one). The wall-clock
    medians, and the CPU time of each (both cores' work)."""
    tn_img, tn = images[2], lms[2]
    mesh = piecewise.build_mesh(tn, tn_img.shape, DLIB68)
    mx, my = piecewise.inverse_maps(mesh.points, mesh.control_points(lms[1]), mesh.triangles, tn_img.shape[:2])
    closed, closed_lms = sample_photos("001", "003")

    def cloned(method: str):
        return lambda: pair(Request.of(images[0], None, tn_img, landmarks=(lms[0], None, tn))).clone_methods(images[1], lms[1], (method,))

    return interleaved(
        {
            "cv2.remap of the photo": lambda: cv2.remap(tn_img, mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE),
            "global (clone)": lambda: clone(*images, method="global", landmarks=lms),
            "e+md (clone)": lambda: clone(*images, method="e+md", landmarks=lms),
            "global (Cloner)": cloned("global"),
            "e+md (Cloner)": cloned("e+md"),
            CLOSED: lambda: clone(*closed, method="e+md", landmarks=closed_lms),
        },
        3 * repeat,
    )


def show_targets(rows: dict[str, float], cpu: dict[str, float]) -> None:
    """The two ratios of :func:`speed_targets` against their targets, through ``clone`` and through ``Cloner``; and each
    clone's CPU time, with the least wall-clock time that much CPU time fits in on the machine's cores (all of them busy
    all along), in global clones: while a clone spends that much, no scheduling of it takes less."""
    for way in ("clone", "Cloner"):
        glob, emd = rows[f"global ({way})"], rows[f"e+md ({way})"]
        for name, ratio, target, peer in (
            (f"global ({way}) / remap", glob / rows["cv2.remap of the photo"], GLOBAL_IN_REMAPS, "remap"),
            (f"e+md ({way}) / global ({way})", emd / glob, EMD_IN_GLOBALS, "global"),
        ):
            print(f"  {name:60s} {ratio:6.2f}x (target {target:g}x {peer}: {'met' if ratio <= target else 'NOT met'})")
    cores, glob = os.cpu_count() or 1, rows["global (clone)"]
    print(f"  {CLOSED + ' / global (clone)':60s} {rows[CLOSED] / glob:6.2f}x")
    for name in ("global (clone)", "e+md (clone)", CLOSED):
        least = cpu[name] / cores
        print(f"  {name + ', CPU time':60s} {cpu[name]:6.1f} ms (on {cores} cores at least {least:.1f} ms, {least / glob:.2f}x global)")


def warp_peers(images, lms, repeat: int) -> dict[str, float]:
    tn_img = images[2]
    tn = lms[2]
    mesh = piecewise.build_mesh(tn, tn_img.shape, DLIB68)
    moved = tn + 4 * np.stack([np.sin(tn[:, 1] / 60), np.cos(tn[:, 0] / 50)], 1)
    dst = mesh.control_points(moved)
    mx, my = piecewise.inverse_maps(mesh.points, dst, mesh.triangles, tn_img.shape[:2])
    # ours and the floor in turn, 3x as many runs: they are fast and their ratio is the target
    rows = interleaved_ms(
        {
            "exprclone warp": lambda: piecewise.warp(tn_img, mesh.points, dst, mesh.triangles),
            "bare cv2.remap, maps precomputed": lambda: cv2.remap(tn_img, mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE),
        },
        3 * repeat,
    )

    rows["scikit-image PiecewiseAffineTransform + warp"] = median_ms(skimage_peer(tn_img, tn), max(1, repeat // 3))
    return rows


def skimage_peer(image: np.ndarray, landmarks: np.ndarray):
    """The naive scikit-image warp of ``image``: ``PiecewiseAffineTransform`` estimated on the clone's mesh of its
    landmarks (with forehead and border points), moved a few pixels, and ``skimage.transform.warp`` of the whole photo
    (bilinear); a function that runs it once."""
    from skimage.transform import PiecewiseAffineTransform
    from skimage.transform import warp as sk_warp

    mesh = piecewise.build_mesh(landmarks, image.shape, DLIB68)
    dst = mesh.control_points(landmarks + 4 * np.stack([np.sin(landmarks[:, 1] / 60), np.cos(landmarks[:, 0] / 50)], 1))

    def skimage_warp():
        t = PiecewiseAffineTransform.from_estimate(dst, mesh.points)  # output -> input, as skimage's warp expects
        return sk_warp(image, t, preserve_range=True).astype(np.uint8)

    return skimage_warp


def tps_vs_mesh(images, lms, repeat: int) -> dict[str, float]:
    """The TPS warp and the mesh warp of the target photo, on the same control points: each timed alone (back to
    back), and the two in turn (so that both see the same load; each then pays for the other's use of the caches)."""
    tn_img, tn = images[2], lms[2]
    mesh = piecewise.build_mesh(tn, tn_img.shape, DLIB68)
    dst = mesh.control_points(tn + 4 * np.stack([np.sin(tn[:, 1] / 60), np.cos(tn[:, 0] / 50)], 1))
    fns = {
        "mesh warp (piecewise-affine)": lambda: piecewise.warp(tn_img, mesh.points, dst, mesh.triangles),
        "TPS warp (three grids, bicubic, one remap)": lambda: tps.warp(tn_img, mesh.points, dst, None, tps_refine(mesh)),
    }
    alone = {f"{name}, alone": median_ms(fn, 3 * repeat) for name, fn in fns.items()}
    return alone | {f"{name}, in turn": ms for name, ms in interleaved_ms(fns, 3 * repeat).items()}


def peak_memory_mb(data: Path) -> float:
    """Max RSS of a child process that runs one full-size e+md clone with detection."""
    code = (
        "import resource, sys; from exprclone import clone; from exprclone.io.images import load_image as l; "
        f"d='{data}/london/'; clone(l(d+'neutral_front/001_03.jpg'), l(d+'smiling_front/001_08.jpg'), l(d+'neutral_front/003_03.jpg')); "
        "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return int(out.stdout.strip()) / 1024


def startup_ms(repeat: int) -> dict[str, float]:
    def cmd(*args):
        return median_ms(lambda: subprocess.run(list(args), capture_output=True, check=True), repeat)

    samples = [str(sample_path(SOURCE)), str(sample_path(SOURCE, "smile")), str(sample_path(TARGET))]
    with tempfile.TemporaryDirectory() as out:
        whole = cmd(sys.executable, "-m", "exprclone", "clone", *samples, "-o", os.path.join(out, "clone.png"))
    return {
        "python -c pass (interpreter floor)": cmd(sys.executable, "-c", "pass"),
        "exprclone --help": cmd(sys.executable, "-m", "exprclone", "--help"),
        "import exprclone": cmd(sys.executable, "-c", "import exprclone"),
        "exprclone clone of the samples (start to file)": whole,
    }


def show(title: str, rows: dict[str, float], ratio_to: str | None = None) -> None:
    print(f"\n{title}")
    for name, ms in rows.items():
        extra = f"  ({ms / rows[ratio_to]:.1f}x)" if ratio_to else ""
        print(f"  {name:60s} {ms:9.1f} ms{extra}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser)
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--quick", action="store_true", help="skip the size sweep and the start-up timing")
    parser.add_argument("--targets", action="store_true", help="only issue 52's speed targets at 1350x1350")
    args = parser.parse_args()
    data = Path(args.data)
    print(f"exprclone benchmarks: {os.cpu_count()} cores, median of {args.repeat} runs")
    if args.targets:
        rows, cpu = speed_targets(*teeth_photos(), args.repeat)
        show("issue 52's speed targets at 1350x1350 (landmarks known), in turn, ratio to the remap", rows, "cv2.remap of the photo")
        return show_targets(rows, cpu)
    for size in (512, 1350):
        images, lms = photos(data, size)
        show(f"stages at {size}x{size}", stages(images, lms, args.repeat))
        show(f"methods end to end at {size}x{size} (landmarks known unless said)", methods(images, lms, args.repeat))
        show(f"e+md against global at {size}x{size}, in turn, ratio to global", against_global(images, lms, args.repeat), "global")
        show_against(
            f"Song et al.'s method and the VTC global warp at {size}x{size}, in turn (landmarks known)",
            song_against_peers(images, lms, args.repeat),
            PEERS,
        )
        if size == 1350:
            rows, cpu = speed_targets(*teeth_photos(), args.repeat)
            show("issue 52's speed targets at 1350x1350 (landmarks known), in turn, ratio to the remap", rows, "cv2.remap of the photo")
            show_targets(rows, cpu)
        show(
            f"piecewise-affine warp at {size}x{size}, ratio to the bare remap",
            warp_peers(images, lms, args.repeat),
            "bare cv2.remap, maps precomputed",
        )
        show(
            f"thin-plate-spline warp at {size}x{size}, ratio to the mesh warp alone",
            tps_vs_mesh(images, lms, args.repeat),
            "mesh warp (piecewise-affine), alone",
        )
    if not args.quick:
        sweep = {}
        for size in (256, 512, 1024, 2048):
            images, lms = photos(data, size)
            sweep[f"e+md at {size}x{size}"] = median_ms(lambda: clone(*images, method="e+md", landmarks=lms), args.repeat)
        show("e+md with image size (landmarks known), ratio to 512", sweep, "e+md at 512x512")
        show("start-up", startup_ms(args.repeat))
    print(f"\npeak memory, one e+md clone at 1350x1350 with detection: {peak_memory_mb(data):.0f} MB (max RSS)")


if __name__ == "__main__":
    main()
