"""The bound the C HPA clamps its DFT pass's Reinsch states to never changes a state (issue 34).

csrc/wake_hpa_dft.c clamps the states s and d of Reinsch's recursion (``d += x_c + lambda s; s += d``) to
REINSCH_S_MAX and REINSCH_D_MAX (csrc/internal/wake_bounds.h) every REINSCH_BLOCK samples, so that Frama-C Eva can bound them
(docs/studies/verification.md, "The DFT pass").  The clamp is only invisible if every state of every window of int16
samples stays below those bounds, roundings included: shown here for every window length the default build
allows (n <= WAKE_HPA_MAX_WINDOW = 512; and n <= 1024 with the larger bounds of a larger build) and every bin
1 <= m < n / 2, then checked on the worst windows with the C code's own single-precision arithmetic.
"""

import re

import numpy as np
import pytest

from support import CSRC

#: |x_c| = |x - mean| for int16 samples and a mean within their range, plus the subtraction's rounding
X_MAX = 65535.0 + 2.0**-7
U = 2.0**-24


def c_bounds(large=False):
    """REINSCH_S_MAX, REINSCH_D_MAX of a build with WAKE_HPA_MAX_WINDOW <= 512 (the default) or above it
    (``large``), and REINSCH_BLOCK."""
    src = (CSRC / "internal" / "wake_bounds.h").read_text()
    pairs = re.findall(r"#define REINSCH_S_MAX ([\d.]+)f.*\n#define REINSCH_D_MAX ([\d.]+)f", src)
    k = re.search(r"#define REINSCH_BLOCK (\d+)u", src)
    assert "#if WAKE_HPA_MAX_WINDOW <= 512\n#define REINSCH_S_MAX" in src and len(pairs) == 2 and k, \
        "the Reinsch bounds are not where this test looks for them (csrc/internal/wake_bounds.h)"
    s_max, d_max = pairs[1 if large else 0]
    return float(s_max), float(d_max), int(k.group(1))


def worst_states(n):
    """For every bin 1 <= m < n / 2 of length n: the largest |s| and |d| any window of |x_c| <= X_MAX gives (exact
    arithmetic), w, and lambda.  s(t) = sum x_c(u) sin(w (t-u+1)) / sin w, d(t) = sum x_c(u) cos(w (t-u+1/2)) / cos(w/2).
    """
    m = np.arange(1, (n - 1) // 2 + 1)[:, None]
    k = np.arange(1, n + 1)[None, :]
    w = 2 * np.pi * m[:, 0] / n
    # the terms are >= 0, so the largest partial sum is the whole one; the angles w k and w (k - 1/2) are exact
    # multiples of 2 pi / (2 n), looked up in one table
    table = np.abs(np.sin(np.pi * np.arange(2 * n) / n)), np.abs(np.cos(np.pi * np.arange(2 * n) / n))
    s = np.sum(table[0][(2 * m * k) % (2 * n)], axis=1) / np.sin(w)
    d = np.sum(table[1][(m * (2 * k - 1)) % (2 * n)], axis=1) / np.cos(w / 2)
    return X_MAX * s, X_MAX * d, w, -4 * np.sin(w / 2) ** 2


def rounding_bounds(n, w, lam, s_max, d_max):
    """What the single-precision recursion adds to the exact states over n samples while they stay within s_max,
    d_max: per sample d gets an error below 2.01 u (d_max + X_MAX + |lambda| s_max) (two additions, one
    product), s one below 1.01 u s_max; an error e in d moves s by at most e / sin w and d by e / cos(w/2) later,
    one in s moves s by e / cos(w/2) and d by 2 e tan(w/2)."""
    e_d = 2.01 * U * (d_max + X_MAX + np.abs(lam) * s_max)
    e_s = 1.01 * U * s_max
    return (n * (e_d / np.sin(w) + e_s / np.cos(w / 2)),
            n * (e_d / np.cos(w / 2) + 2 * e_s * np.tan(w / 2)))


@pytest.mark.parametrize("large, lengths", [(False, range(4, 513)), (True, range(513, 1025))],
                         ids=["WAKE_HPA_MAX_WINDOW<=512", "WAKE_HPA_MAX_WINDOW<=1024"])
def test_exact_states_and_roundings_stay_below_the_clamp(large, lengths):
    s_max, d_max, _ = c_bounds(large)
    worst_s = worst_d = 0.0
    for n in lengths:
        s, d, w, lam = worst_states(n)
        es, ed = rounding_bounds(n, w, lam, s_max, d_max)
        worst_s = max(worst_s, float(np.max((s + es) / s_max)))
        worst_d = max(worst_d, float(np.max((d + ed) / d_max)))
    # docs/studies/verification.md quotes the margins: 2^31.9 of 2^33 and 2^32.9 of 2^34 (n <= 512), 2^34.5 of 2^35 and
    # 2^35.5 of 2^36 (n <= 1024)
    assert worst_s < (0.75 if large else 0.55), worst_s
    assert worst_d < (0.75 if large else 0.55), worst_d


def reinsch_f32(xc, lam):
    """The C code's recursion in single precision, operation by operation (d = d + xc + lam s; s = s + d)."""
    f = np.float32
    s = d = f(0.0)
    lam = f(lam)
    peak_s = peak_d = 0.0
    for v in xc.astype(np.float32):
        d = f(f(d + v) + f(lam * s))
        s = f(s + d)
        peak_s, peak_d = max(peak_s, abs(float(s))), max(peak_d, abs(float(d)))
    return peak_s, peak_d


@pytest.mark.parametrize("n, m", [(512, 1), (500, 1), (511, 255), (500, 30), (100, 6)])
def test_worst_windows_in_single_precision(n, m):
    """The window of full-scale samples whose signs follow the bin's sine (the worst for s at the pass's end, and
    for d the one that follows its cosine), run as the C code runs it: the states stay below half the clamp."""
    s_max, d_max, _ = c_bounds()
    w = 2 * np.pi * m / n
    u = np.arange(n)
    lam = -4 * np.sin(w / 2) ** 2
    for x, bound in ((np.sign(np.sin(w * (n - u))), s_max), (np.sign(np.cos(w * (n - u - 0.5))), d_max)):
        x = np.where(x >= 0, 32767.0, -32768.0)
        xc = x - np.float32(np.mean(x))
        peak_s, peak_d = reinsch_f32(xc, lam)
        assert np.isfinite(peak_s) and np.isfinite(peak_d)
        assert peak_s < s_max / 2 and peak_d < d_max / 2, (peak_s / s_max, peak_d / d_max)
    # the worst window comes close to the exact bound: the test exercises the largest states there are
    s_exact = worst_states(n)[0][m - 1]
    x = np.where(np.sin(w * (n - u)) >= 0, 32767.0, -32768.0)
    assert reinsch_f32(x - np.float32(np.mean(x)), lam)[0] > 0.4 * s_exact


def test_clamp_block_keeps_eva_intervals_finite():
    """Between two clamps an interval of s and d grows at most by the spectral radius of |[[1 + |lambda|, 1],
    [|lambda|, 1]]| per sample (lambda = -4: 3 + 2 sqrt 2): from the clamp bounds over REINSCH_BLOCK samples it
    stays far below FLT_MAX (what Eva's step_dft entry relies on)."""
    s_max, d_max, block = c_bounds()
    growth = (3 + 2 * np.sqrt(2)) ** block
    assert (s_max + d_max + block * X_MAX) * growth < 2.0**100
