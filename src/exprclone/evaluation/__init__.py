"""Scoring clones against real expressions.

:mod:`.scores` (landmark error, identity, teeth), :mod:`.london` (the London Set's
pairs), :mod:`.report` (``exprclone evaluate``'s tables and gallery) and
:mod:`.figures` (the sheet of ``exprclone compare``).
"""
