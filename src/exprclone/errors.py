"""The one exception type (and warning type) a user of exprclone can cause."""

import contextlib
import os
import warnings
from collections.abc import Iterator


class ExprCloneError(ValueError):
    """Bad input: which input (``subject``) and what is wrong with it (``problem``).

    The core names inputs by their role (:data:`exprclone.roles.ROLES`, ``"method"``) and the
    outer layers by what the user gave (a file path, a form field); :meth:`about`
    re-words one into the other. The command line prints ``subject: problem`` on one
    line, the server answers it as JSON with status 400 or 422, and a batch report
    writes it in a row.

    Parameters
    ----------
    subject : str
        Which input: a photo's role (``"target_neutral"``), an option (``"strength"``), a
        form field, or a file's path.
    problem : str
        What is wrong with it, and where it helps, what to do.

    Attributes
    ----------
    subject, problem : str

    Examples
    --------
    >>> e = ExprCloneError("target_neutral", "no face found")
    >>> str(e), str(e.about({"target_neutral": "b.jpg"}))
    ('target_neutral: no face found', 'b.jpg: no face found')

    Any bad input to the public functions raises it:

    >>> import exprclone
    >>> from exprclone import data
    >>> try:
    ...     exprclone.clone(data.photo("126"), data.photo("126", "smile"), data.photo("003"), method="emd")
    ... except ExprCloneError as error:
    ...     print(error.subject, "|", error.problem)
    method | unknown method 'emd'; choose one of: global, local, elastic, global+eri, local+eri, elastic+eri, e+md, song
    """

    def __init__(self, subject: str | os.PathLike[str], problem: str) -> None:
        subject, problem = shortened(str(subject)), shortened(problem)
        super().__init__(f"{subject}: {problem}")
        self.subject, self.problem = subject, problem

    def about(self, names: dict[str, str]) -> "ExprCloneError":
        """The same problem, of the same type, with the subject re-named by ``names``.

        Parameters
        ----------
        names : dict of str to str
            New names of subjects; a subject not in it is kept.

        Returns
        -------
        ExprCloneError
        """
        return type(self)(names.get(self.subject, self.subject), self.problem)

    def __reduce__(self) -> tuple[type["ExprCloneError"], tuple[str, str]]:
        """Pickled as its subject and problem, so it crosses into and out of worker processes whole."""
        return type(self), (self.subject, self.problem)


#: the longest subject or problem an error says, in characters: what a client sent is not echoed whole.
MAX_SAID = 400
#: the longest value an error quotes (:func:`quoted`), in characters.
MAX_QUOTED = 40


def shortened(text: str, longest: int = MAX_SAID) -> str:
    """``text`` on one line, cut to ``longest`` characters (an ellipsis where it was cut)."""
    text = text.replace("\n", " ").replace("\r", " ")
    return text if len(text) <= longest else f"{text[: longest - 1]}…"


def quoted(value: object, longest: int = MAX_QUOTED) -> str:
    """``repr(value)`` as an error quotes a bad value: at most ``longest`` characters of it.

    >>> quoted("x" * 100)
    "'xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx…"
    """
    return shortened(repr(value), longest)


class NoFaceError(ExprCloneError):
    """An input that is a good image or video, but shows no face where one is needed."""


@contextlib.contextmanager
def naming(names: dict[str, str]) -> Iterator[None]:
    """Re-word the ExprCloneErrors raised inside: their subjects re-named by ``names`` (:meth:`ExprCloneError.about`)."""
    try:
        yield
    except ExprCloneError as e:
        raise e.about(names) from None


class ExprCloneWarning(UserWarning):
    """Input that was handled but deserves the user's attention (several faces, converted photo)."""


def one_face(found: int, subject: str, advice: str, stacklevel: int = 2) -> None:
    """What a landmarker says of the ``found`` faces in ``subject``: none is a :class:`NoFaceError`
    (with ``advice``), several an :class:`ExprCloneWarning` (the largest is used).

    ``stacklevel`` counts from the landmarker's method that calls this, as in :func:`warnings.warn`.
    """
    if not found:
        raise NoFaceError(subject, f"no face found ({advice})")
    if found > 1:
        warnings.warn(f"{subject}: {found} faces found, using the largest", ExprCloneWarning, stacklevel=stacklevel + 1)
