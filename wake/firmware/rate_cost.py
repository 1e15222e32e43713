"""What an input rate costs the C core: the front end's push beside the RTP step (issue 33).

Above 150 Hz a firmware pushes every input sample into the front end
(``csrc/wake_rate.c``) and steps the RTP once per group of ``D`` samples
(:func:`wake.sampling.decimation_for`).  Two ways to do it:

* unsplit: ``wake_rate_push`` on every input sample and ``wake_rtp_step`` on
  the one that ends a group, which then costs push + step;
* split (``WAKE_RTP_SPLIT 1``): ``wake_rate_step`` on every input sample,
  which runs ``wake_rtp_prepare`` (the part of the step that does not need
  the group's mean) on the sample before a group's end and
  ``wake_rtp_finish`` on the end; its static bound is the worst input sample.

From the static bounds of these functions (:func:`wake.firmware.wcet.static_bound`):
the worst input sample and the work per second, beside 100 Hz.
"""

from __future__ import annotations

from wake.sampling import decimation_for

__all__ = ["SPLIT_KEYS", "rate_cost", "rate_lines"]

#: The bounds a split build gives :func:`rate_cost`: the push, the prepare, the longer finish
#: (measured or missing) and ``wake_rate_step`` (the worst input sample).
SPLIT_KEYS = ("push", "prepare", "finish", "rate_step")


def rate_cost(fs: float, step: int, push: int | None, split: dict | None = None) -> dict:
    """Instructions (or cycles) of the worst input sample and per second at ``fs`` Hz.

    Parameters
    ----------
    fs : float
        Input rate, Hz.
    step : int
        Static bound of ``wake_rtp_step``.
    push : int or None
        Static bound of ``wake_rate_push`` (not run at ``D = 1``, and may be None there).
    split : dict, optional
        Bounds of the split build, keys :data:`SPLIT_KEYS`; then the worst input sample is
        ``split["rate_step"]`` and a second holds ``fs`` pushes and ``fs / D`` prepares and finishes.
        Without it the unsplit path: the worst input sample is push + step.

    Examples
    --------
    >>> from wake.firmware.rate_cost import rate_cost
    >>> rate_cost(1000.0, 493, 63)
    {'fs': 1000.0, 'decimation': 10, 'bank_rate': 100.0, 'per_sample': 556, 'per_second': 112300.0}
    >>> rate_cost(1000.0, 493, 63, {"push": 63, "prepare": 396, "finish": 367, "rate_step": 451})["per_sample"]
    451
    >>> rate_cost(100.0, 493, None)["per_second"]
    49300.0
    """
    D = decimation_for(fs)
    if D > 1 and push is None:
        raise ValueError(f"fs = {fs:g} Hz needs the front end (decimation {D}): give the bound of wake_rate_push")
    if split is not None and set(split) != set(SPLIT_KEYS):
        raise ValueError(f"split needs exactly the bounds {', '.join(SPLIT_KEYS)}; got {', '.join(sorted(split))}")
    out = {"fs": float(fs), "decimation": D, "bank_rate": fs / D}
    if D == 1:
        return {**out, "per_sample": step, "per_second": fs * step}
    if split is None:
        return {**out, "per_sample": step + push, "per_second": fs * push + (fs / D) * step}
    return {**out, "per_sample": split["rate_step"],
            "per_second": fs * split["push"] + (fs / D) * (split["prepare"] + split["finish"])}


def rate_lines(fs: float, bounds: dict) -> list:
    """Markdown lines of :func:`rate_cost` per target and build.

    ``bounds``: target -> {build label: {"step": wake_rtp_step of the 100 Hz build, "push":
    wake_rate_push of the same build or None, "split": the split build's bounds (:data:`SPLIT_KEYS`) or
    None}}.
    """
    D = decimation_for(fs)
    head = f"## Cost at {fs:g} Hz (front end by {D}, bank at {fs / D:g} Hz; static bounds, J = 5)"
    if D == 1:
        out = [head, "", "No front end at this rate: an input sample is one wake_rtp_step.", "",
               "| target | build | wake_rtp_step = worst input sample | per second |", "|---|---|---:|---:|"]
        for t, builds in bounds.items():
            for label, b in builds.items():
                c = rate_cost(fs, b["step"], None)
                out.append(f"| {t} | {label} | {c['per_sample']:,} | {c['per_second']:,.0f} |")
        return out + [""]
    out = [head, "",
           "| target | build | at 100 Hz: wake_rtp_step | wake_rate_push | prepare | finish (longer of "
           "measured, missing) | worst input sample, unsplit (push + step) | worst input sample, split "
           "(wake_rate_step) | split / 100 Hz | per second, split | per second at 100 Hz |",
           "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for t, builds in bounds.items():
        for label, b in builds.items():
            base = rate_cost(100.0, b["step"], None)
            unsplit = rate_cost(fs, b["step"], b["push"])
            s = b["split"]
            if s is None:
                out.append(f"| {t} | {label} | {b['step']:,} | {b['push']:,} | - | - | {unsplit['per_sample']:,} "
                           f"| - | - | - | {base['per_second']:,.0f} |")
                continue
            c = rate_cost(fs, b["step"], b["push"], s)
            out.append(f"| {t} | {label} | {b['step']:,} | {s['push']:,} | {s['prepare']:,} | {s['finish']:,} | "
                       f"{unsplit['per_sample']:,} | {c['per_sample']:,} | {c['per_sample'] / b['step']:.3f} | "
                       f"{c['per_second']:,.0f} | {base['per_second']:,.0f} |")
    return out + ["", "The split build is the core and front end compiled with -DWAKE_RTP_SPLIT=1; the 100 Hz "
                  "step is the default build's. Per second, split: a push per input sample, a prepare and a "
                  "finish per group (each function's own bound; wake_rate_step's dispatch adds a few "
                  "instructions per sample).", ""]
