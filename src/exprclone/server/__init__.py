"""The web page, the HTTP API and live mode (``exprclone serve``): :mod:`.app` (the application), :mod:`.api` (the
routes and the page), :mod:`.live` (the WebSocket), :mod:`.work` (the CPU work, in worker processes)."""
