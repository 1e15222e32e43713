"""Every output of the C backend's RTP recorded, or checked against a recording (issue 44).

    python bench/rtp_outputs_bit_identity.py save DIR     # on the commit you start from
    python bench/rtp_outputs_bit_identity.py check DIR    # after the change: every array equal bit for bit

bench/bit_identity.py guards the prediction and the HPA history; this guards the rest of what the RTP
hands out per sample, which a batch path computes apart from ``update()``: the tremor ahead, the
confidence, the command and the voluntary motion ahead.  Recorded for ``backend="c"`` (full scale
following the signal, and fixed at 4), ``hpa_backend="c"``, at horizons 1 and 5, at 100 and 1000 Hz,
on a synthetic signal, on it with a gap of NaN at its start and in mid-stream, and on it with a knock
(1e5) and a rail (1e3 for 2 s):

- every array of ``run(x)``;
- ``update_block_ahead`` and ``update_block_voluntary_ahead`` in uneven blocks;
- ``update(v)`` sample by sample (100 Hz only) with ``last_ahead`` and ``last_voluntary_ahead`` after
  each sample;
- the C cores' clip and saturation counters after each.

``check`` prints one line per case and exits non-zero on any difference.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from wake import WakeFilter  # noqa: E402
from wake.eval.synthetic import make_signal  # noqa: E402

SETTINGS = {"c": dict(backend="c"), "c_fs4": dict(backend="c", full_scale=4.0),
            "hpa_c": dict(backend="c", hpa_backend="c")}
BLOCKS = (1, 7, 64, 333, 1000, 2)


def signals(fs):
    s = make_signal(5.0, seed=7, fs=fs, duration=30.0).measurement
    n = s.size
    gaps = s.copy()
    gaps[: n // 20] = np.nan
    gaps[n // 2: n // 2 + n // 100] = np.nan
    gaps[2 * n // 3] = np.nan
    faults = s.copy()
    faults[n // 3] = 1e5
    faults[n // 2: n // 2 + int(2 * fs)] = 1e3
    return {"clean": s, "gaps": gaps, "faults": faults}


def counters(filt):
    return np.array([[getattr(r, "clipped", -1), getattr(r, "saturations", -1),
                      getattr(r, "ahead_saturations", -1), getattr(r, "voluntary_ahead_saturations", -1)]
                     for r in filt.rtp_states], dtype=float)


def record_case(x, fs, settings, horizon):
    out = {}
    kw = dict(fs=fs, horizon=horizon, **settings)
    f = WakeFilter(**kw)
    res = f.run(x)
    for name in ("prediction", "voluntary", "tremor", "tremor_ahead", "confidence", "command"):
        out[f"run.{name}"] = np.asarray(getattr(res, name))
    if f._refusal() is None:
        out["run.voluntary_ahead"] = np.asarray(res.voluntary_ahead)
    out["run.counters"] = np.array([res.clipped, res.saturations], dtype=float)
    f = WakeFilter(**kw)
    rows, k, i = [], 0, 0
    while k < x.size:
        b = BLOCKS[i % len(BLOCKS)]
        rows.append(np.stack(f.update_block_ahead(x[k:k + b])))
        k, i = k + b, i + 1
    out["block_ahead"] = np.concatenate(rows, axis=1)
    out["block_ahead.counters"] = counters(f)
    if f._refusal() is None:
        f = WakeFilter(**kw)
        rows, k, i = [], 0, 0
        while k < x.size:
            b = BLOCKS[(i + 3) % len(BLOCKS)]
            rows.append(np.stack(f.update_block_voluntary_ahead(x[k:k + b])))
            k, i = k + b, i + 1
        out["block_voluntary_ahead"] = np.concatenate(rows, axis=1)
    if fs == 100.0:
        f = WakeFilter(**kw)
        with_ahead = f._refusal() is None
        vals = np.empty((5, x.size))
        for j, v in enumerate(x):
            vals[0, j] = f.update(float(v))
            vals[1:4, j] = f.last_ahead
            vals[4, j] = f.last_voluntary_ahead if with_ahead else 0.0
        out["update"] = vals
        out["update.counters"] = counters(f)
    return out


def cases():
    for fs in (100.0, 1000.0):
        for sig, x in signals(fs).items():
            for sname, settings in SETTINGS.items():
                for horizon in (1, 5):
                    yield f"{int(fs)}Hz/{sig}/{sname}/h{horizon}", x, fs, settings, horizon


def main(argv):
    if len(argv) != 3 or argv[1] not in ("save", "check"):
        print(__doc__)
        return 2
    folder = Path(argv[2])
    folder.mkdir(parents=True, exist_ok=True)
    bad = 0
    warnings.simplefilter("ignore")
    for name, x, fs, settings, horizon in cases():
        path = folder / (name.replace("/", "_") + ".npz")
        got = record_case(x, fs, settings, horizon)
        if argv[1] == "save":
            np.savez(path, **got)
            print(f"saved {name}: {len(got)} arrays")
            continue
        old = np.load(path)
        diffs = [k for k in sorted(set(old.files) | set(got))
                 if k not in old.files or k not in got or not np.array_equal(old[k], got[k], equal_nan=True)]
        bad += len(diffs)
        print(f"{name}: {len(got)} arrays, {len(diffs)} differences" + (f" ({', '.join(diffs)})" if diffs else ""))
    if argv[1] == "check":
        print(f"total: {bad} differences")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
