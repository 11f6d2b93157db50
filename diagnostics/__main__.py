"""``python -m diagnostics``: see :mod:`diagnostics.cli`."""

from __future__ import annotations

import sys

from diagnostics.cli import main

if __name__ == "__main__":
    sys.exit(main())
