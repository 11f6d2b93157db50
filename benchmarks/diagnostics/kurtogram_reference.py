"""Straightforward port of Antoni's fast kurtogram (Fast_Kurtogram.m, revision 12-2014).

This is the baseline the fast implementation in ``diagnostics._kurtosis`` is checked and timed
against. It follows the reference arithmetic step by step: every band is filtered at the full
input rate with ``scipy.signal.lfilter`` (MATLAB ``filter``) and only then decimated, the
tree is walked recursively, and the map and best band are built as the reference builds them.
It is deliberately plain, not fast.

Facts carried over from the reference (J. Antoni, "Fast computation of the kurtogram for the
detection of transient faults", MSSP 21 (2007) 108-124, and its published MATLAB code):

- generating filters: ``h = fir1(16, 0.4) * exp(2i pi n / 8)``, the high band
  ``g[k] = h[15 - k] * (-1)**(k + 1)`` (16 taps), and the 1/3-band prototype
  ``fir1(24, 0.4 * 2/3)`` modulated by ``exp(2i pi n / 12)``, ``exp(2i pi n / 4)`` and
  ``exp(2i pi n * 5/12)``;
- a binary split keeps samples 2, 4, 6, ... (1-based) of each filter output, the high band is
  multiplied by ``(-1)**j`` (j from 1); a ternary split keeps samples 3, 6, 9, ...;
- the kurtosis of a band skips its first ``len(h)`` - 1 = 16 samples (15 for the high band);
- kurtosis of the complex envelope: mean removed, ``mean|c|^4 / mean(|c|^2)^2 - 2`` (``- 3``
  for the real input at level 0), 0 when the band power is below machine epsilon;
- negative values are set to 0; the best cell is the first maximum scanning columns.
"""

from __future__ import annotations

import numpy as np
from scipy import signal

EPS = np.finfo(float).eps


def reference_filters():
    """Return (h, g, h1, h2, h3), the reference's analysis filters."""
    n = np.arange(17)
    h = signal.firwin(17, 0.4) * np.exp(2j * np.pi * n * 0.125)
    g = h[15::-1] * (-1.0) ** (np.arange(16) + 1)
    n3 = np.arange(25)
    h1 = signal.firwin(25, 2.0 / 3.0 * 0.4) * np.exp(2j * np.pi * n3 * 0.25 / 3.0)
    h2 = h1 * np.exp(2j * np.pi * n3 / 6.0)
    h3 = h1 * np.exp(2j * np.pi * n3 / 3.0)
    return h, g, h1, h2, h3


def kurt(c: np.ndarray) -> float:
    """Kurtosis of one band as the reference computes it ('kurt2' option)."""
    if np.all(c == 0):
        return 0.0
    c = c - c.mean()
    energy = np.mean(np.abs(c) ** 2)
    if energy < EPS:
        return 0.0
    value = np.mean(np.abs(c) ** 4) / energy**2
    return value - (3.0 if np.isrealobj(c) else 2.0)


def _binary_split(x, h, g):
    n = x.size
    a = signal.lfilter(h, 1.0, x)[1:n:2]
    d = signal.lfilter(g, 1.0, x)[1:n:2]
    d = d * (-1.0) ** np.arange(1, d.size + 1)
    return a, d


def _ternary_split(x, h1, h2, h3):
    n = x.size
    return [signal.lfilter(f, 1.0, x)[2:n:3] for f in (h1, h2, h3)]


def _tree(x, filters, nlevel, level):
    """Recursive part of the reference (K_wpQ_local): binary rows KD and ternary rows KQ."""
    h, g, h1, h2, h3 = filters
    a, d = _binary_split(x, h, g)
    k_low = kurt(a[len(h) - 1 :])
    k_high = kurt(d[len(g) - 1 :])
    if level > 2:
        parts = _ternary_split(a, h1, h2, h3) + _ternary_split(d, h1, h2, h3)
        kq = [kurt(p[len(h) - 1 :]) for p in parts]
    else:
        kq = [0.0] * 6
    if level == 1:
        kd_rows = np.array([[k_low] * 3 + [k_high] * 3])
        kq_rows = np.array([kq])
    else:
        kd_a, kq_a = _tree(a, filters, nlevel, level - 1)
        kd_d, kq_d = _tree(d, filters, nlevel, level - 1)
        width = kd_a.shape[1]
        top = np.concatenate([np.full(width, k_low), np.full(kd_d.shape[1], k_high)])
        kd_rows = np.vstack([top, np.hstack([kd_a, kd_d])])
        span = kq_a.shape[1] // 3
        top_q = np.repeat(kq, span)
        kq_rows = np.vstack([top_q, np.hstack([kq_a, kq_d])])
    if level == nlevel:
        kd_rows = np.vstack([np.full(kd_rows.shape[1], kurt(x)), kd_rows])
        k3 = [kurt(p[len(h) - 1 :]) for p in _ternary_split(x, h1, h2, h3)]
        span = kq_rows.shape[1] // 3
        kq_rows = np.vstack([np.repeat(k3, span), kq_rows[: kq_rows.shape[0] - 2]])
    return kd_rows, kq_rows


def reference_kurtogram(x, fs: float = 1.0, nlevel: int = 7):
    """Kurtogram map and best band exactly as the reference computes them.

    Returns
    -------
    dict
        ``K`` (2*nlevel, 3*2**nlevel), ``levels``, ``freqs``, and the best band's ``row``,
        ``column``, ``level``, ``fc``, ``bw``, ``kurtosis``.
    """
    x = np.asarray(x, dtype=float)
    if nlevel > np.log2(x.size) - 7:
        raise ValueError("Please enter a smaller number of decomposition levels")
    x = x - x.mean()
    kd, kq = _tree(x, reference_filters(), nlevel, nlevel)
    K = np.zeros((2 * nlevel, 3 * 2**nlevel))
    K[0] = kd[0]
    for i in range(1, nlevel):
        K[2 * i - 1] = kd[i]
        K[2 * i] = kq[i - 1]
    K[2 * nlevel - 1] = kd[nlevel]
    K = K * (K > 0)
    steps = np.arange(1, nlevel + 1)
    levels = np.concatenate([[0.0], np.column_stack([steps, steps + np.log2(3) - 1]).ravel()])
    levels = levels[: 2 * nlevel]
    columns = np.arange(3 * 2**nlevel)
    freqs = fs * (columns / (3 * 2 ** (nlevel + 1)) + 1.0 / (3 * 2 ** (2 + nlevel)))
    # max_IJ: maximum of each column (first row on ties), then the first column holding it.
    rows_of_max = np.argmax(K, axis=0)
    column = int(np.argmax(K[rows_of_max, columns]))
    row = int(rows_of_max[column])
    fi = column / 3 / 2 ** (nlevel + 1) + 2.0 ** (-2 - levels[row])
    return {
        "K": K,
        "levels": levels,
        "freqs": freqs,
        "row": row,
        "column": column,
        "level": float(levels[row]),
        "fc": fs * fi,
        "bw": fs * 2.0 ** -(levels[row] + 1),
        "kurtosis": float(K[row, column]),
    }
