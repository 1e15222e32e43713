"""WakeConfig: every setting of a WAKE filter, validated once.

This module is the one place where the settings are checked: the weight
bound the HPA keeps, the valid choices of every option and the numeric
ranges the constructor accepts.  What lower layers share lives below it:
the highest decomposition level in :mod:`wake.limits`, the cut-off rules in
:mod:`wake.registry`.
The C core's own limits (``WAKE_RTP_MAX_LEVEL``, the Q formats) are checked
against these by the test suite.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, fields

from wake._core import CoreMissingWarning, default_backend as _default_backend
from wake._validation import check_level, check_mode, check_number, check_pair, check_wavelet
from wake.ahead import MAX_HORIZON, bank_horizon, check_horizon
from wake.limits import MAX_LEVEL
from wake.sampling import TUNED_RATES, RateWarning, decimation_for, sample_counts, warn_if_far_from_tuned_rate  # noqa: F401
from wake.registry import cutoff_rule_names

__all__ = ["CoreMissingWarning", "RateWarning", "TUNED_RATES", "WakeConfig", "MAX_LEVEL",
           "WEIGHT_LIMIT", "BACKENDS", "HPA_BACKENDS", "HPA_MODES", "FITS", "RIDGE_SCALES", "LIMITS"]

#: Largest |weight| the HPA hands over.  The C core holds weights in Q24 and
#: accepts |w| <= 64; keeping the HPA at half of that leaves room for the
#: rounding of any later rescaling.
WEIGHT_LIMIT = 32.0
#: Where the RTP runs: the fixed-point C core or the float64 reference.
BACKENDS = ("c", "reference")
#: Streaming HPA: inside ``update()`` or on a worker thread.
HPA_MODES = ("inline", "thread")
#: Where the HPA runs: the Python reference (float64) or the single-precision C port (csrc/wake_hpa.c).
HPA_BACKENDS = ("python", "c")
#: What the HPA fits ``w`` on (see :mod:`wake.hpa.run`).
FITS = ("causal", "paper")
RIDGE_SCALES = ("gram", "centred")  # what the weight fit's ridge is relative to (wake.hpa.fit.ridge_scale_of)
#: Weights before the first HPA (see :mod:`wake.hpa.prior`).
INITIAL_WEIGHTS = ("prior", "deepest")

#: Accepted range of each number, inclusive unless noted: wide enough for
#: every sensor we know of, narrow enough that nothing overflows a float64 on
#: the way (variances are squared once more inside the Kalman update).
LIMITS = {
    "fs": (0.0, 1e5),                 # Hz, exclusive low
    "window_s": (0.0, 3600.0),        # s, exclusive low
    "ar_order": (1, 512),
    "process_noise_ratio": (0.0, 1e6),
    "initial_covariance": (0.0, 1e100),
    "ridge": (0.0, 1e6),
    "full_scale": (0.0, 1e100),       # exclusive low
    "headroom": (1.0, 1e4),
    "hpa_history_limit": (1, 10**9),
    "horizon": (1, MAX_HORIZON),      # samples
    "shallow_max": (0.0, 1e5),        # Hz, exclusive low; at least cutoff_range[0] (checked beside it)
    "decimation": (1, 1000),
    "gate_cutoff": (0.0, 1e5),        # Hz, exclusive low; below fs/2 (checked beside it)
}

def _number(name: str, value, *, integer: bool = False, low_open: bool = False):
    return check_number(name, value, LIMITS[name], integer=integer, low_open=low_open)


#: Candidate warm-up HPA times (s) of the automatic schedule (docs/studies/design.md, "Warm-up").
AUTO_WARMUP_S = (1.0, 2.0, 3.0, 4.0)


def auto_warmup_points(fs: float, window_s: float, level: int) -> tuple:
    """The automatic warm-up schedule: :data:`AUTO_WARMUP_S` and then every 4 s, each
    before the first full window and holding at least ``2 * 2**level`` samples."""
    need = 2 * 2**level
    L = int(round(window_s * fs))
    times = list(AUTO_WARMUP_S)
    while times[-1] + 4.0 < window_s:
        times.append(times[-1] + 4.0)
    return tuple(t for t in times if need <= int(round(t * fs)) < L)


@dataclass(frozen=True)
class WakeConfig:
    """Every setting of a :class:`~wake.WakeFilter`, validated on construction.

    Parameters
    ----------
    fs : float
        Sampling rate in Hz, in (0, 1e5].
    wavelet : str
        Mother wavelet (a discrete PyWavelets name; the paper: ``"sym3"``).
    level : int
        Decomposition level ``J``, 1 to :data:`MAX_LEVEL`; the RTP window is ``2**J`` samples.
    window_s : float
        HPA window ``L`` in seconds; the HPA runs every ``L`` samples.
        ``L`` must hold at least ``2 * 2**J`` samples and more than ``2 * ar_order``.
    ar_order : int
        Yule-Walker AR order ``p``.
    backend : {"c", "reference"} or None
        ``"c"`` runs the RTP in the fixed-point C core (the code firmware
        runs); ``"reference"`` in the float64 reference it is tested
        against.  ``None`` (the default): ``"c"`` when the compiled core is
        installed (a machine without a C compiler installs without it), else
        ``"reference"``, with a :class:`CoreMissingWarning`; the resolved
        name is what the config holds, and ``WakeResult.backend`` says which
        ran.  An explicit ``"c"`` without the core raises
        :class:`~wake.rtp.CoreUnavailable`, saying how to get it.
    mode : str
        Wavelet boundary mode of the filter bank (docs/studies/design.md).
    fit : {"causal", "paper"}
        What the HPA fits ``w`` on (see :mod:`wake.hpa.run`).
    process_noise_ratio : float
        Kalman process noise relative to the measurement noise: ``Q = q I``
        with ``q = process_noise_ratio * R`` of the current HPA window.  0
        (the default, docs/studies/design.md) keeps the pure filter bank.  The RTP
        classes take the absolute ``q`` (their ``process_noise``).
    initial_covariance : float
        ``P(0) = p0 I`` in squared signal units.
    ridge : float
        Relative ridge of the weight fit.
    ridge_scale : {"gram", "centred"}
        ``ridge`` relative to the Gram matrix (default, the C HPA's) or to its centred form, which gravity
        does not inflate (:func:`wake.hpa.fit.ridge_scale_of`; issue 46; the C HPA's
        ``wake_hpa_config_t::ridge_scale``).
    tremor_band, cutoff_range, default_cutoff
        Cut-off search, see :func:`wake.hpa.find_cutoff`.
    cutoff_rule : {"floor", "paper", "shallow"}
        ``"paper"``: a valley 3 dB deep or the default cut-off (the
        paper's rule).  ``"shallow"``: the same, and where the window has a
        tremor peak but no 3 dB valley, the PSD minimum below the peak and
        at or below ``shallow_max``.  ``"floor"`` (default): as
        ``"shallow"``, with both dips compared to the noise floor above the
        tremor band: a shallow dip at the floor gives the default, a valley
        at the floor moves to the floor's low edge (see
        :func:`wake.hpa.find_cutoff`; docs/studies/design.md, "Cut-off on real
        wear": 33 % instead of 82 % of PADS windows on the default, PADS
        tremor NRMSE 0.101 instead of 0.112, synthetic 0.0701 instead of
        0.0725, whole recordings).
    shallow_max : float
        Highest cut-off the ``"shallow"`` and ``"floor"`` rules take from a
        shallow dip, Hz (default 4, the lower edge of pathological tremor);
        at least ``cutoff_range[0]``.  The ``"paper"`` rule does not read it.
    full_scale : float or None
        C backend: the physical value mapped to the int16 full scale.
        ``None`` (the default) lets it follow the signal, per channel
        (:mod:`wake.rtp.full_scale`): at every HPA, the power of two at or
        above ``headroom`` times the window's robust peak (the 99th
        percentile of ``|x|``, so up to 1 % of glitches cannot set it); up
        at once when 4 samples in a row lie beyond it, down after two
        windows far below it.  The float reference runs until the first
        window with signal.
    headroom : float
        Factor of the automatic full scale, in [1, 1e4].  16 (24 dB) because
        real recordings often start quiet: on the PADS recordings 4x
        clipped, 16x did not (docs/studies/fixed_point.md); it costs 4 of the 16 bits.
    hpa_mode : {"inline", "thread"}
        Streaming only (:meth:`~wake.WakeFilter.update`).  ``"inline"`` runs
        the HPA inside the ``update()`` call that completes a window;
        ``"thread"`` runs it on a worker thread and swaps the new weights in
        between two later samples, so ``update()`` never waits for an HPA.
        Each :class:`~wake.hpa.HPAUpdate` records the sample count at which
        its weights took effect (``applied_at``).  ``run()`` is always inline.
    hpa_backend : {"python", "c"}
        ``"python"`` (default): the float64 reference HPA.  ``"c"``: the
        single-precision C port a standalone device runs
        (:mod:`wake.hpa.c_port`, docs/studies/hpa_c.md), on the window quantised to
        int16 as the RTP sees it.
    warmup_hpa_s : tuple of float or None
        Progressive HPA: times since start (s), each shorter than
        ``window_s``, at which the HPA also runs, on every sample seen so far,
        before the first full window (docs/studies/design.md, "Warm-up").  ``()``
        keeps the paper's schedule (the first HPA at ``window_s``).  Each
        must leave at least ``2 * 2**J`` samples.  ``None`` (the default):
        :func:`auto_warmup_points`, 1, 2, 3 and 4 s at the defaults.  A fit
        on less than 2 s is installed only on a clean valley
        (:data:`wake.hpa.run.CLEAN_ONLY_BELOW_S`).
    initial_weights : {"prior", "deepest"}
        Weights before the first HPA: ``"prior"`` the designed one-step-ahead
        predictor of :func:`wake.hpa.prior.prior_weights`; ``"deepest"`` the
        deepest approximation alone (the first release).
    decimation : int or None
        Input samples per filter-bank sample ``D``: the bank, HPA and RTP run
        at ``fs / D`` behind a causal boxcar front end (:mod:`wake.rate`;
        docs/studies/design.md, "Sampling rates other than 100 Hz").  ``None`` (the
        default): :func:`~wake.sampling.decimation_for`, ``fs / 100`` rounded
        halves up, at least 1: the bank runs at 67-150 Hz, where ``level``,
        ``ar_order`` and ``window_s`` keep their 100 Hz meaning, and below
        150 Hz there is no front end (100 Hz runs as before).
    hpa_history_limit : int
        Streaming only: how many HPA updates per channel
        :attr:`~wake.WakeFilter.hpa_history` keeps (the newest; one update
        is about 420 B, so the default 1,000 is ~0.4 MB per channel, 83 min
        at 100 Hz with 5 s windows).  :meth:`~wake.WakeFilter.run` keeps
        every update of the recording it returns.
    horizon : int
        Samples ahead of the tremor prediction (an actuator's delay ``h``),
        1..32 at the bank's rate, 1..32 D at an input rate D times it:
        ``tremor_ahead``, ``confidence`` and ``command`` of the result are the
        tremor at ``n + h`` predicted at ``n``, the gate and the gated command
        (:mod:`wake.ahead`; docs/studies/design.md, "Tremor ahead").  Above 150 Hz
        the bank predicts ``h / D`` of its samples ahead (rounded) and the
        prediction holds over the ``D`` input samples of a group, like the
        voluntary motion.  The voluntary outputs do not depend on it.
    gate_cutoff : float or None
        The gate's held-out gain (:func:`wake.ahead.held_out_gain`) measured against the window's tremor
        above ``max(f_d, gate_cutoff)`` Hz instead of above ``f_d``: what a rhythm just above the HPA's
        cut-off (a 3-Hz voluntary pronation-supination) predicts then opens no gate.  ``None`` (the
        default): ``f_d``.  4 is the lower edge of pathological tremor (issue 46,
        docs/studies/design.md, "Tremor ahead where tremor is strong").  The C HPA's
        ``wake_hpa_config_t::gate_cutoff`` (0 for None).

    Examples
    --------
    >>> from wake import WakeConfig
    >>> cfg = WakeConfig(fs=100.0, level=5)
    >>> cfg.window_samples, cfg.n_taps
    (500, 32)
    >>> WakeConfig(level=9)
    Traceback (most recent call last):
    ...
    ValueError: level must be from 1 to 6, got 9
    """

    fs: float = 100.0
    wavelet: str = "sym3"
    level: int = 5
    window_s: float = 5.0
    ar_order: int = 17
    backend: str | None = None
    mode: str = "constant"
    fit: str = "causal"
    process_noise_ratio: float = 0.0
    initial_covariance: float = 0.0
    ridge: float = 1e-6
    ridge_scale: str = "gram"
    tremor_band: tuple = (2.5, 15.0)
    cutoff_range: tuple = (0.5, 6.0)
    default_cutoff: float = 2.0
    cutoff_rule: str = "floor"
    shallow_max: float = 4.0
    full_scale: float | None = None
    headroom: float = 16.0
    hpa_mode: str = "inline"
    hpa_backend: str = "python"
    warmup_hpa_s: tuple | None = None
    initial_weights: str = "prior"
    hpa_history_limit: int = 1000
    decimation: int | None = None
    horizon: int = 1
    gate_cutoff: float | None = None

    def __post_init__(self):
        put = lambda name, value: object.__setattr__(self, name, value)  # noqa: E731 (frozen)
        put("fs", _number("fs", self.fs, low_open=True))
        check_wavelet(self.wavelet)
        if self.backend is None:
            put("backend", _default_backend())
        if self.backend not in BACKENDS:
            raise ValueError(f"unknown backend {self.backend!r}; valid choices: {', '.join(BACKENDS)}")
        put("level", check_level(self.level, MAX_LEVEL))
        check_mode(self.mode)
        put("window_s", _number("window_s", self.window_s, low_open=True))
        put("ar_order", _number("ar_order", self.ar_order, integer=True))
        need = max(2 * 2**self.level, 2 * self.ar_order + 1)
        if self.window_samples < need:
            raise ValueError(
                f"the HPA window holds {self.window_samples} samples (window_s * fs); level {self.level} "
                f"and ar_order {self.ar_order} need at least {need}: lengthen window_s to "
                f">= {need / self.fs:g} s or lower the level")
        if self.cutoff_rule not in cutoff_rule_names():
            raise ValueError(f"unknown cutoff_rule {self.cutoff_rule!r}; valid choices: "
                             f"{', '.join(cutoff_rule_names())}")
        for name, choices in (("fit", FITS), ("ridge_scale", RIDGE_SCALES), ("hpa_mode", HPA_MODES),
                              ("hpa_backend", HPA_BACKENDS), ("initial_weights", INITIAL_WEIGHTS)):
            if getattr(self, name) not in choices:
                raise ValueError(f"unknown {name} {getattr(self, name)!r}; valid choices: {', '.join(choices)}")
        for name in ("process_noise_ratio", "initial_covariance", "ridge"):
            put(name, _number(name, getattr(self, name)))
        nyquist = self.fs / 2
        lo, hi = check_pair("tremor_band", self.tremor_band)
        if 0 < lo < hi and hi > nyquist:
            low, high = TUNED_RATES
            raise ValueError(
                f"fs = {self.fs:g} Hz is too low for the tremor band {lo:g}-{hi:g} Hz: its top lies above fs/2 = "
                f"{nyquist:g} Hz, so it needs at least {2 * hi:g} Hz. WAKE supports {low:g}-{high:g} Hz: record or "
                f"resample into that range (from Python, a tremor_band ending at or below {nyquist:g} Hz also serves)")
        if not 0 < lo < hi <= nyquist:
            raise ValueError(f"tremor_band must satisfy 0 < low < high <= fs/2 = {nyquist:g}, got {self.tremor_band!r}")
        clo, chi = check_pair("cutoff_range", self.cutoff_range)
        if not 0 < clo < chi < nyquist:
            raise ValueError(f"cutoff_range must satisfy 0 < low < high < fs/2 = {nyquist:g}, got {self.cutoff_range!r}")
        put("tremor_band", (lo, hi))
        put("cutoff_range", (clo, chi))
        if isinstance(self.default_cutoff, bool) or not isinstance(self.default_cutoff, numbers.Real) \
                or not clo <= float(self.default_cutoff) <= chi:
            raise ValueError(f"default_cutoff must lie in cutoff_range {self.cutoff_range}, got {self.default_cutoff!r}")
        put("default_cutoff", float(self.default_cutoff))
        put("shallow_max", _number("shallow_max", self.shallow_max, low_open=True))
        if self.shallow_max < clo:
            raise ValueError(f"shallow_max must be at least cutoff_range[0] = {clo:g} Hz, got {self.shallow_max!r}")
        if self.full_scale is not None:
            put("full_scale", _number("full_scale", self.full_scale, low_open=True))
        put("headroom", _number("headroom", self.headroom))
        if self.gate_cutoff is not None:
            put("gate_cutoff", _number("gate_cutoff", self.gate_cutoff, low_open=True))
            if not self.gate_cutoff < nyquist:
                raise ValueError(f"gate_cutoff must lie below fs/2 = {nyquist:g} Hz (or be None), got {self.gate_cutoff!r}")
        put("warmup_hpa_s", self._warmup_points())
        put("hpa_history_limit", _number("hpa_history_limit", self.hpa_history_limit, integer=True))
        if self.decimation is not None:
            put("decimation", _number("decimation", self.decimation, integer=True))
        put("horizon", check_horizon(self.horizon, self.fs, self.decimation_factor))
        if self.decimation_factor > 1:  # every setting valid at the rate the bank runs at, too
            try:
                self.bank_config()
            except ValueError as exc:
                raise ValueError(f"with decimation {self.decimation_factor} the filter bank runs at "
                                 f"{self.fs / self.decimation_factor:g} Hz, where {exc}") from None

    @property
    def bank_horizon(self) -> int:
        """The horizon at the bank's rate (:func:`wake.ahead.bank_horizon`)."""
        return bank_horizon(self.horizon, self.decimation_factor)

    def _warmup_points(self) -> tuple:
        if self.warmup_hpa_s is None:
            return auto_warmup_points(self.fs, self.window_s, self.level)
        try:
            points = tuple(self.warmup_hpa_s)
        except TypeError:
            raise ValueError(f"warmup_hpa_s must be a tuple of times in seconds, got {self.warmup_hpa_s!r}") from None
        need = 2 * 2**self.level
        out = []
        for t in points:
            if isinstance(t, bool) or not isinstance(t, numbers.Real) or not math.isfinite(t):
                raise ValueError(f"warmup_hpa_s must hold finite times in seconds, got {self.warmup_hpa_s!r}")
            n = int(round(float(t) * self.fs))
            if not need <= n < self.window_samples:
                raise ValueError(
                    f"warmup_hpa_s: {t:g} s is {n} samples; each warm-up HPA needs at least {need} samples "
                    f"(2 * 2**level) and must come before the first full window ({self.window_samples} samples, "
                    f"{self.window_s:g} s); pass () for none")
            out.append(float(t))
        if out != sorted(set(out)):
            raise ValueError(f"warmup_hpa_s must be strictly increasing, got {self.warmup_hpa_s!r}")
        return tuple(out)

    def hpa_points(self) -> tuple:
        """Sample counts of the warm-up HPA runs (before the first full window)."""
        return sample_counts(self.warmup_hpa_s, self.fs)   # made once per setting (asked at every point)

    def next_hpa(self, count: int) -> int:
        """The sample count of the first HPA after ``count`` samples."""
        L = self.window_samples
        for point in self.hpa_points():
            if point > count:
                return point
        return L if count < L else (count // L + 1) * L

    @property
    def window_samples(self) -> int:
        """``L``, the HPA window in samples."""
        return int(round(self.window_s * self.fs))

    @property
    def decimation_factor(self) -> int:
        """``D``: ``decimation``, or :func:`decimation_for` of ``fs`` when it is None."""
        return decimation_for(self.fs) if self.decimation is None else self.decimation

    def bank_config(self) -> "WakeConfig":
        """The settings of the filter bank, HPA and RTP: these at ``fs / D`` (``self`` when ``D`` is 1).

        Examples
        --------
        >>> from wake import WakeConfig
        >>> cfg = WakeConfig(fs=1000.0, backend="reference")
        >>> cfg.decimation_factor, cfg.bank_config().fs, cfg.bank_config().window_samples
        (10, 100.0, 500)
        """
        D = self.decimation_factor
        return self if D == 1 else self.replace(fs=self.fs / D, decimation=1, horizon=self.bank_horizon)

    @property
    def n_taps(self) -> int:
        """``2**J``, the RTP window in samples."""
        return 2**self.level

    def replace(self, **changes) -> "WakeConfig":
        """A copy with some settings changed (validated again)."""
        values = {f.name: getattr(self, f.name) for f in fields(self)}
        if unknown := set(changes) - set(values):
            raise TypeError(f"unknown setting(s) {sorted(unknown)}; valid: {', '.join(values)}")
        values.update(changes)
        return WakeConfig(**values)
