"""What the tests, the tools and the benchmarks share to try the product as a user would: a real server on a free port
(:mod:`.servers`) and a real browser (:mod:`.browser`), as :mod:`numpy.testing` serves NumPy's. They need the test
dependencies (``pip install 'exprclone[test]'``: httpx, Playwright) and Debian's Chromium and nginx."""
