"""The three photos of a clone, by role: how errors, landmark records, files and form fields name them.

Pure data, like :mod:`exprclone.methods`: the command line builds its arguments from it
without loading numpy.

>>> ROLES
('source_neutral', 'source_expression', 'target_neutral')
"""

from __future__ import annotations

#: the source person's neutral photo, the same person's photo with the expression, and the target person's neutral photo.
ROLES = ("source_neutral", "source_expression", "target_neutral")
SOURCE_NEUTRAL, SOURCE_EXPRESSION, TARGET_NEUTRAL = ROLES
