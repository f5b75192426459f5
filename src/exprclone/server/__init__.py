"""The web page, the HTTP API and live mode (``exprclone serve``).

From the bottom up: what the routes and the machinery share (:mod:`.work`, the CPU work run in worker processes;
:mod:`.session`, a live session; :mod:`.settings`; :mod:`.forms`, the options as form fields; :mod:`.answers` and
:mod:`.described`, the typed answers; :mod:`.openapi`, the schema's errors and its offline pages), the machinery
(:mod:`.runtime`: worker pools, jobs, edits, limits, the live protocol and its host processes), the routes
(:mod:`.routers`, a router per topic) and the application that mounts them (:mod:`.app`). ``tests/test_architecture.py``
checks that no part imports one above it.
"""
