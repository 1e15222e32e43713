"""How closely the C HPA's tremor-ahead fit (csrc/wake_hpa.c, WAKE_HPA_AHEAD) agrees with wake.ahead.

Every window of the paper's ten synthetic signals (the first 20 s: four HPA windows) and, when present,
of every PADS axis (whole windows), at horizons 1, 5, 10 and 20 samples: the C HPA runs the windows in
order on one instance (wake.hpa.c_ahead.run_ahead_c); each window's estimate and truth are recomputed in
float64 from the int16 window the C HPA read and the weights it installed, and fed to
wake.ahead.fit_predictor / held_out_gain / gate_target.  Reported: the largest coefficient difference
(relative to max(1, max |c|)), the largest goal difference, and the largest NRMSE of the command
g P over a window.

    python bench/hpa_c_ahead_agreement.py [--pads DIR]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from wake import WakeConfig  # noqa: E402
from wake.eval.synthetic import paper_dataset  # noqa: E402
from wake.hpa.c_ahead import ahead_agreement  # noqa: E402
from wake.wavelets import filter_bank_taps  # noqa: E402

CONFIG = WakeConfig(backend="reference")
TAPS = filter_bank_taps("sym3", 5)
HORIZONS = (1, 5, 10, 20)


def compare(stream, horizon, worst):
    """Run the C fit on ``stream`` and fold its differences from wake.ahead into ``worst``."""
    full_scale = 2.0 ** np.ceil(np.log2(np.max(np.abs(stream)) * 1.01 + 1e-12))
    for r in ahead_agreement(stream, CONFIG, taps=TAPS, horizon=horizon, full_scale=full_scale):
        c, ref = r["coefficients"], r["reference"]
        worst["coefficient"] = max(worst["coefficient"], np.max(np.abs(c - ref)) / max(1.0, np.max(np.abs(ref))))
        worst["goal"] = max(worst["goal"], abs(r["goal"] - r["reference_goal"]))
        if r["command_nrmse"] is not None:
            worst["command_nrmse"] = max(worst["command_nrmse"], r["command_nrmse"])
        worst["windows"] += 1


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pads", help="folder of PADS recordings")
    args = ap.parse_args(argv)
    L = CONFIG.window_samples
    sets = {"synthetic": [s.measurement[:4 * L] for s in paper_dataset()]}
    if args.pads:
        from wake.eval.datasets import load_pads_folder

        sets["PADS"] = [np.asarray(r.samples[:(r.samples.shape[0] // L) * L, c], dtype=float)
                        for r in load_pads_folder(args.pads) for c in range(r.samples.shape[1])
                        if r.samples.shape[0] >= L]
    for name, streams in sets.items():
        worst = {"coefficient": 0.0, "goal": 0.0, "command_nrmse": 0.0, "windows": 0}
        for s in streams:
            for h in HORIZONS:
                compare(s, h, worst)
        print(f"{name}: {worst['windows']} windows; largest coefficient difference {worst['coefficient']:.1e} "
              f"of max(1, max |c|), goal {worst['goal']:.1e}, command NRMSE {worst['command_nrmse']:.1e}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
