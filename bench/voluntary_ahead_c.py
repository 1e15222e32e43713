"""The voluntary motion at n + h on the C core (WAKE_RTP_VOLUNTARY_AHEAD) against the float reference.

    python bench/voluntary_ahead_c.py          # h = 2, 5, 10

1. The RTP alone (the comparison of tests/rtp/test_fixed_voluntary.py): ``FixedPointRTP`` (J = 5, sym3,
   full scale 4, R = 0.09, Kalman inert and live) with ``w`` and ``w_h`` of one Python HPA, against a
   ``ReferenceRTP`` with its quantised configuration on the Q15-rounded input: the worst and the RMS
   difference of ``v_h`` (physical units; RMS over the output's range).
2. ``WakeFilter(backend="c", horizon=h)`` against ``backend="reference"`` on the paper's first three
   synthetic signals: the NRMSE of ``voluntary_ahead`` against ``s_v`` after 5 s and over the whole
   recording (from 0.5 s), both backends.

Tables: docs/studies/design.md, "Voluntary motion at n + h".
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from wake import WakeConfig, WakeFilter  # noqa: E402
from wake.eval.metrics import nrmse  # noqa: E402
from wake.eval.synthetic import paper_dataset  # noqa: E402
from wake.hpa import run_hpa  # noqa: E402
from wake.rtp.fixed import FixedPointRTP  # noqa: E402
from wake.rtp.reference import ReferenceRTP  # noqa: E402
from wake.wavelets import filter_bank_taps  # noqa: E402

FS_C, R = 4.0, 0.09


def signal(n, seed, amp=1.5):
    rng = np.random.default_rng(seed)
    t = np.arange(n) / 100.0
    return amp * (0.6 * np.sin(2 * np.pi * 0.7 * t + rng.uniform(0, 6)) + 0.2 * np.sin(2 * np.pi * 6.0 * t)
                  + 0.02 * rng.standard_normal(n))


def rtp_difference(h, q_ratio, p0_ratio):
    x = signal(3000, seed=h)
    config = WakeConfig(backend="reference", horizon=h)
    upd = run_hpa(x[:500], config, taps=filter_bank_taps(config.wavelet, config.level, config.mode))
    c = FixedPointRTP(filter_bank_taps("sym3", 5), upd.weights, R, q_ratio * R, p0_ratio * R, full_scale=FS_C)
    c.set_weights_ahead(upd.weights_ahead)
    ref = ReferenceRTP(c.taps, c.weights, c.measurement_noise, c.process_noise, c.initial_covariance)
    ref.set_weights_ahead(c.weights_ahead)
    xq = np.clip(np.round(x / FS_C * 32768), -32768, 32767) / 32768 * FS_C
    want = ref.run_outputs(xq)[4]
    got = c.run_outputs(x)[4]
    return np.abs(got - want).max(), np.sqrt(np.mean((got - want) ** 2)) / np.ptp(want)


def main():
    print("| h | Kalman (q/R, p0/R) | worst |v_h,C - v_h| (FS 4) | RMS / range |")
    print("|---:|---|---:|---:|")
    for h in (2, 5, 10):
        for q, p0 in ((0.0, 0.0), (1e-2, 1.0), (1e-3, 0.0)):
            worst, rms = rtp_difference(h, q, p0)
            print(f"| {h} | {q:g}, {p0:g} | {worst:.2g} | {rms:.2g} |")
    print()
    print("| h | signal | NRMSE after 5 s: C / float / relative | whole (from 0.5 s): C / float / relative |")
    print("|---:|---:|---|---|")
    signals = paper_dataset()[:3]
    for h in (2, 5, 10):
        for i, s in enumerate(signals):
            c = WakeFilter(backend="c", horizon=h).run(s.measurement)
            r = WakeFilter(backend="reference", horizon=h).run(s.measurement)
            cells = []
            for skip in (500, 50):
                nc, nr = nrmse(s.voluntary, c.voluntary_ahead, skip), nrmse(s.voluntary, r.voluntary_ahead, skip)
                cells.append(f"{nc:.5f} / {nr:.5f} / {(nc - nr) / nr:+.2%}")
            print(f"| {h} | {i + 1} | {cells[0]} | {cells[1]} |")


if __name__ == "__main__":
    main()
