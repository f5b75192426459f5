"""The HTTP API, a router per topic (FastAPI's "bigger applications"): :mod:`.clone` (a clone, a compare sheet, a
photo's landmarks and faces), :mod:`.edits` (a clone prepared once, rendered as sliders move), :mod:`.editor` (the
expression editor: a photo prepared once, rendered as its controls move), :mod:`.video` (video jobs), :mod:`.live`
(the WebSocket), :mod:`.samples` (the samples and built-in expressions shipped), :mod:`.options` (the options
described, which the page draws its controls from), :mod:`.health` and :mod:`.pages` (the page, the live page and the
editor's). Each route reads and checks its request (:mod:`.uploads`), hands the work to the server's machinery
(:mod:`exprclone.server.runtime`) and answers a typed model (:mod:`exprclone.server.answers`) or a file.
"""

from fastapi import APIRouter

from . import clone, editor, edits, health, live, options, pages, samples, video

#: every router of the application, in the order the schema lists their paths.
ROUTERS: tuple[APIRouter, ...] = tuple(m.router for m in (pages, health, samples, options, clone, edits, editor, video, live))
