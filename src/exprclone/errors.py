"""The one exception type (and warning type) a user of exprclone can cause."""


class ExprCloneError(Exception):
    """Bad input: a message that names the file and the problem, fit for one line on stderr."""


class ExprCloneWarning(UserWarning):
    """Input that was handled but deserves the user's attention (several faces, converted photo)."""
