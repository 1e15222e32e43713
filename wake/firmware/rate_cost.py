"""What an input rate costs the C core: the front end's push beside the RTP step (issue 33).

Above 150 Hz a firmware pushes every input sample into the front end
(``csrc/wake_rate.c``) and steps the RTP once per group of ``D`` samples
(:func:`wake.sampling.decimation_for`).  From the static bounds of the two
functions (:func:`wake.firmware.wcet.static_bound`), the worst input sample
(a group ends: push and step) and the work per second.
"""

from __future__ import annotations

from wake.sampling import decimation_for

__all__ = ["rate_cost", "rate_lines"]


def rate_cost(fs: float, step: int, push: int | None) -> dict:
    """Instructions (or cycles) of the worst input sample and per second at ``fs`` Hz.

    Parameters
    ----------
    fs : float
        Input rate, Hz.
    step, push : int
        Static bounds of ``wake_rtp_step`` and ``wake_rate_push`` (``push`` is
        not run at ``D = 1``, and may be None there).

    Examples
    --------
    >>> from wake.firmware.rate_cost import rate_cost
    >>> rate_cost(1000.0, 493, 63)
    {'fs': 1000.0, 'decimation': 10, 'bank_rate': 100.0, 'per_sample': 556, 'per_second': 112300.0}
    >>> rate_cost(100.0, 493, None)["per_second"]
    49300.0
    """
    D = decimation_for(fs)
    if D > 1 and push is None:
        raise ValueError(f"fs = {fs:g} Hz needs the front end (decimation {D}): give the bound of wake_rate_push")
    fe = push if D > 1 else 0
    return {"fs": float(fs), "decimation": D, "bank_rate": fs / D, "per_sample": step + fe,
            "per_second": fs * fe + (fs / D) * step}


def rate_lines(fs: float, bounds: dict) -> list:
    """Markdown lines of :func:`rate_cost` per target; ``bounds``: target -> (step Bound, push Bound or None)."""
    base = {t: rate_cost(100.0, step.instructions, None) for t, (step, _) in bounds.items()}
    out = [f"## Cost at {fs:g} Hz (front end by {decimation_for(fs)}, bank at {fs / decimation_for(fs):g} Hz; "
           "static bounds, J = 5)", "",
           "| target | wake_rate_push | wake_rtp_step | worst input sample | per second | at 100 Hz: per sample, per second |",
           "|---|---:|---:|---:|---:|---:|"]
    for t, (step, push) in bounds.items():
        c = rate_cost(fs, step.instructions, None if push is None else push.instructions)
        p = "-" if push is None else f"{push.instructions:,}"
        out.append(f"| {t} | {p} | {step.instructions:,} | {c['per_sample']:,} | {c['per_second']:,.0f} | "
                   f"{base[t]['per_sample']:,}, {base[t]['per_second']:,.0f} |")
    return out + [""]
