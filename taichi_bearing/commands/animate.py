"""`python -m taichi_bearing animate RUN_DIR`: an animation of the spall region from the
run's field frames (deformed mesh coloured by von Mises stress, the rollers passing
through the spall, the time of each frame), as a GIF (Pillow) or an MP4 (ffmpeg).

Only the standard library is imported at load (``--help`` answers at once); the drawing
is :mod:`taichi_bearing.post.animation`.
"""

from __future__ import annotations

import argparse
import math
import shutil

from taichi_bearing.errors import InputError

FORMATS = ("gif", "mp4")  # taichi_bearing.post.animation.FORMATS (not imported: numpy)
SMOOTH_MS = 0.02  # taichi_bearing.post.animation.SMOOTH_FRAME_INTERVAL_MS

EPILOG = (
    "The run writes a frame every run.frame_interval_ms (1 ms in the default case): too "
    "few for a smooth passage. Run the case with --set run.frame_interval_ms="
    f"{SMOOTH_MS:g} (a frame every {1e3 * SMOOTH_MS:g} us) for a smooth one, e.g. "
    "python -m taichi_bearing cases/validation/coarse_spall.yaml --set "
    f"run.frame_interval_ms={SMOOTH_MS:g} --out runs/coarse && python -m taichi_bearing "
    "animate runs/coarse"
)


def _number(text: str, *, low: float, strict: bool, what: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value) or value < low or (strict and value == low):
        raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}")
    return value


def _scale(text: str) -> float | None:
    if text.strip().lower() == "auto":
        return None
    return _number(text, low=0.0, strict=False, what="'auto' or a number >= 0")


def _positive(text: str) -> float:
    return _number(text, low=0.0, strict=True, what="a number > 0")


def _time_ms(text: str) -> float:
    return _number(text, low=-math.inf, strict=False, what="a time in ms")


def _count(text: str) -> int:
    value = _number(text, low=1.0, strict=False, what="an integer >= 1")
    if value != int(value):
        raise argparse.ArgumentTypeError(f"expected an integer >= 1, got {text!r}")
    return int(value)


def _pixels(text: str) -> int:
    value = _number(text, low=64.0, strict=False, what="an integer >= 64")
    if value != int(value) or value > 7680:
        raise argparse.ArgumentTypeError(f"expected an integer in [64, 7680], got {text!r}")
    return int(value)


def _point(text: str) -> tuple[float, float]:
    parts = text.split(",")
    try:
        x, y = (float(p) for p in parts)
    except ValueError:
        x = y = math.nan
    if not (math.isfinite(x) and math.isfinite(y)):
        raise argparse.ArgumentTypeError(f"expected X,Y in mm (e.g. 0,112), got {text!r}")
    return x, y


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.epilog = EPILOG
    parser.add_argument(
        "run_dir", metavar="RUN_DIR", help="run folder with field frames (frames/*.vtu)"
    )
    parser.add_argument(
        "--out",
        default=None,
        metavar="FILE",
        help="animation file (default RUN_DIR/animation.gif, or .mp4 with --format mp4)",
    )
    parser.add_argument(
        "--format",
        choices=FORMATS,
        default=None,
        help="gif (Pillow, always available) or mp4 (needs ffmpeg on the PATH); default: "
        "from the --out suffix, else gif",
    )
    parser.add_argument(
        "--scale",
        type=_scale,
        default=None,
        metavar="K|auto",
        help="elastic displacement scale (rigid motion of each part removed); 1 is the true "
        "deformed shape; default auto: the largest elastic displacement in view shows as "
        "about 4 %% of the window height (a 1-2-5 factor, stated in the title)",
    )
    parser.add_argument(
        "--fps", type=_positive, default=10.0, help="frames per second (default 10)"
    )
    parser.add_argument(
        "--from-ms", type=_time_ms, default=None, metavar="T", help="first frame time, ms"
    )
    parser.add_argument(
        "--to-ms", type=_time_ms, default=None, metavar="T", help="last frame time, ms"
    )
    parser.add_argument(
        "--every", type=_count, default=1, metavar="N", help="every N-th frame (default 1)"
    )
    parser.add_argument(
        "--center-mm",
        type=_point,
        default=None,
        metavar="X,Y",
        help="window centre in bearing coordinates, mm (x right, y up from the bearing "
        "centre), radial direction up; default: the spall, with the raceway at 35 %% of the "
        "height from the ring's side, and the window moves with the spall's ring",
    )
    parser.add_argument(
        "--width-mm",
        type=_positive,
        default=None,
        metavar="W",
        help="window width, mm (default: 3 roller diameters, or the spall and 2)",
    )
    parser.add_argument(
        "--height-mm",
        type=_positive,
        default=None,
        metavar="H",
        help="window height, mm (default 0.55 of the width)",
    )
    parser.add_argument(
        "--width-px",
        type=_pixels,
        default=960,
        metavar="PX",
        help="picture width in pixels, height 9/16 of it (default 960)",
    )


def _format(args: argparse.Namespace) -> str:
    if args.format is not None:
        return args.format
    suffix = str(args.out or "").rsplit(".", 1)[-1].lower() if args.out else ""
    return suffix if suffix in FORMATS else "gif"


def main(args: argparse.Namespace) -> int:
    from pathlib import Path

    from taichi_bearing.commands.common import check_empty, output_folder

    run_dir = check_empty(args.run_dir, "RUN_DIR")
    if not run_dir.is_dir():
        raise InputError(f"RUN_DIR {run_dir}: no such folder")
    fmt = _format(args)
    if fmt == "mp4":
        from matplotlib.animation import FFMpegWriter

        if not FFMpegWriter.isAvailable():
            found = shutil.which("ffmpeg")
            raise InputError(
                "--format mp4: ffmpeg "
                + ("does not run" if found else "not found on the PATH")
                + "; use --format gif (no ffmpeg needed)"
            )
    if args.from_ms is not None and args.to_ms is not None and args.from_ms > args.to_ms:
        raise InputError(f"--from-ms {args.from_ms:g} is after --to-ms {args.to_ms:g}")

    from taichi_bearing.post.animation import ANIMATION_FILES, animate_run

    out = run_dir / ANIMATION_FILES[fmt] if args.out is None else check_empty(args.out, "--out")
    if out.is_dir():
        raise InputError(f"--out {out}: a folder; give a file name (e.g. {out / 'a.gif'})")
    output_folder(out.parent, "--out")
    ms = 1e-3
    try:
        info = animate_run(
            run_dir,
            out,
            fmt=fmt,
            scale=args.scale,
            fps=args.fps,
            from_s=None if args.from_ms is None else args.from_ms * ms,
            to_s=None if args.to_ms is None else args.to_ms * ms,
            every=args.every,
            centre=None if args.center_mm is None else tuple(v * ms for v in args.center_mm),
            width=None if args.width_mm is None else args.width_mm * ms,
            height=None if args.height_mm is None else args.height_mm * ms,
            width_px=args.width_px,
        )
    except (FileNotFoundError, ValueError) as exc:
        raise InputError(f"RUN_DIR: {exc}") from None
    lo, hi = info["von_mises_range_Pa"]
    times = info["times_s"]
    print(
        f"wrote {Path(info['file'])}: {info['n_frames']} frames, "
        f"{1e3 * times[0]:.4g}-{1e3 * times[-1]:.4g} ms, {info['size_px'][0]}x"
        f"{info['size_px'][1]} px, displacement x{info['scale']:g}, von Mises "
        f"{lo / 1e6:.4g}-{hi / 1e6:.4g} MPa"
    )
    return 0
