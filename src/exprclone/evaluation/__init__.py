"""Scoring clones against real expressions.

:mod:`.scores` (landmark error, identity, teeth), :mod:`.blendshape_judge` (how close an
expression is to the one asked for, by MediaPipe's blendshapes), :mod:`.london` (the London Set's
pairs), ``exprclone evaluate``'s :mod:`.runner` (every method on many pairs, scored),
:mod:`.statistics` (summaries, pair-by-pair comparisons) and :mod:`.report` (its tables,
files and gallery), and :mod:`.figures` (the sheet of ``exprclone compare``).
"""
