"""The web page, the HTTP API and live mode (``exprclone serve``): to come."""
