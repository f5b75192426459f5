"""Tests for exprclone.io.images: reading any image file as RGB uint8, writing atomically."""

import os
import warnings
from pathlib import Path

import cv2
import numpy as np
import pytest
from PIL import Image

from exprclone import data as samples
from exprclone.errors import ExprCloneError, ExprCloneWarning
from exprclone.io.images import check_output_path, load_image, save_image


@pytest.fixture(scope="module")
def photo_path() -> Path:
    """A real sample photo (read only, never modified)."""
    return samples.path("001")


@pytest.fixture(scope="module")
def photo(photo_path: Path) -> Image.Image:
    """The sample photo, cropped to non-square (so rotations show) and shrunk to keep tests fast."""
    with Image.open(photo_path) as image:
        return image.convert("RGB").crop((0, 100, 1350, 1100)).resize((162, 120))


def load_with_warning(path: Path, *phrases: str) -> np.ndarray:
    """load_image, asserting exactly one ExprCloneWarning naming the file and saying ``phrases``."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        image = load_image(path)
    ours = [w for w in caught if issubclass(w.category, ExprCloneWarning)]
    assert len(ours) == 1, [str(w.message) for w in caught]
    message = str(ours[0].message)
    assert message.startswith(f"{path}: ")
    for phrase in phrases:
        assert phrase in message
    return image


def load_silently(path: Path) -> np.ndarray:
    """load_image, asserting that it warns about nothing."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", ExprCloneWarning)
        return load_image(path)


def assert_rgb(image: np.ndarray, shape: tuple[int, int]) -> None:
    assert image.dtype == np.uint8
    assert image.shape == (*shape, 3)


# --- load_image: conversions -------------------------------------------------------------


def test_real_photo_loads_unchanged_and_silently(photo_path: Path) -> None:
    image = load_silently(photo_path)
    assert_rgb(image, (1350, 1350))
    with Image.open(photo_path) as reference:
        np.testing.assert_array_equal(image, np.asarray(reference.convert("RGB")))
    assert image.flags.writeable


def test_grayscale_is_expanded_to_three_equal_channels(photo: Image.Image, tmp_path: Path) -> None:
    gray = photo.convert("L")
    path = tmp_path / "gray.png"
    gray.save(path)
    image = load_with_warning(path, "grayscale")
    assert_rgb(image, (120, 162))
    for channel in range(3):
        np.testing.assert_array_equal(image[..., channel], np.asarray(gray))


def test_transparency_is_composited_over_white(photo: Image.Image, tmp_path: Path) -> None:
    alpha = np.full((120, 162), 255, np.uint8)
    alpha[:, :50] = 0  # transparent
    alpha[:, 50:100] = 128  # half transparent
    rgba = photo.copy()
    rgba.putalpha(Image.fromarray(alpha))
    path = tmp_path / "rgba.png"
    rgba.save(path)

    image = load_with_warning(path, "white")
    original = np.asarray(photo).astype(int)
    assert_rgb(image, (120, 162))
    assert (image[:, :50] == 255).all()
    half = (original[:, 50:100] * 128 + 255 * 127) / 255
    assert np.abs(image[:, 50:100] - half).max() <= 1
    np.testing.assert_array_equal(image[:, 100:], original[:, 100:])


def test_opaque_alpha_loads_silently(photo: Image.Image, tmp_path: Path) -> None:
    path = tmp_path / "opaque.png"
    photo.convert("RGBA").save(path)
    np.testing.assert_array_equal(load_silently(path), np.asarray(photo))


def test_cmyk_jpeg_is_converted(photo: Image.Image, tmp_path: Path) -> None:
    path = tmp_path / "cmyk.jpg"
    photo.convert("CMYK").save(path, quality=95)
    image = load_with_warning(path, "CMYK")
    assert_rgb(image, (120, 162))
    assert np.abs(image.astype(int) - np.asarray(photo)).mean() < 3


def test_16bit_grayscale_is_scaled_not_clipped(tmp_path: Path) -> None:
    values = np.zeros((40, 160), np.uint16)
    values[:, 40:80], values[:, 80:120], values[:, 120:] = 1000, 32768, 65535
    path = tmp_path / "gray16.png"
    Image.fromarray(values).save(path)
    with Image.open(path) as stored:
        assert stored.mode.startswith("I;16")  # really a 16-bit file

    image = load_with_warning(path, "16-bit")
    assert_rgb(image, (40, 160))
    # 1000 / 257 = 3.9: clipping would give 255 and dropping the low byte 3.
    assert [image[0, x, 0] for x in (0, 40, 80, 120)] == [0, 4, 128, 255]
    assert (image == image[..., :1]).all()


def test_48bit_rgb_png_is_scaled(photo: Image.Image, tmp_path: Path) -> None:
    expected = np.array(photo)
    deep = expected.astype(np.uint16) * 257
    deep[:40, :40] = (65535, 32768, 1000)
    expected[:40, :40] = (255, 128, 4)  # Pillow alone would give (255, 128, 3)
    path = tmp_path / "rgb48.png"
    assert cv2.imwrite(str(path), deep[..., ::-1])

    image = load_with_warning(path, "16-bit")
    np.testing.assert_array_equal(image, expected)


def test_exif_orientation_is_applied(photo: Image.Image, tmp_path: Path) -> None:
    plain, rotated = tmp_path / "plain.jpg", tmp_path / "exif6.jpg"
    photo.save(plain, quality=95)
    exif = Image.Exif()
    exif[0x0112] = 6  # stored image must be turned 90 degrees clockwise for display
    photo.save(rotated, quality=95, exif=exif)

    image = load_with_warning(rotated, "EXIF orientation")
    assert_rgb(image, (162, 120))
    np.testing.assert_array_equal(image, np.rot90(load_silently(plain), k=-1))
    clockwise = np.rot90(np.asarray(photo), k=-1).astype(int)
    assert np.abs(image - clockwise).mean() < 3
    assert np.abs(image - np.rot90(np.asarray(photo), k=1)).mean() > 20


def test_palette_image_loads_exactly_and_silently(photo: Image.Image, tmp_path: Path) -> None:
    palette = photo.convert("P", palette=Image.Palette.ADAPTIVE, colors=64)
    path = tmp_path / "palette.png"
    palette.save(path)
    np.testing.assert_array_equal(load_silently(path), np.asarray(palette.convert("RGB")))


# --- load_image: errors ------------------------------------------------------------------


def _missing(tmp_path: Path, photo_path: Path) -> Path:
    return tmp_path / "missing.jpg"


def _directory(tmp_path: Path, photo_path: Path) -> Path:
    return tmp_path


def _text_as_jpeg(tmp_path: Path, photo_path: Path) -> Path:
    path = tmp_path / "notes.jpg"
    path.write_text("not an image\n")
    return path


def _truncated_jpeg(tmp_path: Path, photo_path: Path) -> Path:
    data = photo_path.read_bytes()
    path = tmp_path / "truncated.jpg"
    path.write_bytes(data[: len(data) // 2])
    return path


def _heic(tmp_path: Path, photo_path: Path) -> Path:
    """The start of a phone's HEIC photo (its file-type box: brand heic, compatible mif1), which Pillow cannot read."""
    path = tmp_path / "IMG_0001.HEIC"
    path.write_bytes(b"\x00\x00\x00\x18ftypheic\x00\x00\x00\x00mif1heic" + bytes(64))
    return path


def _tiny_png(tmp_path: Path, photo_path: Path) -> Path:
    path = tmp_path / "tiny.png"
    Image.new("RGB", (20, 40)).save(path)
    return path


def _header_of_108_megapixels(tmp_path: Path, photo_path: Path) -> Path:
    """The sample photo with its JPEG header saying 12000x9000 pixels (a phone's 108 megapixels): decoding it would take
    324 MB before finding the data short; its size is refused from the header first."""
    data = bytearray(photo_path.read_bytes())
    frame = data.index(b"\xff\xc0")  # the start of the frame: its length, precision, then height and width
    data[frame + 5 : frame + 9] = (9000).to_bytes(2, "big") + (12000).to_bytes(2, "big")
    path = tmp_path / "huge.jpg"
    path.write_bytes(bytes(data))
    return path


@pytest.mark.parametrize(
    ("make", "problem"),
    [
        (_missing, "no such file"),
        (_directory, "is a directory"),
        (_text_as_jpeg, "not an image"),
        (_heic, "a HEIC photo, which cannot be read here: save it as JPEG or PNG"),
        (_truncated_jpeg, "corrupt or truncated"),
        (_tiny_png, "too small"),
        (_header_of_108_megapixels, "image is too large (12000x9000 pixels; at most 89.4785 megapixels)"),
    ],
)
def test_bad_input_raises_a_one_line_error_naming_the_file(make, problem, tmp_path, photo_path) -> None:
    path = make(tmp_path, photo_path)
    with pytest.raises(ExprCloneError) as error:
        load_image(path)
    message = str(error.value)
    assert message.startswith(f"{path}: ")
    assert problem in message
    assert "\n" not in message


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() == 0, reason="root can read anything")
def test_unreadable_file_raises(photo: Image.Image, tmp_path: Path) -> None:
    path = tmp_path / "secret.png"
    photo.save(path)
    path.chmod(0)
    with pytest.raises(ExprCloneError, match="permission denied"):
        load_image(path)


# --- save_image --------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("name", "tolerance"),
    [("out.png", 0), ("out.bmp", 0), ("out.tif", 0), ("out.TIFF", 0), ("out.jpg", 3), ("out.jpeg", 3), ("out.webp", 3)],
)
def test_round_trip(photo: Image.Image, tmp_path: Path, name: str, tolerance: float) -> None:
    original = np.asarray(photo)
    path = tmp_path / name
    save_image(path, original)
    loaded = load_silently(path)
    assert np.abs(loaded.astype(int) - original).mean() <= tolerance
    assert os.listdir(tmp_path) == [name]


def test_grayscale_array_is_saved(photo: Image.Image, tmp_path: Path) -> None:
    gray = np.asarray(photo.convert("L"))
    path = tmp_path / "gray.png"
    save_image(path, gray)
    np.testing.assert_array_equal(load_with_warning(path, "grayscale")[..., 1], gray)


def test_new_file_gets_ordinary_permissions(photo: Image.Image, tmp_path: Path) -> None:
    path = tmp_path / "out.png"
    old_umask = os.umask(0o022)
    try:
        save_image(path, np.asarray(photo))
    finally:
        os.umask(old_umask)
    assert path.stat().st_mode & 0o777 == 0o644


def test_existing_output_is_replaced(photo: Image.Image, tmp_path: Path) -> None:
    path = tmp_path / "out.png"
    path.write_bytes(b"old")
    save_image(path, np.asarray(photo))
    np.testing.assert_array_equal(load_silently(path), np.asarray(photo))
    assert os.listdir(tmp_path) == ["out.png"]


def test_overwriting_an_input_is_refused(photo: Image.Image, tmp_path: Path) -> None:
    source = tmp_path / "input.png"
    photo.save(source)
    before = source.read_bytes()
    (tmp_path / "sub").mkdir()
    (tmp_path / "alias.png").symlink_to(source)
    for output in (source, tmp_path / "sub" / ".." / "input.png", tmp_path / "alias.png"):
        with pytest.raises(ExprCloneError, match="overwrite input") as error:
            save_image(output, np.zeros((40, 40, 3), np.uint8), inputs=[str(source)])
        assert str(error.value).startswith(f"{output}: ")
    assert source.read_bytes() == before


def test_unknown_extension_writes_nothing(tmp_path: Path) -> None:
    path = tmp_path / "out.xyz"
    with pytest.raises(ExprCloneError, match=r"unknown output format '\.xyz'") as error:
        save_image(path, np.zeros((40, 40, 3), np.uint8))
    assert str(error.value).startswith(f"{path}: ")
    assert os.listdir(tmp_path) == []


def test_failed_encode_leaves_no_trace(photo: Image.Image, tmp_path: Path, monkeypatch) -> None:
    path = tmp_path / "out.png"
    path.write_bytes(b"previous result")

    def half_written(self, fp, *args, **kwargs):
        fp.write(b"\x89PNG partial")
        raise OSError("disk full")

    monkeypatch.setattr(Image.Image, "save", half_written)
    with pytest.raises(ExprCloneError, match="disk full") as error:
        save_image(path, np.asarray(photo))
    assert str(error.value).startswith(f"{path}: ")
    assert path.read_bytes() == b"previous result"
    assert os.listdir(tmp_path) == ["out.png"]


def test_missing_output_directory_fails_fast(tmp_path: Path) -> None:
    path = tmp_path / "no" / "such" / "out.png"
    with pytest.raises(ExprCloneError, match="does not exist") as error:
        check_output_path(path)
    assert str(error.value).startswith(f"{path}: ")
    assert str(tmp_path / "no" / "such") in str(error.value)
    with pytest.raises(ExprCloneError, match="does not exist"):
        save_image(path, np.zeros((40, 40, 3), np.uint8))


def test_directory_as_output_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "folder.png"
    path.mkdir()
    with pytest.raises(ExprCloneError, match="is a directory"):
        check_output_path(path)


def test_check_output_path_accepts_a_good_path(photo_path: Path, tmp_path: Path) -> None:
    check_output_path(tmp_path / "out.JPG", inputs=[photo_path])
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("bad", [np.zeros((40, 40, 3), np.float32), np.zeros((40, 40, 4), np.uint8), np.zeros(40, np.uint8)])
def test_wrong_array_is_a_programming_error(tmp_path: Path, bad: np.ndarray) -> None:
    with pytest.raises(ValueError):
        save_image(tmp_path / "out.png", bad)
    assert os.listdir(tmp_path) == []


#: what a process does with a FIFO given as each kind of input file (each would wait for a writer for ever, if opened).
FIFO_READS = """
import sys
from exprclone.errors import ExprCloneError
from exprclone.io.images import load_image
from exprclone.io.landmarks import read_landmarks
from exprclone.io.video import probe
for read in (load_image, lambda p: read_landmarks(p, (100, 100)), probe):
    try:
        read(sys.argv[1])
    except ExprCloneError as e:
        print(e)
"""


def test_a_fifo_is_refused_at_the_door_not_waited_on(tmp_path: Path) -> None:
    """A photo, a landmark file or a video that is a FIFO (nothing writes to it): one line each, at once (in a process of
    its own, so that a wait fails the test rather than hang it)."""
    import subprocess
    import sys

    fifo = tmp_path / "photo.json"
    os.mkfifo(fifo)
    done = subprocess.run([sys.executable, "-c", FIFO_READS, str(fifo)], capture_output=True, text=True, timeout=60)
    said = f"{fifo}: not a regular file (a FIFO, a socket or a device): give a file"
    assert done.stdout.splitlines() == [said] * 3, done
