"""The C HPA's slice cost model as one table, and the header generated from it.

:data:`COSTS` holds every constant of the slice cost model (csrc/wake_hpa_pieces.c and the steps' chunk
sizes); :func:`write_costs_header` measures one piece of every step (:func:`calibration`, budget-1 builds
with and without the tremor-ahead fit) and writes the table, each value with that measurement beside it, as
``csrc/internal/wake_hpa_costs.h``; :func:`check_costs_header` lists what makes that header stale.  The
command line is :mod:`wake.firmware.hpa_cost`'s: ``--calibrate --write``, ``--calibrate --check``.
"""

from __future__ import annotations

import re
from pathlib import Path

__all__ = ["COSTS", "COSTS_HEADER", "calibration", "costs_header", "check_costs_header", "write_costs_header"]

#: The generated header of the slice cost model's constants, relative to csrc/.
COSTS_HEADER = "internal/wake_hpa_costs.h"
#: The slice cost model, in Cortex-M4F instructions at -O2: (macro, value, the step whose pieces it prices (a
#: STEP_NAMES entry), what it is).  The values are the budgets the slicing and its proofs assume (run_pieces'
#: termination and the dispatch's contract read piece_cost's bounds: docs/studies/verification.md, "Termination"),
#: set from the calibration with a margin; the header records the calibration beside each (a budget-1 build runs
#: one loop item or one indivisible step per slice, the slice's entry check of about 250 included).  A change of a
#: value moves where a sliced run is cut, never what it computes (bench/hpa_ahead_bit_identity.py counts it apart).
COSTS = (
    ("COST_PIECE", 60, None, "the set-up of any piece of work"),
    ("COST_SUM_PLAIN", 22, "sums", "one sample of the sums pass"),
    ("COST_SUM_AHEAD", 25, "sums", "the same with the tremor ahead's full-scale count"),
    ("COST_LAG", 5, "lags", "one product of a lag sum"),
    ("COST_DFT1", 14, "DFT passes", "one sample of a one-bin DFT pass, its clamps' share"),
    ("COST_DFT2", 20, "DFT passes", "one sample of a two-bin DFT pass"),
    ("COST_SLIDE", 90, "bin slide", "one row of a bin's slide, its clamps' share"),
    ("COST_RAMP", 40, "ramp", "one row of the end-point line's ramp"),
    ("COST_DIAG_BASE", 50, "Rxx diagonal", "one entry of a diagonal of Rxx into Rxx B'"),
    ("COST_DIAG_PER_LEVEL", 16, "Rxx diagonal", "... and per WAKE_HPA_MAX_LEVEL"),
    ("COST_PSD_BIN_BASE", 100, "AR spectrum", "one bin of the AR spectrum"),
    ("COST_PSD_BIN_PER_ORDER", 10, "AR spectrum", "... and per AR coefficient (Clenshaw)"),
    ("COST_LAG_END", 150, "lag end", "the centring of one lag"),
    ("COST_LEVINSON_BASE", 80, "Levinson", "one order of Levinson-Durbin"),
    ("COST_LEVINSON_PER_ORDER", 12, "Levinson", "... and per order reached"),
    ("COST_LEVINSON_CLEAR_PER_ORDER", 2, "Levinson", "the first order's clearing, per max order"),
    ("COST_CUTOFF_BASE", 400, "cut-off", "the valley rule"),
    ("COST_CUTOFF_PER_BIN", 20, "cut-off", "... and per PSD bin up to cutoff_high"),
    ("COST_CUTOFF_PER_SHALLOW", 6, "cut-off", "... and per PSD bin up to shallow_high"),
    ("COST_BINS_BASE", 450, "bin count", "the count of the DFT bins below f_d"),
    ("COST_BINS_PER_BIN", 10, "bin count", "... and per bin up to cutoff_high"),
    ("COST_BIN_START", 450, "bin start", "a bin's X'_m, Q_m(0) and phasors"),
    ("COST_GRAM_BASE", 60, "Gram", "one entry of G"),
    ("COST_GRAM_PER_TAP", 8, "Gram", "... and per tap"),
    ("COST_GRAM_ROW_PER_TAP", 12, "Gram", "a row's first entry: the row's sums, per tap"),
    ("COST_GRAM_TARGETS_PER_TAP", 8, "Gram", "the first row: the targets' sums, per tap"),
    ("COST_GRAM_LAST", 100, "Gram", "the last entry: y'y, R"),
    ("COST_SOLVE_CUBIC", 6, "solve", "one ridge attempt, per J^3"),
    ("COST_SOLVE_SQUARE", 12, "solve", "... per J^2"),
    ("COST_SOLVE_BASE", 500, "solve", "... and the guards' bounds"),
    ("COST_SOLVE_RANK_ONE", 900, "solve", "ridge_scale centred: an attempt's rank one (its own piece)"),
    ("COST_AHEAD_TAP_BASE", 20, "ahead start", "one tap of the estimate's FIR w'B"),
    ("COST_AHEAD_TAP_PER_LEVEL", 8, "ahead start", "... and per WAKE_HPA_MAX_LEVEL"),
    ("COST_AHEAD_CLEAR", 300, "ahead start", "the tremor-ahead sums cleared"),
    ("COST_AHEAD_CHUNK", 150, "ahead pass", "a chunk of the tremor-ahead pass"),
    ("COST_AHEAD_BASE", 140, "ahead pass", "one sample of the tremor-ahead pass"),
    ("COST_AHEAD4_PER_TAP", 3, "ahead pass", "... chunks of 4k samples, per FIR tap"),
    ("COST_AHEAD4_PER_BIN", 6, "ahead pass", "... chunks of 4k samples, per truth bin"),
    ("COST_AHEAD1_PER_TAP", 6, "ahead pass", "... shorter chunks, per FIR tap"),
    ("COST_AHEAD1_PER_BIN", 10, "ahead pass", "... shorter chunks, per truth bin"),
    ("COST_AHEAD_SOLVE_ROW", 700, "ahead solve", "a row of the tremor-ahead Gram"),
    ("COST_AHEAD_SOLVE_ROW_HELD", 1300, "ahead solve", "its last row, with the held-out sums"),
    ("COST_AHEAD_SOLVE_COLUMN", 300, "ahead solve", "a column of L D L'"),
    ("COST_AHEAD_SOLVE_LAST", 950, "ahead solve", "the substitution, the gain and the goal"),
)


def calibration(*, build_dir=None, csrc=None) -> dict:
    """Step name -> (median, max) instructions of one piece, from budget-1 builds: every step of the default
    build, and the tremor-ahead steps from the build with the fit (``calibrate``)."""
    from wake.firmware.hpa_cost import AHEAD_STEPS, calibrate

    out = {k: (r["median"], r["max"]) for k, r in calibrate(build_dir=build_dir, csrc=csrc).items()}
    ahead = calibrate(build_dir=build_dir, csrc=csrc, defs=["-DWAKE_HPA_AHEAD=1"])
    out.update({k: (r["median"], r["max"]) for k, r in ahead.items() if k in AHEAD_STEPS})
    return out


_MEASURED = re.compile(r"^ \* +(?P<step>[^:]+?): +(?P<median>[\d,]+) +(?P<max>[\d,]+)$", re.M)


def costs_header(measured: dict) -> str:
    """The text of csrc/internal/wake_hpa_costs.h: :data:`COSTS` and ``measured`` (step -> (median, max))."""
    steps = []
    for _, _, step, _ in COSTS:
        if step is not None and step not in steps:
            steps.append(step)
    width = max(len(s) for s in steps) + 1
    lines = ["/**",
             " * @file wake_hpa_costs.h",
             " * @brief The HPA's slice cost model, in Cortex-M4F instructions at -O2 (csrc/wake_hpa_pieces.c and the",
             " *        steps' chunk sizes).  Generated by `python -m wake.firmware.hpa_cost --calibrate --write` from",
             " *        wake.firmware.hpa_costs.COSTS, checked by `python -m wake.firmware.hpa_cost --calibrate --check`:",
             " *        change the table and regenerate, never this file.",
             " *",
             " * The values are the budgets the slicing and its proofs assume (docs/studies/verification.md,",
             " * \"Termination\"), set from the calibration with a margin.  The calibration: one piece of each step",
             " * (a build with a slice budget of 1, the slice's entry check of about 250 included), median and",
             " * largest over the profiling windows (wake.firmware.hpa_cost.profile_windows):",
             " *"]
    lines += [f" *   {(s + ':').ljust(width)} {measured[s][0]:>7,.0f} {measured[s][1]:>7,}" for s in steps]
    lines += [" */", "#ifndef WAKE_HPA_COSTS_H", "#define WAKE_HPA_COSTS_H", ""]
    for name, value, step, what in COSTS:
        where = f"; {step}: {measured[step][0]:,.0f} / {measured[step][1]:,}" if step else ""
        lines.append(f"#define {name} {value}".ljust(40) + f"/* {what}{where} */")
    lines += ["", "#endif /* WAKE_HPA_COSTS_H */", ""]
    return "\n".join(lines)


def _recorded(text: str) -> dict:
    return {m["step"].strip(): (float(m["median"].replace(",", "")), int(m["max"].replace(",", "")))
            for m in _MEASURED.finditer(text)}


def write_costs_header(*, csrc=None, measured=None) -> Path:
    """Measure (``measured``: a :func:`calibration` already made) and write the header; its path."""
    from wake.firmware.sources import csrc_dir

    path = csrc_dir(csrc) / COSTS_HEADER
    path.write_text(costs_header(calibration(csrc=csrc) if measured is None else measured), encoding="utf-8")
    return path


def check_costs_header(*, csrc=None) -> list[str]:
    """What makes the header stale (empty: it is the table's): a value or a constant that differs from
    :data:`COSTS`, or any other text the generator would not write."""
    from wake.firmware.sources import csrc_dir

    path = csrc_dir(csrc) / COSTS_HEADER
    if not path.is_file():
        return [f"{path} is missing: run python -m wake.firmware.hpa_cost --calibrate --write"]
    text = path.read_text(encoding="utf-8")
    found = dict(re.findall(r"^#define (COST_\w+) (\d+)", text, re.M))
    problems = [f"{n} is {found.get(n, 'missing')} in the header, {v} in COSTS" for n, v, _, _ in COSTS
                if found.get(n) != str(v)]
    problems += [f"{n} is in the header, not in COSTS" for n in found if n not in {c[0] for c in COSTS}]
    try:
        same = text == costs_header(_recorded(text))
    except KeyError as e:
        same, problems = False, problems + [f"the header records no calibration of step {e}"]
    if not same and not problems:
        problems.append("the header's text is not the generator's: run python -m wake.firmware.hpa_cost "
                        "--calibrate --write")
    return problems
