"""The C HPA's tremor-ahead build (WAKE_HPA_AHEAD) of two versions of csrc/ run side by side, every result compared bit for bit.

    python bench/hpa_ahead_bit_identity.py                    (the working tree's csrc/ against main's)
    python bench/hpa_ahead_bit_identity.py --old REF --hop 25 --pads PADS_DIR

A change to the fit's code that should not move any result (a clamp that never fires on a real window) is checked
here: the build with the fit has no other bit-for-bit guard (bench/hpa_c_results.py compares the fields of the
build without it). The old csrc/ (``git archive REF csrc``) and the new (the working tree's) are each compiled
with the host's gcc (``-O2 -ffp-contract=off``, WAKE_HPA_AHEAD 1) into a shared library with a small shim, in two
configurations: the firmware's defaults and the Python extension's limits (build_ffi.py: windows up to 1024
samples, 512 spectrum bins). On each of the paper's ten synthetic signals and, when present, each PADS axis, one
instance per signal, build and horizon (1 and 20) runs the warm-up windows of 100 to 400 samples and then a window
of L samples every ``--hop`` samples (each scoring the previous window's predictor on its new samples), once with
``wake_hpa_run`` and once slice by slice (``wake_hpa_slice``), on both versions. Every byte of every result
(``wake_hpa_result_t``: the weights, R, e_L, the ridge, the cut-off, the flags, the predictor and the goal) and the
outcome of every call (a result, or the same refusal) must be the same; the script prints the counts and exits 1 on
any difference. How many slices a window takes is counted apart ("slice counts changed"), not as a difference: it
moves with the slice cost model (a step's charge, e.g. ``COST_SLIDE``), which decides where a run is cut, not what
it computes.
"""

from __future__ import annotations

import argparse
import ctypes
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from wake import WakeFilter  # noqa: E402
from wake.eval.datasets import default_pads_dir, load_pads_folder  # noqa: E402
from wake.eval.synthetic import paper_dataset  # noqa: E402
from wake.hpa.c_port import hpa_config_fields, quantize_window, window_full_scale  # noqa: E402
from wake.rtp.qformat import quantize_taps  # noqa: E402
from wake.wavelets import default_weights  # noqa: E402

FLOAT_FIELDS = ("fs", "tremor_low", "tremor_high", "cutoff_low", "cutoff_high", "shallow_high", "default_cutoff",
                "min_depth_ratio", "floor_ratio", "edge_ratio", "ridge", "process_noise_ratio")
INT_FIELDS = ("window", "level", "ar_order", "rule", "clean_below", "horizon")
#: build name -> extra definitions (the firmware's defaults; the Python extension's limits, build_ffi.py)
BUILDS = {"firmware": [], "python": ["-DWAKE_HPA_MAX_WINDOW=1024", "-DWAKE_HPA_MAX_ORDER=128",
                                     "-DWAKE_HPA_MAX_PSD_BINS=512"]}
HORIZONS = (1, 20)
SHIM = r"""
#include <string.h>
#include "wake_hpa.h"
size_t shim_size(void) { return sizeof(wake_hpa_t); }
size_t shim_result_size(void) { return sizeof(wake_hpa_result_t); }
int shim_init(wake_hpa_t *h, const float *f, const unsigned short *u, const short *taps, const float *w)
{
    wake_hpa_config_t c;
    int i;
    memset(&c, 0, sizeof c);
    c.fs = f[0]; c.tremor_low = f[1]; c.tremor_high = f[2]; c.cutoff_low = f[3]; c.cutoff_high = f[4];
    c.shallow_high = f[5]; c.default_cutoff = f[6]; c.min_depth_ratio = f[7]; c.floor_ratio = f[8];
    c.edge_ratio = f[9]; c.ridge = f[10]; c.process_noise_ratio = f[11];
    c.window = u[0]; c.level = u[1]; c.ar_order = u[2]; c.rule = u[3]; c.clean_below = u[4]; c.horizon = u[5];
    for (i = 0; i < WAKE_HPA_MAX_WARMUP; ++i) c.warmup[i] = u[6 + i];
    return (int)wake_hpa_init(h, &c, (const wake_q15_t *)taps, w);
}
/* one window: its start, then the whole run (sliced 0) or slice after slice; the result's bytes into out;
   returns the slices (1 for a whole run) or a negative status */
long shim_window(wake_hpa_t *h, const short *x, unsigned n, unsigned index, int sliced, wake_hpa_result_t *out)
{
    long k = 0;
    wake_hpa_status_t s = wake_hpa_start(h, (const wake_q15_t *)x, (uint16_t)n, (uint32_t)index);
    memset(out, 0, sizeof *out);
    if (s != WAKE_HPA_OK) return -1000 - (long)s;
    if (sliced) {
        do { s = wake_hpa_slice(h); ++k; } while (s == WAKE_HPA_RUNNING && k < 100000);
    } else {
        s = wake_hpa_run(h);
        k = 1;
    }
    if (s != WAKE_HPA_DONE) return -2000 - (long)s;
    s = wake_hpa_take(h, out);
    return s == WAKE_HPA_OK ? k : -3000 - (long)s;
}
"""


def build(csrc: Path, defs: list, out: Path) -> ctypes.CDLL:
    shim = out.with_suffix(".c")
    shim.write_text(SHIM)
    subprocess.run(["gcc", "-O2", "-std=c99", "-ffp-contract=off", "-fPIC", "-shared", f"-I{csrc}",
                    "-DWAKE_HPA_AHEAD=1", "-DWAKE_RTP_AHEAD=1", *defs, str(shim),
                    *(str(p) for p in sorted(csrc.glob("wake_hpa*.c"))),   # the HPA's files, one or split by concern
                    # the RTP's files (one, or by concern since the RTP's split)
                    *(str(p) for p in sorted(csrc.glob("wake_rtp*.c"))), "-o", str(out)], check=True)
    lib = ctypes.CDLL(str(out))
    lib.shim_size.restype = lib.shim_result_size.restype = ctypes.c_size_t
    lib.shim_window.restype = ctypes.c_long
    lib.shim_window.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_uint, ctypes.c_uint, ctypes.c_int,
                                ctypes.c_void_p]
    lib.shim_init.argtypes = [ctypes.c_void_p] * 5
    return lib


def signals(pads_dir):
    """(name, samples (n,), fs) of every synthetic signal and PADS axis."""
    for i, s in enumerate(paper_dataset()):
        yield f"synthetic {i + 1}", np.asarray(s.measurement, dtype=float), s.fs
    folder = default_pads_dir(pads_dir)
    if folder is not None and Path(folder).is_dir():
        for rec in load_pads_folder(folder):
            for c in range(rec.samples.shape[1]):
                yield f"{rec.name} axis {c}", np.asarray(rec.samples[:, c], dtype=float), rec.fs


def windows(n, L, hop):
    """(start, end) of the warm-up windows and of every full window hop samples apart."""
    return [(0, m) for m in range(L // 5, L, L // 5)] + [(e - L, e) for e in range(L, n + 1, hop)]


class Instance:
    """One C HPA instance of a library."""

    def __init__(self, lib, fields, taps_q, w0):
        self.lib, self.taps = lib, taps_q       # the taps must outlive the instance
        self.mem = ctypes.create_string_buffer(lib.shim_size())
        f = np.array([fields[k] for k in FLOAT_FIELDS], dtype=np.float32)
        u = np.array([fields[k] for k in INT_FIELDS] + list(fields["warmup"]), dtype=np.uint16)
        status = lib.shim_init(self.mem, f.ctypes.data, u.ctypes.data, taps_q.ctypes.data, w0.ctypes.data)
        if status != 0:
            raise RuntimeError(f"wake_hpa_init refused the configuration (status {status})")
        self.res = ctypes.create_string_buffer(lib.shim_result_size())

    def window(self, q, index, sliced):
        k = self.lib.shim_window(self.mem, q.ctypes.data, q.size, index, int(sliced), self.res)
        return k, self.res.raw


def compare(pads_dir, hop, libs):
    """Counts of windows, slices and differences over every signal, build, horizon and mode."""
    counts = {"windows": 0, "results": 0, "slices": 0, "differences": 0, "refused": 0, "slice_counts_changed": 0}
    for name, x, fs in signals(pads_dir):
        filt = WakeFilter(fs=fs, backend="c", hpa_backend="c")
        cfg = filt.config
        taps_q = np.ascontiguousarray(quantize_taps(filt.taps), dtype=np.int16)
        w0 = np.clip(np.asarray(default_weights(cfg.level), dtype=np.float32), -32, 32)
        q = np.ascontiguousarray(quantize_window(x, window_full_scale(x)), dtype=np.int16)
        spans = windows(x.size, cfg.window_samples, hop)
        for bname in BUILDS:
            for horizon in HORIZONS:
                fields = dict(hpa_config_fields(cfg), horizon=horizon)
                for sliced in (False, True):
                    old, new = (Instance(libs[v, bname], fields, taps_q, w0) for v in ("old", "new"))
                    for a, b in spans:
                        win = np.ascontiguousarray(q[a:b])
                        k_old, r_old = old.window(win, b, sliced)
                        k_new, r_new = new.window(win, b, sliced)
                        counts["windows"] += 1
                        counts["results"] += k_new > 0
                        counts["refused"] += k_new <= 0
                        counts["slices"] += max(k_new, 0) if sliced else 0
                        # a result (k > 0, its slices) or a refusal (k <= 0, its status), as the shim returns
                        outcome_old, outcome_new = (k if k <= 0 else 1 for k in (k_old, k_new))
                        counts["slice_counts_changed"] += k_old > 0 and k_new > 0 and k_old != k_new
                        if outcome_old != outcome_new or r_old != r_new:
                            counts["differences"] += 1
                            if counts["differences"] <= 10:
                                print(f"DIFFERENT: {name}, {bname} build, horizon {horizon}, "
                                      f"{'sliced' if sliced else 'whole'}, window [{a}, {b}): "
                                      f"status/slices {k_old} vs {k_new}", flush=True)
        print(f"{name}: {counts}", flush=True)
    return counts


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--old", default="main", help="git ref of the old csrc/ (default main)")
    parser.add_argument("--hop", type=int, default=50, help="samples between full windows (default 50)")
    parser.add_argument("--pads", default=None, help="folder of the PADS recordings (default: WAKE_PADS_DIR or "
                        "the usual place; left out when absent)")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        old_src = tmp / "old"
        old_src.mkdir()
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", args.old, "csrc"], check=True,
                                 capture_output=True).stdout
        subprocess.run(["tar", "-x", "-C", str(old_src)], input=archive, check=True)
        libs = {(v, b): build(src, defs, tmp / f"{v}_{b}.so") for v, src in (("old", old_src / "csrc"),
                                                                             ("new", ROOT / "csrc"))
                for b, defs in BUILDS.items()}
        counts = compare(args.pads, args.hop, libs)
    print(f"old csrc/ {args.old} against the working tree's: {counts['windows']} window runs "
          f"({counts['results']} results, {counts['refused']} refused by both or either), "
          f"{counts['slices']} slices, {counts['differences']} differences "
          f"({counts['slice_counts_changed']} windows cut into a different number of slices)")
    return 1 if counts["differences"] else 0


if __name__ == "__main__":
    sys.exit(main())
