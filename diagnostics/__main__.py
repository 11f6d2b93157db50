"""``python -m diagnostics`` and the ``bearing-diagnostics`` script: see
:mod:`diagnostics.app.cli`."""

from __future__ import annotations

import sys

from diagnostics.app.cli import main

if __name__ == "__main__":
    sys.exit(main())
