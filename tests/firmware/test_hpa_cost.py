"""The Cortex-M cost of the on-device HPA (wake.firmware.hpa_cost) is measured, and its memory goal held."""

import shutil

import numpy as np
import pytest

pytestmark = pytest.mark.skipif(shutil.which("arm-none-eabi-gcc") is None,
                                reason="arm-none-eabi-gcc is not installed (the Arm GNU toolchain)")


def test_one_window_on_cortex_m4f_finishes_within_the_next_window_and_fits_6_kib(tmp_path):
    pytest.importorskip("unicorn")
    pytest.importorskip("capstone")
    from wake.firmware.hpa_cost import HPA_GOALS, measure_hpa, profile_windows

    window = {"synthetic 1": profile_windows(n_synthetic=1)["synthetic 1"]}
    r = measure_hpa("m4f-O2", windows=window, build_dir=tmp_path)
    row = r["rows"][0]
    assert row["whole"] > 100_000                       # a real run, not an early exit
    assert row["slices"] < 500                          # done before the next L = 500 samples
    assert row["sliced_total"] >= row["whole"] * 0.9    # the slices do the same work
    assert r["ram_hpa"] <= HPA_GOALS["ram"]             # both window buffers included
    assert 0 < r["stack"] <= 400
    assert np.isfinite(r["whole_median"])


def test_step_names_follow_the_c_enum():
    """The profiler names wake_hpa_t::phase values by position; a step added in C must be named here too."""
    import re

    from wake.firmware.hpa_cost import STEP_NAMES
    from wake.firmware.sources import csrc_dir

    text = (csrc_dir(None, need=("internal/wake_hpa_internal.h",)) / "internal" / "wake_hpa_internal.h").read_text()
    body = re.search(r"enum \{\s*(STEP_IDLE = 0,.*?)\};", text, re.S).group(1)
    steps = re.findall(r"STEP_[A-Z_]+", body)
    assert len(steps) == len(STEP_NAMES)
    assert steps[0] == "STEP_IDLE" and steps[-1] == "STEP_AHEAD_SOLVE"


def test_a_slice_stays_within_its_budget_plus_the_entry_check(tmp_path):
    """The slice cost model is calibrated in Cortex-M4F instructions: no slice may exceed the budget by more
    than the fixed entry cost (the instance check, about 250 instructions), or the cost model is stale."""
    pytest.importorskip("unicorn")
    pytest.importorskip("capstone")
    import re

    from wake.firmware.hpa_cost import step_breakdown
    from wake.firmware.sources import csrc_dir

    header = (csrc_dir(None, need=("wake_hpa.h",)) / "wake_hpa.h").read_text()
    budget = int(re.search(r"#define WAKE_HPA_SLICE_BUDGET (\d+)", header).group(1))
    rows = step_breakdown("m4f-O2", "synthetic 1", build_dir=tmp_path)
    assert {"lags", "Rxx diagonal", "AR spectrum", "DFT passes", "bin slide", "Gram", "solve"} <= set(rows)
    largest = max(r["max_slice"] for r in rows.values())
    assert budget // 2 < largest <= budget + 400
    assert sum(r["slices"] for r in rows.values()) < 500      # done within the next L = 500 samples


@pytest.mark.slow
def test_the_per_function_profile_accounts_for_every_instruction_of_the_tremor_ahead_build(tmp_path):
    """--functions: each executed instruction counts once, under one function and one part, and the fit's parts
    are at least the arithmetic its formulation needs (one multiply-accumulate per tap and sample for the
    estimate's FIR, four float operations per low bin and sample for the oscillators, 16 products per row)."""
    pytest.importorskip("unicorn")
    pytest.importorskip("capstone")
    from wake.firmware.hpa_cost import profile_windows
    from wake.firmware.hpa_functions import AHEAD_PARTS, function_profile, function_report

    window = {"synthetic 1": profile_windows(n_synthetic=1)["synthetic 1"]}
    res = function_profile("m4f-O2", windows=window, build_dir=tmp_path, defs=["-DWAKE_HPA_AHEAD=1"])
    row = res["rows"][0]
    assert row["whole"] > 300_000
    assert sum(row["functions"].values()) == row["whole"]
    assert sum(row["parts"].values()) == row["whole"]
    assert set(AHEAD_PARTS.values()) <= set(row["parts"])            # every part of the fit ran
    taps, pass_samples, rows = 32, row["samples"] - 32, row["samples"] - 32 - 7 - 1   # J = 5, horizon 1
    assert 0 < row["bins"] <= 64
    assert row["parts"]["pass: the estimate's 2^J-tap FIR"] >= taps * pass_samples
    assert row["parts"]["pass: the low-bin oscillators"] >= 4 * row["bins"] * pass_samples
    assert row["parts"]["pass: the row sums"] >= 32 * rows
    assert row["parts"]["ahead steps' dispatch"] < 5_000                # one piece per step in a whole run
    # the report's totals are the same run's
    lines = function_report(defs=["-DWAKE_HPA_AHEAD=1"], windows=window, build_dir=tmp_path)
    assert f"| all | {row['whole']:,} | {row['whole']:,} |" in lines


def test_the_cost_header_is_the_cost_table():
    """csrc/internal/wake_hpa_costs.h is what wake.firmware.hpa_cost.COSTS gives (--calibrate --check), and
    every COST_ constant the C sources read is defined there and nowhere else."""
    import re

    from wake.firmware.hpa_costs import COSTS, COSTS_HEADER, check_costs_header
    from wake.firmware.sources import csrc_dir

    assert check_costs_header() == []
    src = csrc_dir(None, need=(COSTS_HEADER,))
    names = {c[0] for c in COSTS}
    files = [*src.glob("wake_hpa*.c"), *(src / "internal").glob("*.h")]
    defined = {m for f in files if f.name != "wake_hpa_costs.h"
               for m in re.findall(r"^#define (COST_[A-Z0-9_]+) \d", f.read_text(), re.M)}
    assert not defined, f"a cost constant written outside the cost table: {sorted(defined)}"
    code = [re.sub(r"/\*.*?\*/", "", f.read_text(), flags=re.S) for f in files]   # the loops' notes name costs too
    used = {m for text in code for m in re.findall(r"\bCOST_[A-Z0-9_]+\b", text)}
    derived = {"COST_SUM", "COST_DIAG", "COST_AHEAD_TAP"}     # formulas of the table's constants (internal header)
    assert used - derived <= names and names <= used


def test_a_cost_changed_in_one_place_only_is_stale(tmp_path, monkeypatch):
    """--calibrate --check fails when the header and the table disagree: a value edited in the header, or in COSTS."""
    import shutil

    from wake.firmware import hpa_cost, hpa_costs
    from wake.firmware.sources import csrc_dir

    src = csrc_dir(None)
    copy = tmp_path / "csrc"
    shutil.copytree(src, copy, ignore=shutil.ignore_patterns("build"))
    assert hpa_costs.check_costs_header(csrc=copy) == []
    header = copy / hpa_costs.COSTS_HEADER
    text = header.read_text()
    header.write_text(text.replace("#define COST_SLIDE 90 ", "#define COST_SLIDE 91 "))
    assert any("COST_SLIDE" in p for p in hpa_costs.check_costs_header(csrc=copy))
    header.write_text(text)
    table = tuple((n, v + 1 if n == "COST_LAG" else v, s, w) for n, v, s, w in hpa_costs.COSTS)
    monkeypatch.setattr(hpa_costs, "COSTS", table)
    assert any("COST_LAG" in p for p in hpa_costs.check_costs_header(csrc=copy))
    assert hpa_cost.main(["--calibrate", "--check"]) == 1
