"""``python -m exprclone``: the same as the ``exprclone`` command."""

import sys

from .cli import main

sys.exit(main())
