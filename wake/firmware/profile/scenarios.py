"""Parameters, adversarial inputs and per-step profiles of wake_rtp_step."""


import bisect
import functools
import subprocess
from dataclasses import dataclass

import numpy as np

from .build import Image, toolchain
from .emulator import Emulator

# ---------------------------------------------------------------------------
# Parameters and inputs
# ---------------------------------------------------------------------------

def arithmetic_floor(level):
    """Multiply-accumulates per sample: J 2^J + J^2 + J + J + J(J+1)/2 + J.

    Filter bank, u = P w, S = w'u, d += K e, the upper triangle of P, y.
    """
    J = int(level)
    return J * 2**J + J * J + J + J + J * (J + 1) // 2 + J


def _quantizers(fmt):
    """The package's quantisers (:mod:`wake.rtp.qformat`) for its own formats, else equivalent local ones."""
    from wake.rtp import qformat as cb

    p_frac = fmt["p_frac"]
    if (cb.P_FRAC, cb.TAP_FRAC, cb.WEIGHT_FRAC) == (p_frac, fmt["tap_frac"], fmt["weight_frac"]):
        return cb.quantize_taps, cb.quantize_weights, cb.quantize_variance

    def q_taps(taps):
        q = np.round(np.asarray(taps, dtype=float) * 2.0 ** fmt["tap_frac"])
        if np.abs(q).max() > 2**15 - 1 or np.abs(q).sum(axis=1).max() > fmt["tap_row_abs_max"]:
            raise ValueError("taps outside the int16 range or a row's sum of |taps| above the core's bound")
        return q.astype(np.int16)

    def q_weights(w, level):
        w = np.asarray(w, dtype=float).reshape(level)
        if np.abs(w).max(initial=0.0) > 64:
            raise ValueError("weights must lie within ±64")
        return np.round(w * 2.0 ** fmt["weight_frac"]).astype(np.int32)

    def q_var(v, fs, name, *, positive):
        q = round(float(v) / (fs**2 / 2.0**p_frac))
        if q > 2**31 - 1 or q < 0 or (positive and q == 0):
            raise ValueError(f"{name} = {v!r} is outside the Q{p_frac} range")
        return q

    return q_taps, q_weights, q_var


@functools.lru_cache(maxsize=None)
def _hpa_fits(wavelet, level):
    """Realistic weights: the HPA fits of the float reference on a synthetic recording."""
    from wake.filter import WakeFilter
    from wake.eval.synthetic import make_signal

    sig = make_signal(10.0, seed=3)
    filt = WakeFilter(fs=sig.fs, wavelet=wavelet, level=level, backend="reference")
    res = filt.run(sig.measurement)
    fitted = [u for u in res.hpa[0] if u.cutoff_flag != "silent"]
    first = sig.measurement[: filt.window_samples]
    full_scale = filt.headroom * float(np.max(np.abs(first)))
    return filt.taps, fitted, full_scale, sig.measurement


def fitted_parameters(wavelet="sym3", level=5, *, kalman=True, formats=None):
    """Quantised taps, two realistic weight sets, R, q and p0 for the image.

    The weights are HPA fits of ``WakeFilter(backend="reference")`` on
    ``make_signal(10 dB, seed=3)``: the set with the largest ``max|w|`` first,
    and the next fit as the update.  ``full_scale`` is chosen as the C
    backend does (headroom x the peak of the first HPA window).  ``kalman=True``:
    ``p0 = R`` and ``q = 1e-3 R``; ``kalman=False``: ``q = 0``, ``p0 = 0``
    (the covariance stays zero).  ``formats`` is :attr:`Emulator.formats`
    (default: the header's defaults, Q32 covariance, Q15 taps, Q24 weights).
    """
    taps, fits, fs, measurement = _hpa_fits(wavelet, level)
    fmt = formats or {"p_frac": 32, "sample_frac": 15, "tap_frac": 15, "weight_frac": 24,
                      "tap_row_abs_max": 2**16 - 1}
    q_taps, q_weights, q_var = _quantizers(fmt)
    k = max(range(len(fits)), key=lambda i: float(np.max(np.abs(fits[i].weights))))
    a, b = fits[k], fits[(k + 1) % len(fits)]
    # R must fit the Q(P_FRAC) range; realistic R are far below 0.5 FS^2.
    r1 = min(a.measurement_noise, 0.25 * fs**2)
    r2 = min(b.measurement_noise, 0.25 * fs**2)
    params = {
        "wavelet": wavelet,
        "level": int(level),
        "kalman": bool(kalman),
        "full_scale": fs,
        "taps": q_taps(taps),
        "weights": q_weights(a.weights, level),
        "weights2": q_weights(b.weights, level),
        "r": q_var(r1, fs, "R", positive=True),
        "r2": q_var(r2, fs, "R", positive=True),
        "q": q_var(1e-3 * r1, fs, "q", positive=False) if kalman else 0,
        "q2": q_var(1e-3 * r2, fs, "q", positive=False) if kalman else 0,
        "p0": q_var(r1, fs, "p0", positive=False) if kalman else 0,
        "measurement": np.clip(np.round(measurement / fs * 2.0 ** fmt["sample_frac"]), -32768, 32767).astype(np.int16),
    }
    return params


def adversarial_inputs(level, n, *, seed=0, measurement=None):
    """Input sequences (int16 Q15) meant to reach the slowest paths of ``step``.

    silence; full-scale square waves at Nyquist and at the window length;
    full-scale steps between the rails; single-sample full-scale spikes of
    alternating sign (saturate the prediction); uniform random samples;
    and, when ``measurement`` is given, a realistic recording.
    """
    N = 2**level
    k = np.arange(n)
    hi, lo = 32767, -32768
    out = {
        "silence": np.zeros(n, dtype=np.int16),
        "square_nyquist": np.where(k % 2 == 0, hi, lo),
        "square_window": np.where((k // max(N // 2, 1)) % 2 == 0, hi, lo),
        "steps": np.where((k // (N + 3)) % 2 == 0, lo, hi) * ((k // (N + 3)) % 3 != 2),
        "spikes": np.where(k % 7 == 3, np.where((k // 7) % 2 == 0, hi, lo), 0),
        "random": np.random.default_rng(seed).integers(lo, hi + 1, n),
    }
    if measurement is not None:
        m = np.asarray(measurement, dtype=np.int16)
        out["synthetic"] = np.resize(m[len(m) // 2:], n)
    return {name: np.asarray(v, dtype=np.int16) for name, v in out.items()}


# ---------------------------------------------------------------------------
# Profiles
# ---------------------------------------------------------------------------

@dataclass
class StepProfile:
    """Per-sample instruction counts of one configuration."""

    target: str
    level: int
    wavelet: str
    kalman: bool
    counts: dict  #: input kind -> list of instructions per step (first = priming step)
    set_weights: int  #: instructions of one wake_rtp_set_weights
    stack_bytes: int  #: deepest stack measured below the caller's SP
    update_at: int
    cycles: dict = None  #: input kind -> list of cycles per step (the image's cycle model)
    bound: object = None  #: wake.firmware.wcet.Bound of this configuration (static)
    build: str = ""  #: "" for the default build, else the variant's name (LEAN_BUILD: "WAKE_RTP_AHEAD=0")

    def all_counts(self, *, priming=True):
        return np.concatenate([np.asarray(c[0 if priming else 1:]) for c in self.counts.values()])

    @property
    def max(self):
        return int(self.all_counts().max())

    @property
    def median(self):
        return float(np.median(self.all_counts()))

    @property
    def min(self):
        return int(self.all_counts().min())

    @property
    def steady_max(self):
        """Worst case without the first (priming) sample of a stream."""
        return int(self.all_counts(priming=False).max())

    @property
    def priming(self):
        return int(max(c[0] for c in self.counts.values()))

    @property
    def after_update(self):
        """Worst step right after a weight update."""
        return int(max(c[self.update_at] for c in self.counts.values()))

    @property
    def max_cycles(self):
        return int(max(max(c) for c in self.cycles.values())) if self.cycles else None

    def worst(self):
        """(input kind, sample index, instructions) of the worst step."""
        best = None
        for kind, c in self.counts.items():
            i = int(np.argmax(c))
            if best is None or c[i] > best[2]:
                best = (kind, i, int(c[i]))
        return best

    def as_dict(self):
        kind, idx, _ = self.worst()
        return {
            "target": self.target, "build": self.build, "level": self.level, "wavelet": self.wavelet,
            "kalman": self.kalman, "max": self.max, "median": self.median, "min": self.min, "steady_max": self.steady_max,
            "priming": self.priming, "after_update": self.after_update, "worst_input": kind,
            "worst_index": idx, "set_weights": self.set_weights, "stack_bytes": self.stack_bytes,
            "floor_macs": arithmetic_floor(self.level),
            "per_input_max": {k: int(max(v)) for k, v in self.counts.items()},
            "max_cycles": self.max_cycles,
            "bound_instructions": self.bound.instructions if self.bound else None,
            "bound_cycles": self.bound.cycles if self.bound else None,
            "bound_loops": [(f, int(h), int(n)) for f, h, n in self.bound.loops] if self.bound else None,
            "bound_callees": self.bound.callees if self.bound else None,
        }


#: What an inert Kalman never calls (both behind ``if (!s->inert)`` in internal/wake_rtp_sample.h): the inert bound leaves them out.
INERT_EXCLUDED = ("wake_rtpi_kalman_update", "wake_rtpi_time_update")


def profile_configuration(emu: Emulator, wavelet="sym3", level=5, *, kalman=True, n=None, kinds=None,
                          seed=0) -> StepProfile:
    """Run every input kind through ``wake_rtp_step`` and count each step.

    Each kind starts from a fresh ``wake_rtp_init``; the weights are updated
    (``wake_rtp_set_weights``) before sample ``n // 2``.
    """
    params = fitted_parameters(wavelet, level, kalman=kalman, formats=emu.formats)
    n = int(n or max(128, 4 * 2**level))
    update_at = n // 2
    inputs = adversarial_inputs(level, n, seed=seed, measurement=params["measurement"])
    if kinds is not None:
        inputs = {k: v for k, v in inputs.items() if k in kinds}
    counts, cycles = {}, {}
    sw = 0
    stack = 0
    emu.write_config(params)
    for kind, x in inputs.items():
        emu.init()
        c, cy = [], []
        for i, sample in enumerate(x):
            if i == update_at:
                sw = emu.set_weights()
            _, ni, depth = emu.step(int(sample), stack=(i < 2 or i == update_at))
            c.append(ni)
            cy.append(emu.last_cycles)
            if depth is not None:
                stack = max(stack, depth)
        counts[kind] = c
        cycles[kind] = cy
    from wake.firmware.wcet import static_bound

    bound = static_bound(emu.image, level, exclude=() if kalman else INERT_EXCLUDED)
    return StepProfile(emu.image.target, int(level), wavelet, bool(kalman), counts, sw, stack, update_at,
                       cycles, bound)


PHASES = ("wake_rtpi_check_structure", "push", "wake_rtpi_kalman_update", "wake_rtpi_time_update", "predict")


def hotspots(emu: Emulator, wavelet="sym3", level=5, *, kalman=True, n=None):
    """Where the worst step of a configuration spends its instructions.

    Each executed block is attributed with ``addr2line -i`` (inlined frames
    resolved; the image carries debug information) to its phase (the
    outermost of :data:`PHASES` in its inline chain), its innermost function
    and its source line.  Returns a dict with ``total``, the worst step's
    ``input`` and ``index``, and ``phase``, ``function``, ``line`` lists of
    ``(name, instructions, share)`` sorted by cost.
    """
    prof = profile_configuration(emu, wavelet, level, kalman=kalman, n=n)
    kind, idx, total = prof.worst()
    params = fitted_parameters(wavelet, level, kalman=kalman, formats=emu.formats)
    x = adversarial_inputs(level, len(prof.counts[kind]), measurement=params["measurement"])[kind]
    emu.write_config(params)
    emu.init()
    for i, sample in enumerate(x[: idx + 1]):
        if i == prof.update_at:
            emu.set_weights()
        emu.counter.keep_hits = i == idx
        emu.step(int(sample))
    hits = dict(emu.counter.hits)
    emu.counter.keep_hits = False
    chains = _inline_chains(emu.image, [a for a, _ in hits])
    src_lines = emu.image.source.read_text().splitlines() if emu.image.source else []

    def line_label(func, line):
        text = src_lines[int(line) - 1].strip() if line.isdigit() and int(line) <= len(src_lines) else ""
        text = text if len(text) <= 70 else text[:67] + "..."
        return f"{func}:{line} `{text}`" if text else f"{func}:{line}"

    tallies = {"phase": {}, "function": {}, "line": {}}
    for (addr, size), h in hits.items():
        cnt = h * emu.counter.instructions_in(addr, size)
        chain = chains.get(addr) or [("?", "?")]
        phase = next((f for f, _ in reversed(chain) if f in PHASES), chain[-1][0])
        func, line = chain[0]
        for key, name in (("phase", phase), ("function", func), ("line", line_label(func, line))):
            tallies[key][name] = tallies[key].get(name, 0) + cnt
    tot = sum(tallies["phase"].values())
    out = {"total": tot, "input": kind, "index": idx}
    for key, tab in tallies.items():
        out[key] = [(name, c, c / tot) for name, c in sorted(tab.items(), key=lambda kv: -kv[1])]
    return out


def _inline_chains(image: Image, addrs):
    """Per address, the inline chain ``[(function, line), ...]``, innermost first (addr2line -i)."""
    funcs = image.functions()
    starts = [f[0] for f in funcs]
    out = {}
    for a in addrs:
        k = bisect.bisect_right(starts, a) - 1
        out[a] = [(funcs[k][2] if k >= 0 and a < funcs[k][1] else "?", "?")]
    tool = toolchain().get("addr2line")
    if tool is None:
        return out
    addrs = sorted(set(addrs))
    # -a prints each address, then 1+ (function, file:line) pairs, innermost inline frame first.
    proc = subprocess.run([tool, "-f", "-i", "-a", "-e", str(image.elf)],
                          input="\n".join(f"{a:#x}" for a in addrs) + "\n", capture_output=True, text=True)
    if proc.returncode != 0:
        return out
    lines = proc.stdout.splitlines()
    current, i = None, 0
    while i < len(lines):
        if lines[i].startswith("0x"):
            current = int(lines[i], 16)
            out[current] = []
            i += 1
            continue
        where = lines[i + 1] if i + 1 < len(lines) else "?:?"
        line = where.rsplit(":", 1)[-1].split()[0] if ":" in where else "?"
        out[current].append((lines[i].strip(), line))
        i += 2
    return out
