"""The figure of docs/studies/design.md, "Tremor ahead": the true tremor, the 50-ms-ahead prediction and the gated command,
with the confidence beneath, for one PADS axis and one synthetic signal.

    python bench/ahead_figure.py [OUT.png]      # default docs/figures/tremor_ahead.png

PADS from ``$WAKE_PADS_DIR`` or ``../shared/data/pads`` next to the checkout (the synthetic column alone without
it); the C core when built, else the float reference.  Truth: PADS, the tremor independent of WAKE
(``wake.eval.warmup.independent_ground_truth``); synthetic, the tremor component ``s_t``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

from support import pads_dir  # noqa: E402
from wake import WakeFilter  # noqa: E402
from wake.ahead import horizon_from_ms  # noqa: E402
from wake.eval.synthetic import paper_dataset  # noqa: E402
from wake.eval.warmup import independent_ground_truth  # noqa: E402
from wake.rtp import c_backend_available  # noqa: E402

BACKEND = "c" if c_backend_available() else "reference"
HORIZON_MS = 50
#: The PADS recording and axis drawn: a resting tremor with the gate opening in the 2-s HPA.
PADS_RECORDING, PADS_AXIS = "027_DrinkGlas_RightWrist", 1
SYNTHETIC_SIGNAL = 0


def panel(x, fs, truth):
    """(t, truth, prediction, command, confidence) of one channel at HORIZON_MS."""
    res = WakeFilter(fs=fs, backend=BACKEND, horizon=horizon_from_ms(HORIZON_MS, fs)).run(x)
    return np.arange(x.size) / fs, truth, res.tremor_ahead, res.command, res.confidence


def cases():
    out = []
    folder = pads_dir()
    if folder is not None:
        from wake.io import read_pads

        rec = read_pads(folder / f"{PADS_RECORDING}.txt")
        x = rec.samples[:, PADS_AXIS].astype(float)
        out.append((f"PADS {rec.name}, {rec.channels[PADS_AXIS]}", panel(x, rec.fs,
                                                                     independent_ground_truth(x, rec.fs)[1])))
    s = paper_dataset()[SYNTHETIC_SIGNAL]
    stop = int(12 * s.fs)   # the first 12 s: the warm-up and two full windows
    out.append((f"synthetic signal {SYNTHETIC_SIGNAL + 1} (first 12 s)",
                panel(s.measurement[:stop], s.fs, s.tremor[:stop])))
    return out


def main(argv=None):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    argv = sys.argv[1:] if argv is None else argv
    path = Path(argv[0]) if argv else ROOT / "docs" / "figures" / "tremor_ahead.png"
    drawn = cases()
    fig, axes = plt.subplots(2, len(drawn), figsize=(6.5 * len(drawn), 5.2), sharex="col",
                             gridspec_kw={"height_ratios": [3, 1]}, squeeze=False)
    for k, (title, (t, truth, pred, cmd, conf)) in enumerate(drawn):
        top, bottom = axes[0, k], axes[1, k]
        top.plot(t, truth, color="0.25", lw=1.0, label="true tremor")
        top.plot(t, pred, color="tab:orange", lw=0.8, alpha=0.8, label=f"predicted {HORIZON_MS} ms before")
        top.plot(t, cmd, color="tab:blue", lw=1.0, label="gated command")
        top.set_title(title, fontsize=10)
        lim = 1.5 * np.max(np.abs(truth))
        top.set_ylim(-lim, lim)
        bottom.plot(t, conf, color="tab:green", lw=1.2)
        bottom.set_ylim(-0.05, 1.05)
        bottom.set_xlabel("time since start (s)")
        if k == 0:
            top.set_ylabel("tremor")
            bottom.set_ylabel("confidence")
            top.legend(loc="upper right", fontsize=8)
    fig.suptitle(f"Tremor {HORIZON_MS} ms ahead: each sample is what the actuator plays there ({BACKEND} backend)",
                 fontsize=11)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
