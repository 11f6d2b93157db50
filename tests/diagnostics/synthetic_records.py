"""Synthetic records the diagnostics tests share: a resonance struck by a fault's impacts
in noise, a ball fault gated by the load zone, noise with chosen envelope lines, passages
over a spall (entry and exit events), and a CWRU-named ``.mat`` file. Imported by name
(``from synthetic_records import ...``), as tests/synthetic_run.py is by the simulator's
tests."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from scipy.io import savemat

from diagnostics import BearingGeometry, bearing_frequencies

GEOMETRY = BearingGeometry(9, 7.94e-3, 39.04e-3)  # CWRU drive end, SKF 6205
SHAFT_HZ = 29.95
FREQS = bearing_frequencies(GEOMETRY, SHAFT_HZ)
FS = 12000.0


def fault_signal(
    fs: float,
    rate_hz: float,
    resonance_hz: float,
    amplitude: float = 3.0,
    duration_s: float = 2.0,
    mod_hz: float = 0.0,
    mod_depth: float = 0.0,
    jitter: float = 0.005,
    seed: int = 0,
) -> np.ndarray:
    """Decaying resonances struck at ``rate_hz`` (random period jitter), in unit white noise.

    With ``mod_hz`` the impact amplitude follows ``1 + mod_depth cos(2 pi mod_hz t)``, as an
    inner-race defect turning through the load zone.
    """
    rng = np.random.default_rng(seed)
    n = int(duration_s * fs)
    periods = (1.0 + jitter * rng.standard_normal(int(duration_s * rate_hz) + 10)) / rate_hz
    times = np.cumsum(periods)
    times = times[times < duration_s - 0.01]
    tail = np.arange(int(0.01 * fs)) / fs
    response = np.exp(-600.0 * tail) * np.sin(2 * np.pi * resonance_hz * tail)
    x = np.zeros(n)
    for t in times:
        i = int(round(t * fs))
        weight = amplitude * (1.0 + mod_depth * math.cos(2 * math.pi * mod_hz * t))
        x[i : i + response.size] += weight * response[: n - i]
    return x + rng.standard_normal(n)


def gated_ball_impacts(fs: float, seconds: float, jitter: float, seed: int) -> np.ndarray:
    """A damaged ball striking at 2 x BSF with a wandering spin axis (``jitter`` of random
    spacing, so the lines at 2 BSF smear), only while it is in the load zone: a third of
    each cage turn, once per FTF. Unit noise."""
    rng = np.random.default_rng(seed)
    n = int(seconds * fs)
    x = rng.standard_normal(n)
    tail = np.arange(int(0.004 * fs)) / fs
    ring = 4.0 * np.exp(-900.0 * tail) * np.sin(2 * np.pi * 3500.0 * tail)
    t = 0.01
    while t < seconds - 0.01:
        in_zone = np.mod(t * FREQS.ftf, 1.0) < 1.0 / 3.0
        if in_zone:
            i = int(t * fs)
            x[i : i + ring.size] += ring[: n - i]
        t += (1.0 + jitter * rng.standard_normal()) / (2.0 * FREQS.bsf)
    return x


def modulated_noise(lines: dict[float, float], seconds: float = 4.0, seed: int = 0, fs=FS):
    """Unit noise whose squared envelope is ``1 + sum(a cos 2 pi f t)`` (``lines``: f ->
    a): lines in its envelope spectrum at those frequencies alone, no harmonics."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(seconds * fs)) / fs
    power = 1.0 + sum(a * np.cos(2 * np.pi * f * t) for f, a in lines.items())
    return rng.standard_normal(t.size) * np.sqrt(power)


def impacts(fs: float, rate: float, seconds: float, seed: int) -> np.ndarray:
    """Resonance at 3 kHz struck at ``rate`` (1 % jitter) in unit noise."""
    return fault_signal(fs, rate, 3000.0, amplitude=4.0, duration_s=seconds, jitter=0.01,
                        seed=seed)  # fmt: skip


def cwru_file(folder: Path, name: str, number: int, de, fe, rpm=None) -> Path:
    """A ``.mat`` file as the CWRU data center names it: drive-end and fan-end channels
    ``XNNN_DE_time``, ``XNNN_FE_time`` and, given ``rpm``, ``XNNNRPM``."""
    variables = {f"X{number:03d}_DE_time": de[:, None], f"X{number:03d}_FE_time": fe[:, None]}
    if rpm is not None:
        variables[f"X{number:03d}RPM"] = np.array([[rpm]])
    path = folder / name
    savemat(path, variables)
    return path


def spall_record(
    fs: float,
    separation_s: float,
    duration_s: float = 1.0,
    noise: float = 0.1,
    seed: int = 0,
    race_rate_hz: float | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Acceleration of repeated passages over a spall, and the true exit times.

    Entry: the load is released, a downward step ringing at a 600 Hz mode. Exit, a time
    ``separation_s`` later: an impact ringing a 12 kHz resonance, and the load step back up.
    Passages repeat at ``race_rate_hz`` (default BPFO) with 0.3 % random period jitter.
    """
    rng = np.random.default_rng(seed)
    rate = race_rate_hz or bearing_frequencies(GEOMETRY, SHAFT_HZ).bpfo
    t = np.arange(int(duration_s * fs)) / fs
    x = np.zeros_like(t)
    exits = []
    te = 0.5 / rate
    while te < duration_s - 0.02:
        exits.append(te)
        te += (1.0 + 0.003 * rng.standard_normal()) / rate
    w_low = 2 * np.pi * 600.0
    for te in exits:
        for t0, sign in ((te - separation_s, -1.0), (te, 1.0)):
            tt = t[t >= t0] - t0
            x[t >= t0] += sign * np.exp(-0.3 * w_low * tt) * np.cos(w_low * tt)
        tt = t[t >= te] - te
        x[t >= te] += 3.0 * np.exp(-tt / 2e-4) * np.sin(2 * np.pi * 12000.0 * tt)
    return x + noise * rng.standard_normal(t.size), np.asarray(exits)
