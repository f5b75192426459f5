"""Image files in and out, at the edge of the package.

Inside exprclone an image is a numpy array of shape (H, W, 3), dtype uint8, RGB order.
:func:`load_image` turns any image file Pillow can read into that form, and
:func:`save_image` writes one atomically, so no half-written output ever exists.
"""

from __future__ import annotations

import io
import os
import stat
import tempfile
import warnings
from collections.abc import Callable, Iterable
from typing import IO

import cv2
import numpy as np
from PIL import ExifTags, Image, ImageFile, ImageOps, UnidentifiedImageError

from ..errors import ExprCloneError, ExprCloneWarning

PathLike = str | os.PathLike[str]

MIN_SIDE = 32
"""Smallest width and height, in pixels, that :func:`load_image` accepts."""
MAX_ASPECT = 8
"""Largest ratio of an image's long side to its short one: a face photo is never a strip, and a strip shrunk to the
detector's 512 pixels (or a video's 16) would keep no rows at all."""

_FORMATS: dict[str, tuple[str, dict[str, int]]] = {
    # zlib level 1: three times faster than Pillow's default 6 on a 1350-pixel photo (64 against 187 ms), the file 17% larger
    ".png": ("PNG", {"compress_level": 1}),
    ".jpg": ("JPEG", {"quality": 95}),
    ".jpeg": ("JPEG", {"quality": 95}),
    ".bmp": ("BMP", {}),
    ".tif": ("TIFF", {}),
    ".tiff": ("TIFF", {}),
    ".webp": ("WEBP", {"quality": 95}),
}
#: the photo files a folder of photos may hold (batch targets, eigenface training photos): the formats :func:`save_image` writes.
PHOTO_SUFFIXES = frozenset(_FORMATS)
_GRAY_MODES = {"1", "L", "LA", "La"}
_PLAIN_MODES = _GRAY_MODES | {"RGB", "RGBA", "RGBa", "RGBX", "P", "PA"}


def load_image(path: PathLike | bytes, *, name: str | None = None, max_pixels: int | None = None) -> np.ndarray:
    """Read an image file as 8-bit RGB, upright according to its EXIF orientation.

    Transparent areas are composited over white; grayscale, palette, CMYK and
    16-bit or floating-point images are converted. A conversion the user should
    know about is reported by one :class:`ExprCloneWarning` naming the file.

    Parameters
    ----------
    path : str, os.PathLike or bytes
        The image file, or its content; any format Pillow reads.
    name : str, optional
        What to call it in messages (by default the path, or ``image`` for content).
    max_pixels : int, optional
        Refuse larger images before decoding them (a guard against decompression bombs); by default Pillow's own
        bound, ``PIL.Image.MAX_IMAGE_PIXELS`` (89.5 megapixels, which Pillow would only warn of up to twice that, after
        decoding), read from the file's header too.

    Returns
    -------
    numpy.ndarray
        Array of shape (H, W, 3), dtype uint8, RGB order.

    Raises
    ------
    ExprCloneError
        If the file is missing, not a regular file (:func:`check_file`), unreadable, not an image, corrupt or
        truncated, smaller than ``MIN_SIDE`` pixels on a side, longer than ``MAX_ASPECT`` times its width
        (or wider than that times its height), or larger than ``max_pixels``.
    """
    name = ("image" if isinstance(path, bytes) else str(path)) if name is None else name
    image, rawmode = _open(path, name, max_pixels)
    with image:
        notes = []
        if image.mode in ("RGB", "RGBA") and ";16" in rawmode:
            image.frombytes(_read_16bit_colour(path, name, image).tobytes())
            notes.append("16-bit colour reduced to 8 bits per channel")
        orientation = image.getexif().get(ExifTags.Base.Orientation, 1)
        if orientation in range(2, 9):
            notes.append(f"turned upright as its EXIF orientation ({orientation}) asks")
        rgb = _to_rgb(ImageOps.exif_transpose(image) if orientation in range(2, 9) else image, rawmode, notes)
    if notes:
        warnings.warn(f"{name}: {'; '.join(notes)}", ExprCloneWarning, stacklevel=2)
    return rgb


def check_size(width: int, height: int, name: str, max_pixels: int | None = None) -> None:
    """An image's size as its header gives it, checked before its pixels are decoded.

    Raises
    ------
    ExprCloneError
        About ``name``: a side under :data:`MIN_SIDE`, sides in a ratio over :data:`MAX_ASPECT`,
        or more than ``max_pixels`` pixels (a guard against decompression bombs).

    Examples
    --------
    >>> check_size(32, 40000, "strip.png")
    Traceback (most recent call last):
    ...
    exprclone.errors.ExprCloneError: strip.png: image is too narrow (32x40000 pixels; the long side may be at most 8 times the short one)
    """
    if min(width, height) < MIN_SIDE:
        raise ExprCloneError(name, f"image is too small ({width}x{height} pixels; at least {MIN_SIDE} on each side needed)")
    if max(width, height) > MAX_ASPECT * min(width, height):
        problem = f"the long side may be at most {MAX_ASPECT} times the short one"
        raise ExprCloneError(name, f"image is too {'narrow' if height > width else 'flat'} ({width}x{height} pixels; {problem})")
    if max_pixels is not None and width * height > max_pixels:
        raise ExprCloneError(name, f"image is too large ({width}x{height} pixels; at most {max_pixels / 1e6:g} megapixels)")


def check_file(path: PathLike, name: str | None = None) -> None:
    """An input file checked before it is opened: ExprCloneError about ``name`` (the path by default) for a directory, or
    for anything else that is not a regular file (a FIFO, whose opening would wait for a writer for ever; a socket; a
    device). A path that cannot be looked at is left to the opening, whose error says why.
    """
    try:
        mode = os.stat(path).st_mode
    except (OSError, ValueError):
        return
    name = str(path) if name is None else name
    if stat.S_ISDIR(mode):
        raise ExprCloneError(name, "is a directory")
    if not stat.S_ISREG(mode):
        raise ExprCloneError(name, "not a regular file (a FIFO, a socket or a device): give a file")


def check_output_path(path: PathLike, inputs: Iterable[PathLike] = (), extensions: Iterable[str] | None = None) -> None:
    """Check, before any work is done, that an output file can be written at ``path``.

    Parameters
    ----------
    path : str or os.PathLike
        The output file; its extension chooses the format.
    inputs : iterable of str or os.PathLike
        Input files that the output must not overwrite.
    extensions : iterable of str, optional
        Allowed extensions (with the dot); the image formats by default.

    Raises
    ------
    ExprCloneError
        If the extension is not a known image format, ``path`` is one of
        ``inputs`` or a directory, or its directory is missing or not writable.
    """
    extension = os.path.splitext(path)[1].lower()
    allowed = list(_FORMATS) if extensions is None else list(extensions)
    if extension not in allowed:
        listed = f"{', '.join(allowed[:-1])} or {allowed[-1]}" if len(allowed) > 1 else allowed[0]
        raise ExprCloneError(path, f"unknown output format '{extension}' (use {listed})")
    if any(_same_file(path, source) for source in inputs):
        raise ExprCloneError(path, "output would overwrite input file")
    if os.path.isdir(path):
        raise ExprCloneError(path, "is a directory")
    directory = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(directory):
        raise ExprCloneError(path, f"output directory {directory} does not exist")
    if not os.access(directory, os.W_OK | os.X_OK):
        raise ExprCloneError(path, f"output directory {directory} is not writable")


def save_image(path: PathLike, image: np.ndarray, *, inputs: Iterable[PathLike] = ()) -> None:
    """Write an image atomically: the file at ``path`` is either complete or untouched.

    Parameters
    ----------
    path : str or os.PathLike
        The output file; its extension (.png, .jpg, .jpeg, .bmp, .tif, .tiff,
        .webp) chooses the format. JPEG and WebP are written at quality 95.
    image : numpy.ndarray
        uint8 array of shape (H, W, 3) in RGB order, or (H, W) grayscale.
    inputs : iterable of str or os.PathLike
        Input files that the output must not overwrite.

    Raises
    ------
    ExprCloneError
        If :func:`check_output_path` rejects ``path`` or the file cannot be written.
        Also if ``image`` is not a uint8 array of shape (H, W, 3) or (H, W).
    """
    check_output_path(path, inputs)
    if image.dtype != np.uint8 or not (image.ndim == 2 or image.shape[2:] == (3,)):
        raise ExprCloneError(path, f"expected a uint8 (H, W, 3) or (H, W) image, got {image.dtype} {image.shape}")
    atomic_write(path, lambda f: _encode(image, os.path.splitext(path)[1], f))


def encode_image(image: np.ndarray, extension: str) -> bytes:
    """An image encoded in the format of a file ``extension`` (``.png``, ``.jpg``, ...), as :func:`save_image` writes it.

    Parameters
    ----------
    image : numpy.ndarray
        uint8 array of shape (H, W, 3) in RGB order, or (H, W) grayscale.
    extension : str
        One of the extensions :func:`save_image` knows.
    """
    out = io.BytesIO()
    _encode(image, extension, out)
    return out.getvalue()


def _encode(image: np.ndarray, extension: str, out: IO[bytes]) -> None:
    image_format, options = _FORMATS[extension.lower()]
    Image.fromarray(image).save(out, format=image_format, **options)


def atomic_write(path: PathLike, write: Callable[[IO[bytes]], object]) -> None:
    """Write a file through ``write(file)`` so that ``path`` is either complete or untouched.

    The data goes to a temporary file in the same folder, is flushed to disk, then
    renamed over ``path``; on any failure the temporary file is removed.

    Raises
    ------
    ExprCloneError
        If the file cannot be written.
    """
    directory, name = os.path.split(os.path.abspath(path))
    try:
        temporary = tempfile.NamedTemporaryFile(dir=directory, prefix=f".{name}.", suffix=os.path.splitext(name)[1], delete=False)
    except OSError as exc:
        raise ExprCloneError(path, f"cannot be written ({exc.strerror})") from exc
    try:
        with temporary:
            write(temporary)
            temporary.flush()
            os.fsync(temporary.fileno())
        os.chmod(temporary.name, _new_file_mode())
        os.replace(temporary.name, path)
    except BaseException as exc:
        os.unlink(temporary.name)
        if isinstance(exc, (OSError, ValueError)):
            raise ExprCloneError(path, f"cannot be written ({exc})") from exc
        raise


def _open(path: PathLike | bytes, name: str, max_pixels: int | None) -> tuple[Image.Image, str]:
    """Open ``path`` (or content) and decode its pixels; return the image and the raw mode it was stored in."""
    if not isinstance(path, bytes):
        check_file(path, name)
    image = None
    try:
        with warnings.catch_warnings():  # Pillow's alarm at a large header: the size is checked next, before decoding
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            image = Image.open(io.BytesIO(path) if isinstance(path, bytes) else path)
        check_size(image.width, image.height, name, Image.MAX_IMAGE_PIXELS if max_pixels is None else max_pixels)
        rawmode = _stored_rawmode(image)
        image.load()
    except (OSError, SyntaxError, ValueError, EOFError, Image.DecompressionBombError) as exc:
        if image is not None:
            image.close()
        if isinstance(exc, ExprCloneError):
            raise
        raise _read_error(name, exc, max_pixels, _heif(path) if isinstance(exc, UnidentifiedImageError) else False) from exc
    return image, rawmode


#: the brands an ISO base media file names in its first box (``ftyp``) when it holds a HEIF photo of HEVC tiles, as
#: phones take them (AVIF, which Pillow reads, names its own).
HEIF_BRANDS = (b"heic", b"heix", b"heim", b"heis", b"hevc", b"hevx", b"mif1", b"msf1")


def _heif(path: PathLike | bytes) -> bool:
    """Whether the file (or content) begins as a HEIF photo does (:data:`HEIF_BRANDS`)."""
    if isinstance(path, bytes):
        head = path[:12]
    else:
        try:
            with open(path, "rb") as file:
                head = file.read(12)
        except OSError:  # (gone since Pillow read it: the error says what Pillow found)
            return False
    return head[4:8] == b"ftyp" and head[8:12] in HEIF_BRANDS


def _stored_rawmode(image: ImageFile.ImageFile) -> str:
    """Pillow's name for the pixel layout in the file (such as 'RGB;16B'); read before loading."""
    if not image.tile:
        return ""
    args = image.tile[0][3]
    return args[0] if isinstance(args, tuple) else str(args)


def _read_error(name: str, exc: BaseException, max_pixels: int | None = None, heif: bool = False) -> ExprCloneError:
    """The ExprCloneError for a failure to open or decode the image called ``name`` (its size bounded by ``max_pixels``;
    ``heif``: a HEIF photo, which Pillow cannot read)."""
    if isinstance(exc, FileNotFoundError):
        problem = "no such file"
    elif isinstance(exc, PermissionError):
        problem = "cannot be read (permission denied)"
    elif isinstance(exc, UnidentifiedImageError) and heif:
        problem = "a HEIC photo, which cannot be read here: save it as JPEG or PNG (a phone can take photos as JPEG)"
    elif isinstance(exc, UnidentifiedImageError):
        problem = "not an image (cannot be read by Pillow)"
    elif isinstance(exc, Image.DecompressionBombError):  # Pillow's own guard, in its header: said as check_size says it
        limit = max_pixels or Image.MAX_IMAGE_PIXELS or 0
        problem = f"image is too large (at most {limit / 1e6:g} megapixels)"
    elif isinstance(exc, OSError) and exc.errno is not None:
        problem = f"cannot be read ({exc.strerror})"
    else:
        problem = f"image data is corrupt or truncated ({exc})"
    return ExprCloneError(name, problem)


def _read_16bit_colour(path: PathLike | bytes, name: str, image: Image.Image) -> np.ndarray:
    """Read the 16-bit RGB(A) pixels Pillow truncates, scaled to uint8 in Pillow's channel order."""
    try:
        raw = np.frombuffer(path, np.uint8) if isinstance(path, bytes) else np.fromfile(path, dtype=np.uint8)
        data = cv2.imdecode(raw, cv2.IMREAD_UNCHANGED)
    except OSError as exc:
        raise _read_error(name, exc) from exc
    bands = len(image.getbands())
    if data is None or data.dtype != np.uint16 or data.shape != (image.height, image.width, bands):
        raise ExprCloneError(name, "image data is corrupt or truncated (16-bit colour)")
    rgb_order = [2, 1, 0, 3][:bands]  # OpenCV reads BGR(A)
    return _scale_to_uint8(data[..., rgb_order], 65535)


def _to_rgb(image: Image.Image, rawmode: str, notes: list[str]) -> np.ndarray:
    """Convert an upright image of any mode to an RGB array, appending to ``notes`` what changed."""
    mode = image.mode
    if mode in ("I", "F") or mode.startswith("I;16"):
        image = Image.fromarray(_deep_gray_to_uint8(image, rawmode, notes))
    elif mode not in _PLAIN_MODES:
        notes.append(f"converted from {mode} to RGB")
    if image.mode in _GRAY_MODES:
        notes.append("grayscale expanded to RGB")
    if image.mode in ("RGBA", "RGBa", "LA", "La", "PA") or "transparency" in image.info:
        rgba = image.convert("RGBA")
        # an RGBA image's extrema are four (min, max) pairs, one per band; Pillow's stubs cannot tell them from one band's
        if rgba.getextrema()[3][0] < 255:  # type: ignore[misc]
            notes.append("transparent areas composited over white")
        image = Image.alpha_composite(Image.new("RGBA", rgba.size, "white"), rgba)
    # an RGB image needs no conversion (converting would copy it twice: 10 ms of 15 at 1350 px)
    return np.array(np.asarray(image if image.mode == "RGB" else image.convert("RGB")))


def _deep_gray_to_uint8(image: Image.Image, rawmode: str, notes: list[str]) -> np.ndarray:
    """Scale 16-bit, 32-bit integer or floating-point grayscale to uint8 by its full range.

    Integers use the full range of their bit depth (65535 or 2**31 - 1; negatives
    become black). Floats are taken as 0..1 if none exceeds 1, else as 0..255.
    """
    values = np.asarray(image, dtype=np.float64)
    if image.mode == "F":
        values = np.nan_to_num(values)
        full_scale = 1.0 if values.max() <= 1.0 else 255.0
        notes.append(f"floating-point grayscale (0..{full_scale:g}) scaled to 8 bits")
    elif "16" in image.mode + rawmode:
        full_scale = 65535
        notes.append("16-bit grayscale scaled to 8 bits")
    else:
        full_scale = 2**31 - 1
        notes.append("32-bit grayscale scaled to 8 bits")
    return _scale_to_uint8(values, full_scale)


def _scale_to_uint8(values: np.ndarray, full_scale: float) -> np.ndarray:
    """Map 0..full_scale linearly to 0..255, rounding and clipping."""
    return np.clip(np.rint(values * (255.0 / full_scale)), 0, 255).astype(np.uint8)


def _same_file(path: PathLike, other: PathLike) -> bool:
    """Whether two paths name one file (symlinks and hard links included)."""
    try:
        return os.path.samefile(path, other)
    except OSError:  # one of them does not exist yet
        return os.path.realpath(path) == os.path.realpath(other)


def _new_file_mode() -> int:
    """Permissions for a new file under the current umask (temporary files get 0o600)."""
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask
