"""Closed-loop suppression, the field's metric: an actuator driven by a method's command cancels what it can.

A suppression device measures the motion, predicts the tremor ``h`` samples ahead and drives an actuator
that acts after a pure delay of ``h`` samples (the command sent at ``m - h`` plays at ``m``: what
:func:`wake.eval.tremor_ahead.aligned` gives) through its own dynamics, a first- or second-order lag
(:class:`Actuator`).  What it produces is subtracted from the motion.  Scored after 5 s, against the
recording's tremor truth ``T`` (:func:`wake.eval.truth.tremor_truth`; the synthetic sets: their tremor
component) at the truth's cut-off ``f_c``:

* **tremor power reduction** (%), in the tremor band: ``100 (1 - sum (T - A_t)^2 / sum T^2)``, ``A_t`` the
  actuator's output above ``f_c`` (:func:`wake.eval.truth.smooth_highpass`): what is left of the tremor
  after cancellation, as a share of the tremor's power (1 - r^2 for an NRMSE-like ratio ``r``; negative
  when the device adds tremor-band motion);
* **voluntary disturbance** (RMS, the input's units): the actuator's output below ``f_c``, ``A - A_t``, the
  motion it imposes on the voluntary movement.

Defaults (:data:`DEFAULT_ACTUATOR`): a first-order lag of 10 ms (a bandwidth of 16 Hz, above the tremor band
like the motors of the orthoses the field reports; the lag is not compensated by the prediction, whose
horizon is the pure delay alone).  A second-order lag takes a natural frequency and a damping ratio.

Examples
--------
>>> import numpy as np
>>> from wake.eval.suppression import Actuator, suppression
>>> t = np.arange(1500) / 100.0
>>> T = np.sin(2 * np.pi * 6 * t)
>>> red, dist = suppression(T, T, 100.0, 2.0, actuator=Actuator(order=1, tau_ms=1e-6))
>>> bool(red > 99.8), bool(dist < 0.03)        # an ideal actuator playing the true tremor
(True, True)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wake._validation import check_positive
from wake.eval.truth import smooth_highpass

__all__ = ["Actuator", "DEFAULT_ACTUATOR", "actuate", "suppression", "START_S", "suppression_section", "suppression_figure"]

#: Scores start here (s), as the tremor ahead's "after 5 s".
START_S = 5.0


@dataclass(frozen=True)
class Actuator:
    """The actuator's dynamics after its pure delay.

    Parameters
    ----------
    order : {1, 2}
        First-order lag ``1 / (tau s + 1)`` or second-order ``w^2 / (s^2 + 2 zeta w s + w^2)``.
    tau_ms : float
        First order: the time constant, ms (default 10).
    natural_hz : float
        Second order: ``w / 2 pi``, Hz (default 15).
    damping : float
        Second order: ``zeta`` (default 0.7).
    """

    order: int = 1
    tau_ms: float = 10.0
    natural_hz: float = 15.0
    damping: float = 0.7

    def __post_init__(self):
        if self.order not in (1, 2):
            raise ValueError(f"the actuator's order must be 1 (first-order lag) or 2 (second-order), got {self.order!r}")
        check_positive("tau_ms", self.tau_ms)
        check_positive("natural_hz", self.natural_hz)
        check_positive("damping", self.damping)

    def describe(self) -> str:
        return (f"first-order lag, tau {self.tau_ms:g} ms" if self.order == 1 else
                f"second-order lag, {self.natural_hz:g} Hz, damping {self.damping:g}")


#: The actuator of ``wake evaluate``'s suppression section.
DEFAULT_ACTUATOR = Actuator()


def actuate(command, fs, actuator=DEFAULT_ACTUATOR):
    """The actuator's output for a command already delayed (``aligned``): the lag applied along axis 0.

    Examples
    --------
    >>> import numpy as np
    >>> out = actuate(np.ones(200), 100.0, Actuator(order=1, tau_ms=100.0))
    >>> round(float(out[9]), 2), round(float(out[-1]), 3)     # about 1 - exp(-1) after one time constant
    (0.61, 1.0)
    >>> round(float(actuate(np.ones(400), 100.0, Actuator(order=2))[-1]), 3)
    1.0
    """
    import scipy.signal  # here, not at import: it parses docstrings for about a second (issue 44)

    fs = check_positive("fs", fs)
    u = np.asarray(command, dtype=float)
    if actuator.order == 1:                   # both lags by the bilinear transform: the same at any rate
        b, a = scipy.signal.bilinear([1.0], [actuator.tau_ms / 1000.0, 1.0], fs=fs)
        return scipy.signal.lfilter(b, a, u, axis=0)
    if not actuator.natural_hz < fs / 2:
        raise ValueError(f"the actuator's natural frequency must lie below fs/2 = {fs / 2:g} Hz, "
                         f"got {actuator.natural_hz:g}")
    w = 2 * np.pi * actuator.natural_hz
    b, a = scipy.signal.bilinear([w * w], [1.0, 2 * actuator.damping * w, w * w], fs=fs)
    return scipy.signal.lfilter(b, a, u, axis=0)


def suppression(truth, command, fs, cutoff, actuator=DEFAULT_ACTUATOR, start_s=START_S):
    """``(reduction %, disturbance RMS)`` of one channel (module docstring), after ``start_s``.

    Parameters
    ----------
    truth : array_like, shape (n,)
        The true tremor (NaN where unknown: left out).
    command : array_like, shape (n,)
        What plays at each sample, already delayed (``WakeResult.command``, a baseline's aligned extrapolation).
    fs, cutoff : float
        Hz; ``cutoff`` splits the actuator's output into tremor band and voluntary disturbance.
    actuator : Actuator
    start_s : float

    Returns
    -------
    (float, float)
        NaN, NaN when fewer than two scored samples or no tremor power.
    """
    T = np.asarray(truth, dtype=float)
    A = actuate(np.nan_to_num(np.asarray(command, dtype=float)), fs, actuator)
    if T.shape != A.shape or T.ndim != 1:
        raise ValueError(f"truth and command must be 1-D of one length, got {T.shape} and {A.shape}")
    lo = int(round(start_s * fs))
    if A.size < 2 or not np.abs(A).max() > 0:
        A_t = np.zeros_like(A)
    else:
        A_t = smooth_highpass(A, fs, cutoff)
    ok = np.isfinite(T)
    ok[:lo] = False
    power = float(np.sum(T[ok] ** 2))
    if ok.sum() < 2 or not power > 0:
        return float("nan"), float("nan")
    reduction = 100.0 * (1.0 - float(np.sum((T[ok] - A_t[ok]) ** 2)) / power)
    disturbance = float(np.sqrt(np.mean((A - A_t)[ok] ** 2)))
    return reduction, disturbance


# -- in wake evaluate's report --------------------------------------------------------------------------------

_SET_TITLES = {"paper": "Synthetic set", "cohort": "Synthetic cohort", "real": "Recordings",
               "strong": "Strong synthetic set", "pdkit": "pdkit (smartphone)"}


def suppression_section(ahead, actuator=DEFAULT_ACTUATOR):
    """The report's "Closed-loop suppression" section from :func:`wake.eval.tables.ahead_summary`, or "" without
    its numbers.

    Examples
    --------
    >>> part = {"axes": 2, "horizons": {}, "suppression": {20.0: {"zero (the actuator stays off)":
    ...         {"reduction": 0.0, "disturbance": 0.0}}}}
    >>> "| zero (the actuator stays off) | 0.0 % / 0 |" in suppression_section({"real": part})
    True
    """
    parts = {k: p for k, p in (ahead or {}).items() if p.get("suppression")}
    if not parts:
        return ""
    out = ["## Closed-loop suppression", "",
           f"An actuator ({actuator.describe()}) after a pure delay equal to the horizon plays each method's "
           "command and cancels what it can (wake.eval.suppression). Per delay, mean over axes after 5 s: tremor "
           "power reduction in the tremor band (%, higher is better; negative: the device adds tremor-band "
           "motion) / the voluntary motion it disturbs (RMS, the input's units). `fig_suppression.png` draws the "
           "reduction.", ""]
    for key, part in parts.items():
        delays = sorted(part["suppression"])
        methods = list(part["suppression"][delays[0]])
        rows = []
        for m in methods:
            cells = []
            for ms in delays:
                v = part["suppression"][ms].get(m, {})
                r, d = v.get("reduction", float("nan")), v.get("disturbance", float("nan"))
                cells.append("n/a" if not np.isfinite(r) else f"{r:.1f} % / {d:.3g}")
            rows.append(f"| {m} | " + " | ".join(cells) + " |")
        out += [f"**{_SET_TITLES.get(key, key)}**, {part['axes']} axes", "",
                "| method | " + " | ".join(f"{ms:g} ms" for ms in delays) + " |",
                "|---|" + "---:|" * len(delays), *rows, ""]
    return "\n".join(out)


def suppression_figure(ahead, path):
    """``fig_suppression.png``: per set, each method's tremor power reduction against the delay; the path, or
    None without numbers or matplotlib."""
    parts = {k: p for k, p in (ahead or {}).items() if p.get("suppression")}
    if not parts:
        return None
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return None
    fig, axes = plt.subplots(1, len(parts), figsize=(5.5 * len(parts), 4.2), squeeze=False)
    for ax, (key, part) in zip(axes[0], parts.items()):
        delays = sorted(part["suppression"])
        for m in part["suppression"][delays[0]]:
            if m.startswith(("oracle", "limit", "zero")):
                continue
            red = [part["suppression"][ms].get(m, {}).get("reduction", np.nan) for ms in delays]
            ax.plot(delays, red, marker="o", label=m, lw=2.2 if m.startswith("WAKE") else 1.2)
        ax.axhline(0.0, color="k", lw=0.6)
        ax.set_xscale("log")
        ax.set_xticks(delays)
        ax.set_xticklabels([f"{ms:g}" for ms in delays])
        ax.set_ylim(max(-100.0, ax.get_ylim()[0]), 100.0)
        ax.set_xlabel("actuator delay (ms)")
        ax.set_ylabel("tremor power reduction (%)")
        ax.set_title(f"{_SET_TITLES.get(key, key)} ({part['axes']} axes)")
    axes[0][0].legend(fontsize=7, loc="lower left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
