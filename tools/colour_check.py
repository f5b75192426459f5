"""Colour cast of the pasted mouth interior (and of the ERI), on GRID clips and on London stills.

    python tools/colour_check.py [--data ../shared/data] [--portraits 083 112 ...] [--size 512]
                                 [--clips lbax4n ...] [--stills 60] [--cast R G B] [--ref REV] [--jobs 2]
    python tools/colour_check.py --lightness [--data ../shared/data]
    python tools/colour_check.py --strip OUT.jpg [--ref REV] [--strip-pairs lbax4n:003 lrwp9a:025] [--crop 96]
    python tools/colour_check.py --spread [--data ../shared/data]

The measure. The *relation* of a face is the CIELAB (a*, b*) of the brightest 30% of
the pixels inside its inner lips (teeth, and the lit part of the cavity) minus the
(a*, b*) of its cheeks (two discs below the eyes). A right transfer gives the output the
driver's relation, whatever the two lights; pasting the driver's interior with the
driver's light does not. For every open-mouth frame (the paste's weight at least
:data:`OPEN_WEIGHT`) the distance between the driver's relation (driving frame, its
landmarks) and the output's (output frame, its final landmarks) is taken; each clip and
portrait reports its mean over those frames, and the summary the mean and the worst case.

- Videos: every GRID clip drives each portrait (scaled to ``--size``, neutral frame
  "closed", e+md). The default portraits (:data:`PORTRAITS`) are the palest and the
  darkest of the 72 London people by the CIELAB L* of their cheeks (``--lightness``
  prints the ranking), and 141, the pale young man with fair hair of issue 24. Each row
  gives the flicker: the mean change from one open-mouth frame to the next of the
  pasted interior's mean (a*, b*) (where the paste is whole), beside the same change of
  the driver's interior (inside its inner lips), which moves as the mouth shows more
  or less teeth, tongue and cavity. Each row also gives the ERI check: the shift of the (a*, b*) of the
  output's cheeks and nasolabial folds from the portrait's own (mean over all frames), and
  for scale the driver's cast, the distance between the (a*, b*) of the driver's cheeks
  and of the portrait's.
- Stills: the first ``--stills`` ordered London pairs (seed 0) whose e+md clone has an
  open mouth; the mean distance as above, the source's smile photo being the driver.
  Also the teeth brightness: on those pairs where the source's smile and the target's
  real smile both show teeth (:data:`TEETH_SHOWN`) and the paste is whole somewhere
  (:data:`WHOLE`), the log ratio of the pasted interior's brightness (the median luma
  of the brightest 30% where the paste is whole) to the target's own real smile's (the
  same inside its inner lips), rms over the pairs: in one studio, the target's real
  teeth are the right brightness.

``--cast R G B`` also clones the stills with the source's two photos multiplied by that
light (the synthetic cast of ``tests/mouth/test_paste.py``, on every pair): it prints the
relation distance with the cast smile as the driver, the distance that a transfer
undoing the cast exactly would score (the uncast clone against the cast driver: the
relation in CIELAB is not kept by a change of light, so a strong cast moves it even
when nothing else changes), and how much the paste changed.

``--own-teeth`` prints, for scale, what each portrait person's own real smile (teeth
shown, in the studio's white light) would score against each clip: the measure is not
kept by a change of light (the CIELAB differences of an orange-lit face are stretched),
and real teeth in white light need not score low against an orange-lit driver.

``--lightness`` prints the 72 London people ordered by the CIELAB L* of their cheeks
(the median over the skin cue's pixels, :func:`exprclone.mouth.illuminant.skin_pixels`, of
the neutral photo), palest first.

``--spread`` prints the between-people spread of the cues to the light
(:mod:`exprclone.mouth.illuminant`) on the London neutral photos, one studio and one light:
``SKIN_SPREAD`` and ``SCLERA_SPREAD``.

``--ref REV`` measures the code of a commit instead of the working tree (its ``src``
exported by ``git archive`` to a temporary folder). ``--strip OUT.jpg`` writes, for
the :data:`STRIP_ROWS` most open mouths of each ``CLIP:PORTRAIT`` pair, mouth crops of
the driving frame, of the output of ``REV`` (with ``--ref``) and of the output of the
working tree, side by side: a before/after figure.

exprclone is imported inside the functions, so that ``--ref`` imports the tree it names
(one with the package's present layout: ``exprclone.io``, ``exprclone.drive``).
"""

from __future__ import annotations

import argparse
import concurrent.futures
import contextlib
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import cv2
import numpy as np

from exprclone.data import sets as datasets

ROOT = Path(__file__).resolve().parents[1]
#: share of the pixels inside the inner lips, the brightest, that stand for the interior.
BRIGHTEST = 0.30
#: a frame's mouth is open when the pasted interior's weight reaches this.
OPEN_WEIGHT = 0.5
#: cheek discs: centre below each eye's centre, and radius, in outer-eye-corner distances.
CHEEK_DROP, CHEEK_RADIUS = 0.35, 0.10
#: fold discs: centre beside the middle of nose wing and mouth corner, and radius.
FOLD_SIDE, FOLD_RADIUS = 0.06, 0.07
#: the pasted interior is whole where its weight reaches this.
WHOLE = 0.9
#: teeth show from this area, in squared mouth widths (as ``exprclone.evaluation.TEETH_SHOWN``).
TEETH_SHOWN = 0.004
#: frames in a strip (``--strip``), the default pairs shown, and the crops' size in pixels.
STRIP_ROWS, STRIP_PAIRS, CROP = 5, ("lbax4n:003", "lrwp9a:025"), 96
#: fewest frames between two frames of a strip.
STRIP_SPACING = 4
#: the default portraits: the three palest London people by ``--lightness`` (L* 79.3,
#: 77.0, 76.4), the three darkest (29.9, 34.8, 36.2), 141, the pale young man with fair
#: hair of issue 24 (L* 72.2), and the next palest and darkest whose smile shows teeth
#: (:data:`TEETH_SHARE`): 097, 009 (74.2) and 099 (38.8). Of the first seven only 083,
#: 096 and 062 smile with their teeth; the own-teeth error so has three pale people and
#: three dark ones.
PORTRAITS = ("083", "112", "124", "137", "096", "062", "141", "097", "009", "099")
#: a mouth shows teeth (for the own-teeth error) when they are at least this share of
#: the pixels inside its inner lips (``exprclone.mouth.measure.interior``): half of the
#: :data:`BRIGHTEST` share, so that the brightest pixels are mostly teeth, not tongue.
TEETH_SHARE = BRIGHTEST / 2


def lab(pixels: np.ndarray) -> np.ndarray:
    """CIELAB of uint8 sRGB pixels ``(K, 3)`` (D65), ``(K, 3)``."""
    return cv2.cvtColor(pixels.reshape(-1, 1, 3).astype(np.float32) / 255.0, cv2.COLOR_RGB2LAB).reshape(-1, 3)


def lab_ab(pixels: np.ndarray) -> np.ndarray:
    """CIELAB (a*, b*) of uint8 sRGB pixels ``(K, 3)`` (D65), ``(K, 2)``."""
    return lab(pixels)[:, 1:]


def discs(shape: tuple[int, ...], centres: np.ndarray, radius: float) -> np.ndarray:
    """Boolean mask of filled discs."""
    mask = np.zeros(shape[:2], np.uint8)
    for c in centres:
        cv2.circle(mask, (int(round(c[0])), int(round(c[1]))), max(1, int(round(radius))), 1, -1)
    return mask > 0


def regions(shape: tuple[int, ...], landmarks: np.ndarray) -> dict[str, np.ndarray]:
    """Masks of the cheeks (below the eyes) and of the nasolabial folds, lips left out."""
    from exprclone.landmarks import align
    from exprclone.landmarks.layout import DLIB68

    iod = align.interocular(landmarks, DLIB68)
    right, down = align.face_axes(landmarks, DLIB68)
    eyes = np.array([landmarks[list(eye)].mean(0) for eye in DLIB68.eyes])
    folds = np.array(
        [(landmarks[31] + landmarks[48]) / 2 - FOLD_SIDE * iod * right, (landmarks[35] + landmarks[54]) / 2 + FOLD_SIDE * iod * right]
    )
    lips = np.zeros(shape[:2], np.uint8)
    cv2.fillPoly(lips, [np.round(landmarks[list(DLIB68.mouth_outer)]).astype(np.int32)], 1)
    return {
        "cheeks": discs(shape, eyes + CHEEK_DROP * iod * down, CHEEK_RADIUS * iod) & (lips == 0),
        "folds": discs(shape, folds, FOLD_RADIUS * iod) & (lips == 0),
    }


def brightest_ab(pixels: np.ndarray) -> np.ndarray:
    """Mean (a*, b*) of the brightest :data:`BRIGHTEST` of uint8 pixels ``(K, 3)`` by luma."""
    luma = pixels.astype(np.float32) @ np.array([0.299, 0.587, 0.114], np.float32)
    return lab_ab(pixels[luma >= np.percentile(luma, 100 * (1 - BRIGHTEST))]).mean(0)


def interior_ab(image: np.ndarray, landmarks: np.ndarray) -> np.ndarray:
    """Mean (a*, b*) of the brightest :data:`BRIGHTEST` of the pixels inside the inner lips."""
    return brightest_ab(image[inner_mask(image.shape, landmarks)])


def inner_mask(shape: tuple[int, ...], landmarks: np.ndarray) -> np.ndarray:
    """The pixels inside the inner lips."""
    from exprclone.landmarks.layout import DLIB68

    inner = np.zeros(shape[:2], np.uint8)
    cv2.fillPoly(inner, [np.round(landmarks[list(DLIB68.mouth_inner)]).astype(np.int32)], 1)
    return inner > 0


def cheeks_ab(image: np.ndarray, landmarks: np.ndarray) -> np.ndarray:
    """Mean (a*, b*) of the cheeks (:func:`regions`)."""
    return lab_ab(image[regions(image.shape, landmarks)["cheeks"]]).mean(0)


def relation(image: np.ndarray, landmarks: np.ndarray) -> np.ndarray:
    """The interior's (a*, b*) minus the cheeks' (:func:`interior_ab`, :func:`regions`)."""
    return interior_ab(image, landmarks) - cheeks_ab(image, landmarks)


def paste_relation(result) -> np.ndarray:
    """The relation of a clone's output with the pasted interior where it is whole (:data:`WHOLE`) as its interior.

    Inside the final inner lips the paste fades out toward the lip line, and there the
    output shows the target's own lips, stretched: on a pale portrait they are as bright
    as the pasted teeth, and would count among the brightest pixels.
    """
    whole = result.mouth_mask >= WHOLE * result.mouth_mask.max()
    return brightest_ab(result.image[whole]) - cheeks_ab(result.image, result.landmarks["final"])


def teeth_share(image: np.ndarray, landmarks: np.ndarray, gain: np.ndarray | None = None) -> float:
    """The share of the pixels inside the inner lips that are teeth (``exprclone.mouth.measure.interior``, after ``gain``)."""
    from exprclone.landmarks import lips
    from exprclone.landmarks.layout import DLIB68
    from exprclone.mouth import measure

    landmarks = lips.uncross(landmarks, DLIB68)
    return float(measure.interior(image, landmarks, DLIB68, gain)[0].sum() / max(int(inner_mask(image.shape, landmarks).sum()), 1))


def eye_white_balance(frames: list[np.ndarray], points: np.ndarray) -> np.ndarray:
    """The per-channel gain that makes a clip's eye whites grey (their midmean over every frame), its brightness kept.

    The light of a clip is the same in all its frames; under it a coloured light
    saturates teeth as it does lips, and ``exprclone.mouth.measure.interior`` no longer tells
    them apart.
    """
    from exprclone.landmarks.layout import DLIB68
    from exprclone.mouth import illuminant

    white = np.maximum(illuminant.midmean(np.concatenate([illuminant.sclera_pixels(f, p, DLIB68) for f, p in zip(frames, points)])), 1.0)
    return np.exp(np.log(white).mean()) / white


def own_smile(data: Path, face: str, size: int | None) -> np.ndarray | None:
    """The relation (:func:`relation`) of a London person's own smile, scaled as the portraits are; None when it shows too few teeth."""
    from exprclone.landmarks import lips
    from exprclone.landmarks.backends import default_detector
    from exprclone.landmarks.layout import DLIB68

    smile = load_image(data / "london/smiling_front" / f"{face}_08.jpg")
    if size:
        smile = resize_portrait(smile, size)
    points = lips.uncross(default_detector().detect(smile), DLIB68)
    return relation(smile, points) if teeth_share(smile, points) >= TEETH_SHARE else None


def own_floor(data: Path, size: int | None) -> tuple[dict[str, float], float]:
    """What pasting the average real teeth would score on the own-teeth error: each person's distance to the others' mean.

    Over the London smiles that show teeth (:func:`own_smile`): for each person, the
    distance between their relation and the mean of everyone else's (leave one out);
    and the mean of those distances, the between-person spread of the relation.
    """
    faces = sorted(p.name[:3] for p in (data / "london/smiling_front").glob("*_08.jpg"))
    smiles = {face: r for face in faces if (r := own_smile(data, face, size)) is not None}
    values = np.array(list(smiles.values()))
    total = values.sum(0)
    floors = {face: float(np.linalg.norm(r - (total - r) / (len(values) - 1))) for face, r in smiles.items()}
    return floors, float(np.mean(list(floors.values())))


def load_image(path):
    """exprclone's image reader."""
    from exprclone.io.images import load_image as load

    return load(path)


def driven(portrait: np.ndarray, portrait_points: np.ndarray | None, clip: Path):
    """The portrait driven by a clip (neutral frame: the most closed mouth): ``(points, frames)``.

    ``frames`` yields objects with ``index``, ``driving``, ``image`` and ``result``.
    """
    from exprclone import drive
    from exprclone.io.video import probe, read_frames

    recording = drive.prepare(portrait, portrait_points, lambda: read_frames(clip), float(probe(clip).fps), neutral_frame="closed")
    return recording.points, recording.frames(read_frames(clip))


def resize_portrait(image: np.ndarray, size: int) -> np.ndarray:
    from exprclone.drive.framing import resize_portrait as resize

    return resize(image, None, size)[0]


def pasted(result) -> bool:
    """Whether a clone shows a pasted interior of weight :data:`OPEN_WEIGHT` or more."""
    return result.mouth_mask is not None and float(result.mouth_mask.max()) >= OPEN_WEIGHT


def inner_ab(image: np.ndarray, landmarks: np.ndarray) -> np.ndarray:
    """Mean (a*, b*) of all the pixels inside the inner lips."""
    return lab_ab(image[inner_mask(image.shape, landmarks)]).mean(0)


def steps(colours: list[np.ndarray | None]) -> float:
    """Mean distance between consecutive colours, where both are given (None: a closed mouth)."""
    moves = [np.linalg.norm(b - a) for a, b in zip(colours, colours[1:]) if a is not None and b is not None]
    return float(np.mean(moves)) if moves else np.nan


def drive(clip: Path, portrait: np.ndarray, portrait_points: np.ndarray, own: np.ndarray | None = None) -> dict:
    """One clip driving one portrait: the relation distance, the own-teeth error, the flicker, the ERI shift and the driver's cast.

    ``own`` is the relation of the portrait person's own smile (:func:`own_smile`): the
    own-teeth error is the distance of the paste's relation (:func:`paste_relation`) to
    it, on the open frames whose driver shows teeth (:data:`TEETH_SHARE`, told once the
    clip's light is made white by its eye whites, :func:`eye_white_balance`).
    """
    from exprclone.io.video import read_frames

    points_of, frames = driven(portrait, portrait_points, clip)
    balance = eye_white_balance(list(read_frames(clip)), points_of) if own is not None else None
    target = regions(portrait.shape, portrait_points)
    target_ab = {k: lab_ab(portrait[m]).mean(0) for k, m in target.items()}
    distances, pastes, owned, shifts, casts, paste, source = [], [], [], [], [], [], []
    for f in frames:
        final, points = f.result.landmarks["final"], points_of[f.index]
        out = regions(f.image.shape, final)
        shifts.append(np.mean([np.linalg.norm(lab_ab(f.image[out[k]]).mean(0) - target_ab[k]) for k in out]))
        casts.append(np.linalg.norm(lab_ab(f.driving[regions(f.driving.shape, points)["cheeks"]]).mean(0) - target_ab["cheeks"]))
        opened = pasted(f.result)
        if opened:
            driver = relation(f.driving, points)
            distances.append(np.linalg.norm(driver - relation(f.image, final)))
            pastes.append(np.linalg.norm(driver - paste_relation(f.result)))
            if own is not None and teeth_share(f.driving, points, balance) >= TEETH_SHARE:
                owned.append(np.linalg.norm(own - paste_relation(f.result)))
        whole = f.result.mouth_mask >= WHOLE * f.result.mouth_mask.max() if opened else None
        paste.append(lab_ab(f.image[whole]).mean(0) if opened else None)
        source.append(inner_ab(f.driving, points) if opened else None)
    return {
        "distance": np.mean(distances) if distances else np.nan,
        "paste_distance": np.mean(pastes) if pastes else np.nan,
        "own": np.mean(owned) if owned else np.nan,
        "teeth_frames": len(owned),
        "open": len(distances),
        "frames": len(shifts),
        "flicker": steps(paste),
        "driver_flicker": steps(source),
        "eri_shift": float(np.mean(shifts)),
        "cast": float(np.mean(casts)),
    }


def drive_case(case: tuple[Path, str, Path, int]) -> dict:
    """:func:`drive` on ``(data, portrait id, clip, size)``: the portrait loaded and its landmarks found here (a task of ``--jobs``)."""
    from exprclone.landmarks.backends import default_detector

    data, face, clip, size = case
    portrait = resize_portrait(load_image(data / "london/neutral_front" / f"{face}_03.jpg"), size)
    own = own_smile(data, face, size)
    return dict(drive(clip, portrait, default_detector().detect(portrait), own), clip=clip.stem, portrait=face)


def mouth_crop(image: np.ndarray, landmarks: np.ndarray, size: int = CROP) -> np.ndarray:
    """A square crop around the mouth (1.6 mouth widths), ``size`` pixels."""
    from exprclone.landmarks.layout import DLIB68

    outer = landmarks[list(DLIB68.mouth_outer)]
    centre, half = outer.mean(0), 0.8 * np.ptp(outer[:, 0])
    m = np.array(
        [[size / (2 * half), 0, size / 2 - centre[0] * size / (2 * half)], [0, size / (2 * half), size / 2 - centre[1] * size / (2 * half)]]
    )
    return cv2.warpAffine(image, m, (size, size), flags=cv2.INTER_AREA, borderMode=cv2.BORDER_REPLICATE)


def strip_crops(data: Path, pairs: list[str], size: int, crop: int = CROP) -> np.ndarray:
    """Mouth crops (driver, output) of :data:`STRIP_ROWS` frames of each ``CLIP:PORTRAIT`` pair, ``(rows, pairs, 2, h, w, 3)``.

    The frames are those whose driving mouth is the most open (``mouth.opening``), at
    least :data:`STRIP_SPACING` frames apart, told by the tracked landmarks alone, so
    that every version of the code shows the same frames.
    """
    from exprclone.landmarks.layout import DLIB68
    from exprclone.mouth import measure

    columns = []
    for pair in pairs:
        clip, face = pair.split(":")
        portrait = resize_portrait(load_image(data / "london/neutral_front" / f"{face}_03.jpg"), size)
        points_of, frames = driven(portrait, None, data / "grid" / f"{clip}.mpg")
        chosen: list[int] = []
        for i in np.argsort([-measure.opening(p, DLIB68) for p in points_of], kind="stable"):
            if len(chosen) < STRIP_ROWS and all(abs(int(i) - j) >= STRIP_SPACING for j in chosen):
                chosen.append(int(i))
        columns.append(
            [
                (mouth_crop(f.driving, points_of[f.index], crop), mouth_crop(f.image, f.result.landmarks["final"], crop))
                for f in frames
                if f.index in chosen
            ]
        )
    return np.array(columns).transpose(1, 0, 2, 3, 4, 5)


def stills(data: Path, wanted: int, cast: np.ndarray | None = None) -> dict:
    """The first ``wanted`` seed-0 London pairs with an open mouth: relation distances and teeth brightness errors.

    With ``cast`` (per-channel factors) each pair is also cloned with the source's two
    photos under that light, and the result holds, per pair: the relation distance with
    the cast source's smile as the driver (``cast_distances``); the same against the
    uncast clone, the score of a transfer that undid the cast exactly
    (``perfect_distances``); and the mean absolute change of the whole paste, per channel
    (``changes``).
    """
    import exprclone
    from exprclone.landmarks.backends import default_detector
    from exprclone.landmarks.layout import DLIB68
    from exprclone.mouth.measure import interior, mouth_width

    london = data / "london"
    ids = sorted(p.name[:3] for p in (london / "neutral_front").glob("*_03.jpg"))
    every = [(a, b) for a in ids for b in ids if a != b]
    detector, cache = default_detector(), {}

    def photo(face: str, smile: bool):
        if (face, smile) not in cache:
            image = load_image(london / ("smiling_front" if smile else "neutral_front") / f"{face}_{'08' if smile else '03'}.jpg")
            cache[face, smile] = image, detector.detect(image)
        return cache[face, smile]

    def shows_teeth(image, points):
        return interior(image, points, DLIB68)[0].sum() / mouth_width(points, DLIB68) ** 2 >= TEETH_SHOWN

    def brightest_luma(pixels):
        luma = pixels.astype(np.float32) @ np.array([0.299, 0.587, 0.114], np.float32)
        return float(np.median(luma[luma >= np.percentile(luma, 100 * (1 - BRIGHTEST))]))

    own_smiles: dict[str, np.ndarray | None] = {}
    distances, brightness, owned, cast_distances, perfect_distances, changes = [], [], [], [], [], []
    for i in np.random.default_rng(0).permutation(len(every)):
        if len(distances) == wanted:
            break
        a, b = every[i]
        (sn, sn_lm), (se, se_lm), (tn, tn_lm) = photo(a, False), photo(a, True), photo(b, False)
        r = exprclone.clone(sn, se, tn, method="e+md", landmarks=(sn_lm, se_lm, tn_lm))
        if not pasted(r):
            continue
        distances.append(np.linalg.norm(relation(se, se_lm) - relation(r.image, r.landmarks["final"])))
        if b not in own_smiles:
            own_smiles[b] = own_smile(data, b, None)
        if own_smiles[b] is not None and teeth_share(se, se_lm) >= TEETH_SHARE:
            owned.append(np.linalg.norm(own_smiles[b] - paste_relation(r)))
        real, real_lm = photo(b, True)
        if r.mouth_mask.max() >= WHOLE and shows_teeth(se, se_lm) and shows_teeth(real, real_lm):
            real_inside = np.zeros(real.shape[:2], np.uint8)
            cv2.fillPoly(real_inside, [np.round(real_lm[list(DLIB68.mouth_inner)]).astype(np.int32)], 1)
            brightness.append(np.log(brightest_luma(r.image[r.mouth_mask >= WHOLE]) / brightest_luma(real[real_inside > 0])))
        if cast is not None:
            lit = [np.round(im * cast).astype(np.uint8) for im in (sn, se)]
            c = exprclone.clone(*lit, tn, method="e+md", landmarks=(sn_lm, se_lm, tn_lm))
            driver = relation(lit[1], se_lm)
            perfect_distances.append(np.linalg.norm(driver - relation(r.image, r.landmarks["final"])))
            whole = r.mouth_mask >= WHOLE * r.mouth_mask.max()
            changes.append(np.abs(c.image[whole].astype(float) - r.image[whole]).mean(0))
            cast_distances.append(np.linalg.norm(driver - relation(c.image, c.landmarks["final"])) if pasted(c) else np.nan)
    return {
        "distances": np.array(distances),
        "brightness": np.array(brightness),
        "own": np.array(owned),
        "cast_distances": np.array(cast_distances),
        "perfect_distances": np.array(perfect_distances),
        "changes": np.array(changes),
    }


def spread(data: Path) -> None:
    """Print the standard deviation over the London neutral photos of each cue's log brightness and log colour."""
    from exprclone.landmarks.backends import default_detector
    from exprclone.landmarks.layout import DLIB68
    from exprclone.mouth import illuminant

    detector, colours = default_detector(), []
    for path in sorted((data / "london" / "neutral_front").glob("*_03.jpg")):
        image = load_image(path)
        colours.append(illuminant.Light.measure(image, detector.detect(image), DLIB68).log_colour)
    brightness, colour = illuminant.split(np.array(colours))
    for i, name in enumerate(("SKIN_SPREAD", "SCLERA_SPREAD")):
        print(f"{name} = ({brightness[:, i].std():.3f}, {np.sqrt(colour[:, i].var(0).sum() / 2):.3f})  # {len(colours)} photos")


def skin_lightness(data: Path) -> list[tuple[str, float]]:
    """The London people and the CIELAB L* of their cheeks on their neutral photos (median over the skin cue's pixels), palest first."""
    from exprclone.landmarks.backends import default_detector
    from exprclone.landmarks.layout import DLIB68
    from exprclone.mouth import illuminant

    detector, rows = default_detector(), []
    for path in sorted((data / "london" / "neutral_front").glob("*_03.jpg")):
        image = load_image(path)
        pixels = illuminant.skin_pixels(image, detector.detect(image), DLIB68)
        rows.append((path.name[:3], float(np.median(lab(pixels)[:, 0]))))
    return sorted(rows, key=lambda row: -row[1])


def own_teeth(data: Path, portraits: list[str], clips: list[Path], size: int) -> None:
    """``--own-teeth``: the floor of the own-teeth error, and what each portrait's own real smile would score on the issue's measure.

    The floor (:func:`own_floor`): for each person, the distance between their real
    smile's relation and the average of the others'. Then the relation of the portrait
    person's smile (scaled as the portraits are), against the driver's relation on the
    frames whose mouth is fully open (``mouth.OPENING``), for the people whose smile
    shows teeth (:func:`own_smile`): a right answer, in white light, on that measure.
    """
    from exprclone.drive import tracking
    from exprclone.io.video import probe, read_frames
    from exprclone.landmarks.backends import default_detector
    from exprclone.landmarks.layout import DLIB68
    from exprclone.mouth import measure

    floors, spread = own_floor(data, size)
    print(f"{len(floors)} London smiles show teeth; the between-person spread of their relation {spread:.1f}")
    own = {face: r for face in portraits if (r := own_smile(data, face, size)) is not None}
    print(" ".join(f"{face}: floor {floors[face]:.1f}" for face in own))
    detector, rows = default_detector(), []
    for clip in clips:
        points = tracking.smooth(tracking.track(read_frames(clip), detector, clip.name).points, float(probe(clip).fps))
        driver = [relation(f, p) for f, p in zip(read_frames(clip), points) if measure.opening(p, DLIB68) >= measure.OPENING[1]]
        rows.append([np.mean([np.linalg.norm(d - r) for d in driver]) for r in own.values()])
        print(f"{clip.stem} | {' | '.join(f'{v:.1f}' for v in rows[-1])}", flush=True)
    scores = np.array(rows)
    print(f"own real teeth on the issue's measure: mean {scores.mean():.1f}, worst {scores.max():.1f}; ", end="")
    print(f"at most 8 in {np.sum(scores <= 8)} of {scores.size}")


def report_videos(cases: list[tuple[Path, str, Path, int]], jobs: int) -> None:
    """Drive every case (:func:`drive_case`), on ``jobs`` processes; print a row per case, then the means and the worst cases."""
    if not cases:
        return
    print("clip | portrait | open frames | relation distance (paste only) | own-teeth error (frames) | ", end="")
    print("flicker (driver's) | ERI shift | driver's cast")
    print("---|---|---|---|---|---|---|---")
    rows = []
    with concurrent.futures.ProcessPoolExecutor(jobs) if jobs > 1 else contextlib.nullcontext() as pool:
        for row in (pool.map if pool else map)(drive_case, cases):
            rows.append(row)
            cells = [row["clip"], row["portrait"], f"{row['open']}/{row['frames']}", f"{row['distance']:.1f} ({row['paste_distance']:.1f})"]
            cells += [f"{row['own']:.1f} ({row['teeth_frames']})", f"{row['flicker']:.2f} ({row['driver_flicker']:.2f})"]
            cells += [f"{row['eri_shift']:.1f}", f"{row['cast']:.1f}"]
            print(" | ".join(cells), flush=True)
    d = np.array([r["distance"] for r in rows])
    worst = rows[int(np.nanargmax(d))]
    print(f"\nvideos: relation distance mean {np.nanmean(d):.1f}, ", end="")
    print(f"worst {worst['distance']:.1f} ({worst['clip']} on {worst['portrait']})", end="")
    print(f"; at most 8 in {np.sum(d <= 8)} of {np.sum(np.isfinite(d))}")
    print(f"videos: the same with the paste alone as the output's interior: mean {np.nanmean([r['paste_distance'] for r in rows]):.1f}")
    report_own([r for r in rows if np.isfinite(r["own"])], cases[0][0], cases[0][3])
    flicker = np.array([[r["flicker"], r["driver_flicker"]] for r in rows])
    print(f"flicker: the paste's mean (a*, b*) moves {np.nanmean(flicker[:, 0]):.2f} a frame ", end="")
    print(f"(worst case {np.nanmax(flicker[:, 0]):.2f}), ", end="")
    print(f"the driver's interior {np.nanmean(flicker[:, 1]):.2f}")
    shift = [r["eri_shift"] for r in rows]
    print(f"ERI shift mean {np.mean(shift):.2f}, max {np.max(shift):.2f}")


def report_own(rows: list[dict], data: Path, size: int) -> None:
    """Print the own-teeth error: mean, worst, and per portrait beside its floor (:func:`own_floor`)."""
    if not rows:
        return
    floors, spread = own_floor(data, size)
    own = np.array([r["own"] for r in rows])
    worst = rows[int(np.argmax(own))]
    print(f"videos: own-teeth error mean {own.mean():.1f}, worst {worst['own']:.1f} ({worst['clip']} on {worst['portrait']}), ", end="")
    print(f"on {len(rows)} cases; floor (the average real teeth pasted) {np.mean([floors[r['portrait']] for r in rows]):.1f}, ", end="")
    print(f"between-person spread {spread:.1f}")
    for face in dict.fromkeys(r["portrait"] for r in rows):
        mine = [r["own"] for r in rows if r["portrait"] == face]
        print(f"  {face}: own-teeth error mean {np.mean(mine):.1f}, worst {np.max(mine):.1f}; floor {floors[face]:.1f}")


def report_stills(s: dict, cast: list[float] | None, data: Path) -> None:
    """Print the figures of :func:`stills`."""
    d, b = s["distances"], s["brightness"]
    print(f"stills: relation distance mean {d.mean():.1f} (median {np.median(d):.1f}, worst {d.max():.1f}) on {len(d)} pairs")
    print(f"stills: teeth log brightness error {np.sqrt(np.mean(b**2)):.3f} rms, mean {b.mean():+.3f}, on {len(b)} pairs")
    own, spread = s["own"], own_floor(data, None)[1]
    print(f"stills: own-teeth error mean {own.mean():.1f} (median {np.median(own):.1f}, worst {own.max():.1f}) ", end="")
    print(f"on {len(own)} pairs ", end="")
    print(f"whose source and target smile with teeth; floor (between-person spread) {spread:.1f}")
    if cast:
        c, perfect, changes = s["cast_distances"], s["perfect_distances"], s["changes"]
        lost = f"paste lost in {np.isnan(c).sum()} of {len(c)} pairs"
        print(f"cast {cast}: relation distance mean {np.nanmean(c):.1f} (median {np.nanmedian(c):.1f}), {lost}")
        print(f"cast {cast}: a transfer that undid the cast exactly would score {perfect.mean():.1f} (median {np.median(perfect):.1f})")
        print(f"cast {cast}: the paste changed by {changes.mean(0).round(1).tolist()} grey levels (R, G, B; mean absolute), ", end="")
        print(f"at most {changes.mean(1).max():.1f} in a pair")


def run_at(ref: str, arguments: list[str]) -> int:
    """Run this tool with ``arguments`` on the code of commit ``ref`` (its ``src`` exported to a temporary folder)."""
    with tempfile.TemporaryDirectory() as tmp:
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", ref, "src"], check=True, capture_output=True).stdout
        subprocess.run(["tar", "-x", "-C", tmp], input=archive, check=True)
        return subprocess.run([sys.executable, __file__, *arguments], env=dict(os.environ, PYTHONPATH=str(Path(tmp) / "src"))).returncode


def write_strip(args: argparse.Namespace) -> int:
    """``--strip``: the driving frames' mouths, the outputs of ``--ref`` (if given) and of the working tree, side by side."""
    after = strip_crops(args.data, args.strip_pairs, args.size, args.crop)
    columns = [after[:, :, 0]]
    if args.ref:
        with tempfile.TemporaryDirectory() as tmp:
            before = Path(tmp) / "before.npy"
            common = ["--data", str(args.data), "--size", str(args.size), "--crop", str(args.crop), "--strip-pairs", *args.strip_pairs]
            if run_at(args.ref, ["--crops-to", str(before), *common]):
                return 1
            columns.append(np.load(before)[:, :, 1])
    columns.append(after[:, :, 1])
    rows, pairs = after.shape[:2]
    gap = np.full((args.crop, args.crop // 8, 3), 255, np.uint8)
    strip = np.vstack(
        [np.hstack([np.hstack([c[r, p] for c in columns] + [gap]) for p in range(pairs)])[:, : -gap.shape[1]] for r in range(rows)]
    )
    cv2.imwrite(args.strip, cv2.cvtColor(strip, cv2.COLOR_RGB2BGR), [cv2.IMWRITE_JPEG_QUALITY, 90])
    return 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser)
    parser.add_argument("--portraits", nargs="*", default=list(PORTRAITS))
    parser.add_argument("--clips", nargs="*", help="clip names (default: every clip in DATA/grid)")
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--stills", type=int, default=60, help="open-mouth London pairs (0: none)")
    parser.add_argument(
        "--cast", type=float, nargs=3, metavar=("R", "G", "B"), help="also clone the stills with the source's photos under this light"
    )
    parser.add_argument("--ref", help="a git commit to measure instead of the working tree")
    parser.add_argument("--spread", action="store_true", help="print the spread of the cues to the light on the London Set, and stop")
    parser.add_argument("--lightness", action="store_true", help="print the London people by the L* of their cheeks, and stop")
    parser.add_argument("--own-teeth", action="store_true", help="print what the portraits' own real smiles would score, and stop")
    parser.add_argument("--jobs", type=int, default=1, help="processes for the videos (default 1)")
    parser.add_argument("--strip", help="write driver | REV's output | output mouth crops of the --strip-pairs here, and stop")
    parser.add_argument("--strip-pairs", nargs="*", default=list(STRIP_PAIRS), metavar="CLIP:PORTRAIT")
    parser.add_argument("--crop", type=int, default=CROP, help="the strip's mouth crops, in pixels")
    parser.add_argument("--crops-to", help=argparse.SUPPRESS)  # internal: --strip's crops, as .npy, by the code of --ref
    args = parser.parse_args()
    if args.crops_to:
        np.save(args.crops_to, strip_crops(args.data, args.strip_pairs, args.size, args.crop))
        return 0
    if args.strip:
        return write_strip(args)
    if args.ref:
        return run_at(args.ref, [a for a in sys.argv[1:] if a != args.ref and a != "--ref" and not a.startswith("--ref=")])

    if args.spread:
        spread(args.data)
        return 0
    clips = [args.data / "grid" / f"{c}.mpg" for c in args.clips] if args.clips else sorted((args.data / "grid").glob("*.mpg"))
    if args.own_teeth:
        own_teeth(args.data, args.portraits, clips, args.size)
        return 0
    if args.lightness:
        for face, lightness in skin_lightness(args.data):
            print(f"{face} {lightness:.1f}")
        return 0
    report_videos([(args.data, face, clip, args.size) for face in args.portraits for clip in clips], args.jobs)
    if args.stills:
        report_stills(stills(args.data, args.stills, None if args.cast is None else np.array(args.cast)), args.cast, args.data)
    return 0


if __name__ == "__main__":
    sys.exit(main())
