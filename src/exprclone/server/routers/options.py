"""The options described (``GET /api/options``): what the page draws its controls from (:mod:`exprclone.server.described`)."""

from __future__ import annotations

from fastapi import APIRouter

from ..described import OptionsAnswer, options_answer

router = APIRouter(tags=["options"])


@router.get("/api/options")
async def options() -> OptionsAnswer:
    """Every option: its ``name`` in Python and ``key`` in forms and live messages, its ``kind``, ``default``, the
    ``choices`` allowed, its ``minimum`` and ``maximum`` or ``pattern`` (as the form fields' schema says them), its
    ``help`` and command line ``flag``, and how a page shows it (``page``: a label, a plain sentence, the values a menu
    offers in words: the methods with their panel letters, the lambdas the DB metric searches); the live WebSocket's
    output sizes."""
    return options_answer()
