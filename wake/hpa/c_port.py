"""The single-precision C port of the HPA (``csrc/wake_hpa.c``), run from Python.

The Python HPA (:func:`wake.hpa.run_hpa`) stays the reference; this module
only exists so that the C port can be tested against it and so that
``WakeFilter(hpa_backend="c")`` runs the whole pipeline a standalone device
runs.  The C HPA reads the window as the RTP does: int16 Q15 of a full
scale.  docs/studies/hpa_c.md records how closely it agrees.
"""

from __future__ import annotations

import numpy as np

from wake.config import RIDGE_SCALES, WakeConfig
from wake.hpa.cutoff import CUTOFF_FLAGS, EDGE_DB, FLOOR_MARGIN_DB, FLOOR_STRIDE, MIN_DEPTH_DB
from wake.hpa.run import HPAUpdate, clean_only_below
from wake.registry import cutoff_rule_names, cutoff_rules, get_cutoff_rule
from wake.rtp.full_scale import GLITCH_SHARE, power_of_two_at_least
from wake.target import TARGET
from wake.wavelets import default_weights

__all__ = ["c_flag_name", "c_mirror_problems", "hpa_config", "hpa_config_fields", "quantize_window", "run_hpa_c",
           "check_c_hpa_config", "update_from_result", "window_full_scale"]

#: 10^(-MIN_DEPTH_DB / 10): the valley depth of :func:`wake.hpa.find_cutoff` as a ratio of PSD values
MIN_DEPTH_RATIO = 10.0 ** (-MIN_DEPTH_DB / 10.0)
#: 10^(-FLOOR_MARGIN_DB / 10) and 10^(-EDGE_DB / 10): rule "floor"'s margins as ratios of PSD values
FLOOR_RATIO = 10.0 ** (-FLOOR_MARGIN_DB / 10.0)
EDGE_RATIO = 10.0 ** (-EDGE_DB / 10.0)
#: Warm-up points wake_hpa_config_t holds (WAKE_HPA_MAX_WARMUP; :func:`c_mirror_problems` checks it)
MAX_WARMUP = 8
_Q15 = 32768.0


_LOADED = None   # (ffi, lib) once the compiled core has loaded


def _core():
    global _LOADED
    if _LOADED is None:
        from wake.rtp import load_fixed_point

        load_fixed_point()  # CoreUnavailable with how to build it
        from wake._rtp import ffi, lib

        _LOADED = ffi, lib
    return _LOADED


def c_flag_name(flag: str) -> str:
    """The ``wake_hpa_flag_t`` enumerator of a key of :data:`wake.hpa.CUTOFF_FLAGS` (``"valley"`` ->
    ``WAKE_HPA_VALLEY``)."""
    return "WAKE_HPA_" + flag.upper()


def c_mirror_problems(lib) -> list:
    """Where the Python side and the compiled C HPA ``lib`` disagree: the one check of every number the
    two both state.  Each registered cut-off rule (:mod:`wake.registry`) must have its ``c_name`` numbered
    by its place in the registry, each key of :data:`~wake.hpa.CUTOFF_FLAGS` its :func:`c_flag_name`;
    each of :data:`~wake.config.RIDGE_SCALES` its ``WAKE_HPA_RIDGE_*`` numbered by its place there;
    ``MAX_WARMUP``, ``FLOOR_STRIDE`` and the prediction target's horizon (:mod:`wake.target`) must equal
    the header's, and the share of a window at full scale that shuts the tremor ahead's gate
    (:data:`~wake.rtp.full_scale.GLITCH_SHARE`) must be ``1 / WAKE_HPA_GLITCH_DIVISOR``.  Returns one message
    per problem."""
    problems = []
    for number, rule in enumerate(cutoff_rules()):
        have = getattr(lib, rule.c_name, None)
        if have is None:
            problems.append(f"cut-off rule {rule.name!r}: {rule.c_name} is not in wake_hpa_rule_t "
                            "(add it to csrc/wake_hpa.h and its case to csrc/wake_hpa_spectrum.c)")
        elif int(have) != number:
            problems.append(f"cut-off rule {rule.name!r}: {rule.c_name} = {int(have)}, but it is rule number "
                            f"{number} in wake.registry (register the rules in the enumerators' order)")
    for number, flag in enumerate(CUTOFF_FLAGS):
        have = getattr(lib, c_flag_name(flag), None)
        if have is None or int(have) != number:
            problems.append(f"cut-off flag {flag!r}: {c_flag_name(flag)} = {have}, expected {number} "
                            "(wake_hpa_flag_t follows the order of wake.hpa.CUTOFF_FLAGS)")
    for name, value in (("WAKE_HPA_MAX_WARMUP", MAX_WARMUP), ("WAKE_HPA_FLOOR_STRIDE", FLOOR_STRIDE),
                        ("WAKE_HPA_HORIZON", TARGET.horizon)):
        if int(getattr(lib, name)) != value:
            problems.append(f"{name} = {int(getattr(lib, name))}, the Python side says {value}")
    for number, rule in enumerate(RIDGE_SCALES):
        name = "WAKE_HPA_RIDGE_" + rule.upper()
        have = getattr(lib, name, None)
        if have is None or int(have) != number:
            problems.append(f"ridge_scale {rule!r}: {name} = {have}, expected {number} (wake_hpa_ridge_scale_t "
                            "follows the order of wake.config.RIDGE_SCALES)")
    if 1.0 / int(lib.WAKE_HPA_GLITCH_DIVISOR) != GLITCH_SHARE:
        problems.append(f"WAKE_HPA_GLITCH_DIVISOR = {int(lib.WAKE_HPA_GLITCH_DIVISOR)}, but "
                        f"wake.rtp.full_scale.GLITCH_SHARE = {GLITCH_SHARE!r} (the C HPA's clipping rule must be "
                        "1 / GLITCH_SHARE)")
    return problems


def check_c_hpa_config(config: WakeConfig) -> None:
    """Raise ``ValueError`` naming the limit when the compiled C HPA cannot run ``config``."""
    _, lib = _core()
    problems = []
    if config.window_samples > lib.WAKE_HPA_MAX_WINDOW:
        problems.append(f"the window L = {config.window_samples} samples exceeds WAKE_HPA_MAX_WINDOW = "
                        f"{lib.WAKE_HPA_MAX_WINDOW} (shorten window_s)")
    if config.ar_order > lib.WAKE_HPA_MAX_ORDER:
        problems.append(f"ar_order = {config.ar_order} exceeds WAKE_HPA_MAX_ORDER = {lib.WAKE_HPA_MAX_ORDER}")
    if config.level > lib.WAKE_HPA_MAX_LEVEL:
        problems.append(f"level = {config.level} exceeds WAKE_HPA_MAX_LEVEL = {lib.WAKE_HPA_MAX_LEVEL}")
    if config.cutoff_range[1] >= config.fs / 2:
        problems.append(f"cutoff_range[1] = {config.cutoff_range[1]:g} Hz must lie below fs/2 = {config.fs / 2:g} Hz")
    if config.cutoff_range[1] * lib.WAKE_HPA_PSD_GRID / config.fs >= lib.WAKE_HPA_MAX_PSD_BINS - 1:
        problems.append(f"cutoff_range[1] = {config.cutoff_range[1]:g} Hz at fs = {config.fs:g} Hz needs more than "
                        f"WAKE_HPA_MAX_PSD_BINS = {lib.WAKE_HPA_MAX_PSD_BINS} spectrum bins")
    top = (lib.WAKE_HPA_MAX_PSD_BINS - 1) * (config.fs / lib.WAKE_HPA_PSD_GRID)   # wake_hpa.c's config_ok
    if config.gate_cutoff is not None and not config.gate_cutoff < top:
        problems.append(f"gate_cutoff = {config.gate_cutoff:g} Hz at fs = {config.fs:g} Hz needs more DFT bins than "
                        f"WAKE_HPA_MAX_PSD_BINS = {lib.WAKE_HPA_MAX_PSD_BINS} hold: the C HPA takes 0 < gate_cutoff "
                        f"< {top:g} Hz (or None)")
    if len(config.hpa_points()) > lib.WAKE_HPA_MAX_WARMUP:
        problems.append(f"{len(config.hpa_points())} warm-up points exceed WAKE_HPA_MAX_WARMUP = "
                        f"{lib.WAKE_HPA_MAX_WARMUP} (pass fewer warmup_hpa_s)")
    rule = get_cutoff_rule(config.cutoff_rule)
    if getattr(lib, rule.c_name, None) is None:
        problems.append(f"cutoff_rule {rule.name!r} has no C function ({rule.c_name} is not in wake_hpa_rule_t)")
    if problems:
        raise ValueError("hpa_backend='c' cannot run this configuration: " + "; ".join(problems)
                         + "; use hpa_backend='python'")


def hpa_config_fields(config: WakeConfig) -> dict:
    """The fields of ``wake_hpa_config_t`` for ``config``, by name (floats for float fields, ints for
    integer ones, ``warmup`` padded with zeros); no compiled core needed (``wake export-header`` renders them)."""
    points = list(config.hpa_points())
    if len(points) > MAX_WARMUP:
        raise ValueError(f"the C HPA holds at most {MAX_WARMUP} warm-up points, this configuration has "
                         f"{len(points)} ({config.warmup_hpa_s!r} s); pass fewer warmup_hpa_s")
    return {"fs": config.fs, "tremor_low": config.tremor_band[0], "tremor_high": config.tremor_band[1],
            "cutoff_low": config.cutoff_range[0], "cutoff_high": config.cutoff_range[1],
            "shallow_high": config.shallow_max,
            "default_cutoff": config.default_cutoff, "min_depth_ratio": MIN_DEPTH_RATIO,
            "floor_ratio": FLOOR_RATIO, "edge_ratio": EDGE_RATIO, "ridge": config.ridge,
            "process_noise_ratio": config.process_noise_ratio,
            "gate_cutoff": 0.0 if config.gate_cutoff is None else config.gate_cutoff,
            "ridge_scale": RIDGE_SCALES.index(config.ridge_scale), "window": config.window_samples,
            "level": config.level, "ar_order": config.ar_order, "rule": cutoff_rule_names().index(config.cutoff_rule),
            "clean_below": clean_only_below(config), "horizon": 1, "warmup": points + [0] * (MAX_WARMUP - len(points))}


def hpa_config(config: WakeConfig):
    """The ``wake_hpa_config_t`` of a :class:`~wake.WakeConfig` (what ``wake export-c`` writes)."""
    ffi, _ = _core()
    c = ffi.new("wake_hpa_config_t *")
    for name, value in hpa_config_fields(config).items():
        setattr(c, name, value)
    return c


def window_full_scale(window) -> float:
    """The smallest power of two that holds every sample of ``window`` (1.0 for a zero window)."""
    peak = float(np.max(np.abs(window))) if len(window) else 0.0
    return power_of_two_at_least(peak * (1 + 2**-14)) if peak > 0 else 1.0


def quantize_window(x, full_scale: float) -> np.ndarray:
    """``x`` as the int16 Q15 samples of ``full_scale`` the C HPA reads: rounded half to even, clipped."""
    return np.clip(np.rint(np.asarray(x, dtype=float) * (_Q15 / full_scale)), -32768, 32767).astype(np.int16)


#: The cut-off flags by the C HPA's enumerator (its place in the registry)
_FLAG_NAMES = tuple(CUTOFF_FLAGS)

#: (config, horizon, taps) -> (wake_hpa_config_t, int16 taps) of configurations that passed
#: check_c_hpa_config: an HPA of a stream checks, fills and quantises them once, not once per window
_PREPARED: dict = {}
_PREPARED_MAX = 32


def _prepared(config: WakeConfig, taps, horizon: int):
    """``check_c_hpa_config(config)``, then the ``wake_hpa_config_t`` at ``horizon`` and the int16 taps,
    remembered per (config, horizon, taps): wake_hpa_init copies the struct, so one serves every instance."""
    ffi, _ = _core()
    from wake.rtp.qformat import quantize_taps

    t = np.asarray(taps)
    try:
        key = (config, int(horizon), t.shape, t.dtype.str, t.tobytes())
        hit = _PREPARED.get(key)
    except TypeError:   # a configuration holding something unhashable: prepared every time
        key, hit = None, None
    if hit is not None:
        return hit
    check_c_hpa_config(config)
    cfg = hpa_config(config)
    cfg.horizon = horizon
    taps_q = np.ascontiguousarray(quantize_taps(taps), dtype=np.int16)
    taps_q.flags.writeable = False   # shared by every instance that reads it
    if key is not None:
        if len(_PREPARED) >= _PREPARED_MAX:
            _PREPARED.clear()
        _PREPARED[key] = (cfg, taps_q)
    return cfg, taps_q


def _instance(config: WakeConfig, taps, weights, name: str, *, horizon: int = 1, prepared=None):
    """A C HPA instance of ``config`` over ``taps`` with ``weights`` in use (the start-up weights,
    :func:`~wake.wavelets.default_weights`, when None; clipped to the C HPA's weight limit), and the
    quantised taps it points into: keep them alive as long as the instance.  ``prepared``: what
    :func:`_prepared` gave for them (looked up when None)."""
    ffi, lib = _core()
    J = config.level
    w0 = np.clip(np.asarray(default_weights(J) if weights is None else weights, dtype=np.float32),
                 -lib.WAKE_HPA_WEIGHT_LIMIT, lib.WAKE_HPA_WEIGHT_LIMIT)
    if w0.shape != (J,) or not np.isfinite(w0).all():
        raise ValueError(f"{name} must be {J} finite numbers, got {weights!r}")
    cfg, taps_q = _prepared(config, taps, horizon) if prepared is None else prepared
    h = ffi.new("wake_hpa_t *")
    status = lib.wake_hpa_init(h, cfg, ffi.from_buffer("int16_t[]", taps_q), ffi.from_buffer("float[]", w0))
    if status != lib.WAKE_HPA_OK:
        raise ValueError(f"wake_hpa_init refused the configuration (status {status})")
    return h, taps_q


def _previous_ahead(h, previous_ahead, index: int, new_samples: int):
    """Give a fresh instance the previous HPA's tremor-ahead predictor, as that HPA's instance would hold it
    (its index ``new_samples`` before ``index``), so its held-out gain scores it: ``wake_hpa_set_previous_ahead``,
    which checks the coefficients."""
    if previous_ahead is None:
        return
    ffi, lib = _core()
    taps = int(lib.WAKE_HPA_AHEAD_TAPS)
    c = np.ascontiguousarray(previous_ahead, dtype=np.float32)
    if c.shape != (taps,):
        raise ValueError(f"previous_ahead must be {taps} finite coefficients within [-8, 8], got {previous_ahead!r}")
    if isinstance(new_samples, bool) or not 0 <= int(new_samples) <= int(index):
        raise ValueError(f"new_samples must be an integer in 0..index = {index}, got {new_samples!r}")
    status = lib.wake_hpa_set_previous_ahead(h, ffi.from_buffer("float[]", c), (int(index) - int(new_samples)) & 0xFFFFFFFF)
    if status != lib.WAKE_HPA_OK:
        raise ValueError(f"previous_ahead must be {taps} finite coefficients within [-8, 8] (the predictor an HPA "
                         f"produces), got {previous_ahead!r} (wake_hpa_set_previous_ahead: status {status})")


def run_hpa_c(window, config: WakeConfig, *, taps, previous_weights=None, index: int = 0,
              full_scale: float | None = None, previous_ahead=None, new_samples: int = 0) -> HPAUpdate:
    """One HPA run by the C port: what :func:`wake.hpa.run_hpa` returns, computed in single precision.

    Parameters
    ----------
    window : array_like, shape (n,)
        Finite samples, oldest first, ``2 * 2**level <= n <= L``.
    config : WakeConfig
    taps : numpy.ndarray, shape (J, 2**J)
        The filter bank; the C HPA reads it as int16 Q15, as the RTP does.
    previous_weights : array_like, optional
        Kept when the window is silent (default: the deepest approximation alone).
    index : int
        Recorded in the result.
    full_scale : float, optional
        The physical value of Q15 1.0 the window is quantised with (the
        RTP's full scale).  Default: :func:`window_full_scale`.
    previous_ahead : array_like, shape (8,), optional
        The previous HPA's tremor-ahead predictor (None before the first HPA), scored on the
        ``new_samples`` samples since it, as in :func:`wake.hpa.run_hpa`.
    new_samples : int
        Samples received since the previous HPA.

    Returns
    -------
    HPAUpdate
        With the C HPA's tremor-ahead fit (``WAKE_HPA_AHEAD``) at ``config.horizon``: its predictor and
        goal.  The C HPA publishes the goal, not the gain: ``ahead_gain`` is that goal, which is the gain
        where the window has a tremor peak and 0 where it has none (the C HPA applies
        :func:`wake.ahead.gate_target` itself), or where more than
        :data:`~wake.rtp.full_scale.GLITCH_SHARE` of the quantised window sits at full scale (the C HPA
        applies :func:`wake.ahead.installed_goal`'s rule itself and notes ``"clipping"``).

    Examples
    --------
    >>> import numpy as np
    >>> from wake import WakeConfig
    >>> from wake.hpa.c_port import run_hpa_c
    >>> from wake.wavelets import filter_bank_taps
    >>> t = np.arange(500) / 100.0
    >>> x = np.sin(2 * np.pi * 0.3 * t) + 0.2 * np.sin(2 * np.pi * 8 * t)
    >>> upd = run_hpa_c(x, WakeConfig(), taps=filter_bank_taps("sym3", 5))
    >>> upd.cutoff_flag                                                    
    'valley'
    """
    ffi, lib = _core()
    prepared = _prepared(config, taps, config.horizon)   # check_c_hpa_config, once per configuration
    x = np.asarray(window, dtype=float)
    J, N = config.level, 2**config.level
    if x.ndim != 1 or not N * 2 <= x.size <= config.window_samples:
        raise ValueError(f"window must be 1-D with {2 * N}..{config.window_samples} samples, got shape {x.shape}")
    if not np.isfinite(x).all():
        raise ValueError("window holds NaN or inf; interpolate gaps first (WakeFilter does)")
    fs_scale = window_full_scale(x) if full_scale is None else float(full_scale)
    if not (np.isfinite(fs_scale) and fs_scale > 0):
        raise ValueError(f"full_scale must be finite and > 0, got {full_scale!r}")
    q = quantize_window(x, fs_scale)
    h, _taps_q = _instance(config, taps, previous_weights, "previous_weights", horizon=config.horizon,
                           prepared=prepared)
    _previous_ahead(h, previous_ahead, index, new_samples)
    q_c = ffi.from_buffer("int16_t[]", q)
    status = lib.wake_hpa_start(h, q_c, q.size, int(index) & 0xFFFFFFFF)
    if status != lib.WAKE_HPA_OK:
        raise ValueError(f"wake_hpa_start refused the window (status {status})")
    status = lib.wake_hpa_run(h)
    res = ffi.new("wake_hpa_result_t *")
    if status != lib.WAKE_HPA_DONE or lib.wake_hpa_take(h, res) != lib.WAKE_HPA_OK:
        raise RuntimeError(f"the C HPA did not finish (status {status})")
    return update_from_result(res, index, fs_scale, J)


def update_from_result(res, index: int, full_scale: float, level: int, *, applied_at: int = -1,
                       flags: tuple = ()) -> HPAUpdate:
    """The :class:`~wake.hpa.HPAUpdate` of a ``wake_hpa_result_t`` of a window quantised at ``full_scale``
    (R and e_L in physical units; :func:`run_hpa_c` and the batch driver, :mod:`wake.hpa.c_batch`, which records
    its ``applied_at`` and adds its install's ``flags`` after the result's own, each once)."""
    ffi, lib = _core()
    J, lsb = level, full_scale / _Q15
    # "clipping": the C HPA has applied wake.ahead.installed_goal's rule (its goal is 0)
    bits = res.notes
    notes = [name for bit, name in ((lib.WAKE_HPA_NOTE_REGULARISED, "regularised"),
                                    (lib.WAKE_HPA_NOTE_WEIGHTS_KEPT, "weights_kept"),
                                    (lib.WAKE_HPA_NOTE_CLIPPED, "weights_clipped"),
                                    (lib.WAKE_HPA_NOTE_FULL_SCALE, "clipping")) if bits & bit] if bits else []
    notes += [flag for flag in flags if flag not in notes]
    weights = np.array(ffi.unpack(res.weights, J), dtype=float)
    flag, goal = _FLAG_NAMES[res.flag], float(res.ahead_goal)
    return HPAUpdate(int(index), float(res.cutoff), flag, weights,
                     float(res.measurement_noise) * lsb * lsb, float(np.sqrt(res.fit_mse)) * lsb,
                     float(res.ridge), tuple(notes), applied_at=applied_at,
                     ahead_coefficients=np.array(ffi.unpack(res.ahead, len(res.ahead)), dtype=float),
                     ahead_gain=goal, ahead_goal=goal)
