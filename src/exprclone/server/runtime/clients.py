"""Who a request comes from, for each client's share of the server (:data:`Client`): the API key it sends, when the
operator has given the server keys (``serve --api-keys FILE``), else its address.

A key identifies one client wherever it connects from (several people behind one address, each with a key of their
own, each get a share); a request without a key is its address's; a key the server does not know is refused (401),
so that no one makes up keys to get more shares. The server keeps the keys' SHA-256 digests only, and a client is
named by a short digest (of its key, or of its address), never by the key itself: that name is what the Dask cluster
stores beside a client's video jobs. The address is the connection's, or behind a proxy trusted with
``--forwarded-allow-ips`` the one the proxy says (uvicorn reads ``X-Forwarded-For`` from those addresses only).
"""

from __future__ import annotations

import hashlib
from pathlib import Path
from typing import Annotated

from fastapi import Depends, Header
from starlette.requests import HTTPConnection

from ...errors import ExprCloneError

#: the header that carries an API key.
HEADER = "X-API-Key"
#: the fewest characters a key may have.
MIN_KEY = 16


class UnknownKey(ExprCloneError):
    """A request with an API key the server does not know: answered 401 (a live session: refused as any bad start)."""


def digest(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()


def read_keys(path: str) -> frozenset[str]:
    """The digests of the API keys in the file ``path``: one key a line, blank lines and ``#`` comments aside, each of at
    least :data:`MIN_KEY` characters; ExprCloneError about the file otherwise."""
    try:
        lines = Path(path).read_text().splitlines()
    except (OSError, UnicodeDecodeError) as e:
        raise ExprCloneError(path, f"cannot be read ({e})") from None
    keys = [line.strip() for line in lines if line.strip() and not line.strip().startswith("#")]
    short = [number for number, key in enumerate(keys, 1) if len(key) < MIN_KEY or any(c.isspace() for c in key)]
    if not keys or short:
        raise ExprCloneError(path, f"must hold API keys, one a line, each of at least {MIN_KEY} characters and no spaces")
    return frozenset(map(digest, keys))


def client_of(connection: HTTPConnection, key: str | None, keys: frozenset[str]) -> str:
    """The name of the client of ``connection`` that sent ``key`` (None: no key), with the server's ``keys`` (digests):
    ``key <digest>`` or ``address <digest>`` (:class:`UnknownKey` for a key not among them; a key sent to a server
    with none is not looked at)."""
    if key is not None and keys:
        found = digest(key)
        if found not in keys:
            raise UnknownKey(HEADER, "not a key this server knows")
        return f"key {found[:16]}"
    address = connection.client.host if connection.client else ""
    return f"address {digest(address)[:16]}"


#: the header's parameter, as the schema describes it.
KeyHeader = Annotated[
    str | None,
    Header(alias=HEADER, max_length=256, description="an API key the operator gave this client (serve --api-keys); none: its address"),
]


def the_client(connection: HTTPConnection, key: KeyHeader = None) -> str:
    """A request's client (:func:`client_of`): a FastAPI dependency."""
    keys: frozenset[str] = connection.app.state.work.settings.api_keys
    return client_of(connection, key, keys)


#: a route's parameter for who its request comes from (:func:`the_client`); the header is described in the schema.
Client = Annotated[str, Depends(the_client)]
