"""What a wrong shaft speed costs the diagnosis, with and without the check on the record's
own shaft lines (``diagnose(..., correct_speed=True)``, the default).

Every development record (CWRU, MFPT) is diagnosed at its file's speed times each factor,
as a speed read off a name plate or a nominal value would be, and every CWRU record's other
accelerometer with the other end's (healthy) bearing, where the right verdict is ``none``.
The table gives the records named right of each set, with the check off and on. Usage::

    python benchmarks/diagnostics/speed_error_scan.py [DATA] [--factors 0.96 0.98 1 1.02 1.04]

``DATA`` is the folder holding ``cwru/``, ``cwru48k/`` and ``mfpt/`` (default
``../shared/data``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
if __name__ == "__main__":  # run as a script: the repository's packages by name
    sys.path.insert(0, str(ROOT))

from diagnostics import diagnose  # noqa: E402
from diagnostics.app.benchmark import find_records, run_benchmark  # noqa: E402


def scaled(factor: float):
    """``diagnose`` told a shaft rate ``factor`` times the file's."""

    def run(x, fs, geometry, shaft_hz, **options):
        return diagnose(x, fs, geometry, factor * shaft_hz, **options)

    return run


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("data", nargs="?", default=str(ROOT.parent / "shared" / "data"))
    parser.add_argument(
        "--factors", type=float, nargs="+", default=[0.96, 0.98, 0.99, 1.0, 1.01, 1.02, 1.04]
    )
    args = parser.parse_args(argv)
    data = Path(args.data)
    folders = [data / name for name in ("cwru", "cwru48k", "mfpt") if (data / name).is_dir()]
    if not folders:
        print(f"error: no cwru/, cwru48k/ or mfpt/ in {data}", file=sys.stderr)
        return 2
    paths = [p for folder in folders for p in find_records(folder)]
    print(f"{len(paths)} records from {', '.join(str(f) for f in folders)}")
    print("right verdicts with the speed given times a factor; check off -> on")
    print(f"{'factor':>7}  {'faults and healthy record':>26}  {'other-end checks':>17}")
    for factor in args.factors:
        cells = []
        for other in (False, True):
            counts = []
            for correct in (False, True):
                results = run_benchmark(
                    paths, scaled(factor), other_bearing=other, correct_speed=correct
                )
                counts.append(f"{sum(r.correct for r in results)}/{len(results)}")
            cells.append(" -> ".join(counts))
        print(f"{factor:>7.3f}  {cells[0]:>26}  {cells[1]:>17}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
