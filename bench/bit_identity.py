"""Record every output of the filter, or check them against a recording: the guard of a refactor.

    python bench/bit_identity.py save DIR     # on the commit you start from
    python bench/bit_identity.py check DIR    # after each step: every array equal bit for bit

What is recorded, for both RTP backends ("c", "reference") and the C HPA
(``backend="c", hpa_backend="c"``), on the paper's synthetic set
(:func:`wake.eval.synthetic.paper_dataset`), the field-fault streams of
tests/test_faults.py (those of bench/fault_streams.py, plus a long and a short
gap in mid-stream) and the PADS recordings (``$WAKE_PADS_DIR`` or
``../shared/data/pads``; left out with a note when absent):

- ``run(x)``: prediction, HPA history (every field), full scale, clip,
  saturation and full-scale-change counts;
- ``update(v)`` sample by sample and ``update_block`` in uneven blocks:
  predictions and HPA history;
- a state taken with ``get_state()`` in mid-stream and a pickled filter,
  both written to DIR by ``save``: ``check`` loads them (written by the old
  code) and continues the stream, which must give what the old code gave, or
  be refused with an error (reported, with its message).

``check`` prints one line per case and exits non-zero on any difference.
"""

from __future__ import annotations

import pickle
import sys
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

from wake import WakeFilter  # noqa: E402
from wake.eval.datasets import default_pads_dir, load_pads_folder  # noqa: E402
from wake.eval.synthetic import paper_dataset  # noqa: E402

FAULTS = ("clean", "glitch", "quiet", "nan_start", "dc_jump", "late_glitch", "rail", "huge")
SETTINGS = {"c": dict(backend="c"), "reference": dict(backend="reference"),
            "hpa_c": dict(backend="c", hpa_backend="c"), "c_fixed_fs": dict(backend="c", full_scale=4.0)}
BLOCKS = (1, 7, 64, 333, 1000, 2)
STATE_AT = 2345  # or two thirds into a shorter signal


def state_at(x):
    return min(STATE_AT, 2 * x.shape[0] // 3)


def signals():
    from test_faults import _stream

    out = {f"paper{i}": s.measurement for i, s in enumerate(paper_dataset())}
    for kind in FAULTS:
        out[f"fault_{kind}"] = _stream(kind)[0]
    x = _stream("clean")[0].copy()
    x[3000:3150] = np.nan     # a long gap (>= 20 % of L)
    x[1200:1230] = np.nan     # a short one
    out["fault_gaps"] = x
    folder = default_pads_dir()
    if folder is not None and folder.is_dir():
        for rec in load_pads_folder(folder):
            out[f"pads_{rec.name}"] = rec.samples
    else:
        print("PADS recordings not found (set WAKE_PADS_DIR): left out", file=sys.stderr)
    return out


def history_arrays(prefix, hpa):
    """Every field of every HPAUpdate, per channel, as arrays."""
    out = {}
    for c, ups in enumerate(hpa):
        p = f"{prefix}/hpa{c}"
        out[p + "/index"] = np.array([u.index for u in ups])
        out[p + "/applied_at"] = np.array([u.applied_at for u in ups])
        for name in ("cutoff", "measurement_noise", "fit_error", "ridge"):
            out[p + "/" + name] = np.array([getattr(u, name) for u in ups], dtype=float)
        out[p + "/weights"] = np.array([u.weights for u in ups], dtype=float)
        out[p + "/flags"] = np.array(["|".join((u.cutoff_flag,) + tuple(u.flags)) for u in ups])
    return out


def blocks(n):
    start, i = 0, 0
    while start < n:
        stop = min(n, start + BLOCKS[i % len(BLOCKS)])
        yield start, stop
        start, i = stop, i + 1


def stream_update(filt, x):
    if x.ndim == 1:
        return np.array([filt.update(float(v)) for v in x])
    return np.array([filt.update(v) for v in x])


def record_case(name, x, settings):
    """The arrays of one signal under one setting, and the states for the state check."""
    out = {}
    res = WakeFilter(fs=100.0, **settings).run(x)
    out["run/prediction"] = res.prediction
    out.update(history_arrays("run", res.hpa))
    for field in ("full_scale", "clipped", "saturations", "full_scale_changes"):
        value = getattr(res, field)
        if value is not None:
            out[f"run/{field}"] = np.asarray(value)
    f = WakeFilter(fs=100.0, **settings)
    out["update/prediction"] = stream_update(f, x)
    out.update(history_arrays("update", f.hpa_history))
    f = WakeFilter(fs=100.0, **settings)
    out["block/prediction"] = np.concatenate([f.update_block(x[a:b]) for a, b in blocks(x.shape[0])])
    out.update(history_arrays("block", f.hpa_history))
    # state in mid-stream: what the continuation gives
    f = WakeFilter(fs=100.0, **settings)
    f.update_block(x[:state_at(x)])
    states = {"state": pickle.dumps(f.get_state()), "filter": pickle.dumps(f)}
    out["continued/prediction"] = f.update_block(x[state_at(x):])
    out.update(history_arrays("continued", f.hpa_history))
    return out, states


def continue_from(blob, x, kind):
    obj = pickle.loads(blob)
    if kind == "state":
        f = WakeFilter(config=obj.config)
        f.set_state(obj)
    else:
        f = obj
    out = {"continued/prediction": f.update_block(x[state_at(x):])}
    out.update(history_arrays("continued", f.hpa_history))
    return out


def cases():
    for name, x in signals().items():
        for tag, settings in SETTINGS.items():
            if tag == "c_fixed_fs" and not name.startswith(("paper", "fault")):
                continue
            yield f"{name}/{tag}", x, settings


def save(folder: Path):
    folder.mkdir(parents=True, exist_ok=True)
    for key, x, settings in cases():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            arrays, states = record_case(key, x, settings)
        stem = key.replace("/", "__")
        np.savez(folder / f"{stem}.npz", **{k.replace("/", "__"): v for k, v in arrays.items()})
        for kind, blob in states.items():
            (folder / f"{stem}.{kind}.pkl").write_bytes(blob)
        print("saved", key, flush=True)


def compare(old, new, label):
    bad = []
    for k in sorted(set(old) | set(new)):
        if k not in old or k not in new:
            bad.append(f"{k}: only in {'new' if k in new else 'old'}")
            continue
        a, b = old[k], new[k]
        if a.shape != b.shape or a.dtype.kind != b.dtype.kind or a.tobytes() != b.tobytes():
            bad.append(f"{k}: differs")
    return [f"{label}: {b}" for b in bad]


def check(folder: Path):
    failures, refused, n = [], [], 0
    for key, x, settings in cases():
        stem = key.replace("/", "__")
        with np.load(folder / f"{stem}.npz") as z:
            old = {k.replace("__", "/"): z[k] for k in z.files}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            new, _ = record_case(key, x, settings)
            failures += compare(old, new, key)
            cont = {k: v for k, v in old.items() if k.startswith("continued/")}
            for kind in ("state", "filter"):
                try:
                    got = continue_from((folder / f"{stem}.{kind}.pkl").read_bytes(), x, kind)
                except Exception as exc:  # a refused old state: reported with its message
                    refused.append(f"{key} {kind}: {type(exc).__name__}: {exc}")
                    continue
                failures += compare(cont, got, f"{key} (old {kind} restored)")
        n += 1
        print("checked", key, "OK" if not failures else f"{len(failures)} difference(s) so far", flush=True)
    for r in refused:
        print("refused:", r)
    for f in failures:
        print("DIFF:", f)
    print(f"{n} cases, {len(failures)} difference(s), {len(refused)} old state(s) refused")
    return 1 if failures else 0


if __name__ == "__main__":
    if len(sys.argv) != 3 or sys.argv[1] not in ("save", "check"):
        sys.exit(__doc__)
    folder = Path(sys.argv[2])
    sys.exit(save(folder) if sys.argv[1] == "save" else check(folder))
