"""Every README block that states a number, a count or a direction, checked against the command it cites.

The same rules hold for the reference pages of the documentation (``docs/reference/*.md``: what is true
now, each figure stated once; the dated measurements are the study pages, ``docs/studies/``, which are
not read here).  The README and the reference pages tag each such block on the line above it:

- ``<!-- claim: NAME -->``: a check below (registered with :func:`claim`) recomputes what the block says with
  the command or function the block cites, and compares every number it can;
- ``<!-- not a claim: REASON -->``: a requirement, a description or a citation, not a result.

:func:`test_every_block_with_a_number_or_direction_is_tagged` fails on an untagged block, and
:func:`test_every_tag_has_its_check` on a tag without a check (or a check no block uses).  Some claims are
records of measurements that depend on the machine (latency, host speed): their check verifies that the
command they cite exists and accepts the options they name, and that the block says it is one run on a
stated machine.  PADS checks need the recordings (skipped without them, naming WAKE_PADS_DIR); firmware
checks need arm-none-eabi-gcc, unicorn and capstone.
"""

from __future__ import annotations

import importlib.util
import re
import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from support import NO_PADS, pads_dir

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
#: The files whose blocks are claims: the README and the documentation's reference pages.
SOURCES = (README, *sorted((ROOT / "docs" / "reference").glob("*.md")))
TAG = re.compile(r"^<!-- (claim: ([\w-]+)|not a claim: (.+?)) -->$")
DIRECTION = re.compile(r"\b(higher|lower) is better\b|\b(better|worse|best|lower|higher|faster|slower|below|above)\b",
                       re.I)

CHECKS = {}


def claim(name):
    """Register the check of the README blocks tagged ``<!-- claim: name -->``."""
    def register(fn):
        CHECKS[name] = fn
        return fn
    return register


def blocks():
    """``(tag, text)`` per block of :data:`SOURCES` (blank-line separated, code fences and headings left out)."""
    text = "\n\n".join(re.sub(r"```.*?```", "", path.read_text(encoding="utf-8"), flags=re.S) for path in SOURCES)
    out = []
    for raw in re.split(r"\n\s*\n", text):
        lines = raw.strip().splitlines()
        if not lines or lines[0].startswith("#"):
            continue
        tag = None
        m = TAG.match(lines[0].strip())
        if m:
            tag = m.group(2) or "not a claim"
            lines = lines[1:]
        if lines:
            out.append((tag, "\n".join(lines)))
    return out


def tagged(name, fold=True):
    """The text of the blocks tagged ``claim: name``, joined (white space folded unless ``fold`` is false)."""
    found = [text for tag, text in blocks() if tag == name]
    assert found, f"no block of the README or docs/reference/ is tagged claim: {name}"
    return " ".join(" ".join(found).split()) if fold else "\n".join(found)


def _states_something(text):
    prose = re.sub(r"`[^`]*`|\]\([^)]*\)|https?://\S+", "", text)
    return bool(re.search(r"\d", prose) or DIRECTION.search(prose))


def test_every_block_with_a_number_or_direction_is_tagged():
    untagged = [text[:100] for tag, text in blocks() if tag is None and _states_something(text)]
    assert not untagged, "README or docs/reference/ blocks state a number or a direction without a claim tag:\n" + "\n".join(untagged)


def test_every_tag_has_its_check():
    tags = {tag for tag, _ in blocks() if tag not in (None, "not a claim")}
    assert tags - set(CHECKS) == set(), "claim tags without a check"
    assert set(CHECKS) - tags == set(), "checks of claims no README block makes"


def table(name, first_cell):
    """The cells after the first of the table row starting ``| first_cell |`` in the blocks tagged ``name``."""
    for line in tagged(name, fold=False).splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.lstrip().startswith("|") and cells[0] == first_cell:
            return cells[1:]
    raise AssertionError(f"no table row {first_cell!r} in the blocks tagged claim: {name}")


def number(cell):
    return float(cell.replace(",", "").replace("*", "").split()[0])


def _bench(name):
    spec = importlib.util.spec_from_file_location(f"bench_{name}", ROOT / "bench" / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _record(name, command, options=()):
    """A measurement record: the command it cites exists and takes its options."""
    text = tagged(name)
    assert command in text, f"the {name} block does not cite {command!r}"
    script = ROOT / command.split()[1] if command.startswith("python ") else None
    if script is not None:
        assert script.is_file(), script
        helptext = subprocess.run([sys.executable, str(script), "--help"], capture_output=True, text=True,
                                  timeout=120, cwd=ROOT).stdout
        for option in options:
            assert option in helptext, f"{command} has no option {option}"
    return text


# --- claims recomputed ---------------------------------------------------------------------------------


@claim("parameters-documented")
def check_parameters_documented():
    import dataclasses

    from wake import WakeConfig, WakeFilter

    assert "Every parameter is documented in `help(WakeFilter)`" in tagged("parameters-documented")
    for f in dataclasses.fields(WakeConfig):
        assert re.search(rf"^    (\w+, )*{f.name}\b", WakeFilter.__doc__, re.M), f"help(WakeFilter) lacks {f.name}"


@claim("lowest-versions")
def check_lowest_versions():
    pins = dict(line.split("==") for line in (ROOT / ".ci" / "constraints-lowest.txt").read_text().splitlines()
                if line and not line.startswith("#"))
    said = re.findall(r"(numpy|scipy|PyWavelets) ([\d.]+)", tagged("lowest-versions"))
    assert len(said) == 3
    for name, version in said:
        assert pins[name].startswith(version), f"README says {name} {version}, the constraints pin {pins[name]}"
    assert "Python 3.9" in tagged("lowest-versions") and ">=3.9" in (ROOT / "pyproject.toml").read_text()


@claim("glossary")
def check_glossary():
    from wake.eval.metrics import nrmse, prf, snr_out

    text = tagged("glossary")
    rng = np.random.default_rng(0)
    truth = np.sin(np.linspace(0, 20, 500))
    close, far = truth + 0.01 * rng.standard_normal(500), truth + 0.1 * rng.standard_normal(500)
    directions = {"NRMSE": nrmse(truth, close) < nrmse(truth, far), "PRF": prf(truth, close) < prf(truth, far),
                  "SNR_out": snr_out(truth, close) > snr_out(truth, far)}
    said = {"NRMSE": "lower", "PRF": "lower", "SNR_out": "higher"}
    for metric, lower_for_closer in directions.items():
        assert lower_for_closer
        entry = re.search(rf"\*\*{metric}\*\*(.*?)(?= - \*\*|$)", text).group(1)
        assert f"{said[metric]} is better" in entry, (metric, entry)


@claim("demo-table")
def check_demo_table():
    from wake import WakeFilter
    from wake.eval.metrics import nrmse
    from wake.eval.synthetic import PAPER_WAKE, paper_dataset

    text = tagged("demo-table")
    ours = []
    for i, s in enumerate(paper_dataset()):
        res = WakeFilter(fs=s.fs).run(s.measurement)
        ours.append(nrmse(s.voluntary, res.voluntary, res.warmup))
        cells = table("demo-table", str(i + 1))
        assert number(cells[0]) == round(s.snr_db, 1)
        assert number(cells[1]) == round(ours[-1], 4), (i + 1, ours[-1])
        assert number(cells[2]) == PAPER_WAKE["nrmse"][i]
    mean = table("demo-table", "**mean**")
    assert number(mean[1]) == round(float(np.mean(ours)), 4)
    assert number(mean[2]) == round(float(np.mean(PAPER_WAKE["nrmse"])), 4)
    assert all(o <= p for o, p in zip(ours, PAPER_WAKE["nrmse"]))
    assert "Every signal is at or below the paper's number" in text
    below = round(100 * (1 - np.mean(ours) / np.mean(PAPER_WAKE["nrmse"])))
    assert f"the mean is {below} % below it" in text


#: The WAKE runs the slice table's rows and its "paper -> floor" sentence name: today's default, the first
#: release's schedule and start-up weights with the paper's rule, and the default with the paper's rule.
WAKE_RUNS = {"WAKE": {}, "first release": dict(warmup_hpa_s=(), initial_weights="deepest", cutoff_rule="paper"),
             "paper rule": dict(cutoff_rule="paper")}


def _slice_means(rows):
    from wake.eval.warmup import mean_slices

    means = mean_slices(rows)
    return [means[k] for k in ("0.5-1 s", "1-2 s", "2-5 s", "after 5 s", "whole (from 0.5 s)")]


def _synthetic_slices():
    from wake import WakeFilter
    from wake.eval.evaluate import baseline_methods
    from wake.eval.synthetic import paper_dataset
    from wake.eval.warmup import slice_nrmse

    rows = {}
    for s in paper_dataset():
        for name, settings in WAKE_RUNS.items():
            rows.setdefault(name, []).append(
                slice_nrmse(s.voluntary, WakeFilter(fs=s.fs, **settings).run(s.measurement).voluntary, s.fs))
        for name, m in baseline_methods(s.fs).items():
            rows.setdefault(name, []).append(slice_nrmse(s.voluntary, m.run(s.measurement).voluntary, s.fs))
    return {name: _slice_means(r) for name, r in rows.items()}


def _pads_runs():
    """Per method, slice means of the tremor NRMSE over the PADS axes, and the HPA cut-off flags."""
    from wake import WakeFilter
    from wake.eval.datasets import load_pads_folder
    from wake.eval.evaluate import baseline_methods
    from wake.eval.warmup import independent_ground_truth, slice_nrmse

    rows, flags = {}, {}
    for rec in load_pads_folder(pads_dir()):
        x = rec.samples
        vols = {}
        for name, settings in WAKE_RUNS.items():
            res = WakeFilter(fs=rec.fs, **settings).run(x)
            vols[name] = res.voluntary
            flags.setdefault(name, []).extend(u.cutoff_flag for ch in res.hpa for u in ch)
        for name, m in baseline_methods(rec.fs).items():
            vols[name] = np.reshape(m.run(x).voluntary, x.shape)
        vols["zero tremor estimate"] = x
        vols["zero prediction"] = np.zeros_like(x)
        for c in range(x.shape[1]):
            _, tremor, _ = independent_ground_truth(x[:, c], rec.fs)
            for name, v in vols.items():
                rows.setdefault(name, []).append(slice_nrmse(tremor, x[:, c] - v[:, c], rec.fs))
    return {name: _slice_means(r) for name, r in rows.items()}, flags


def _assert_row(name, first_cell, values, places=3):
    cells = table(name, first_cell)
    assert [number(c) for c in cells] == [round(v, places) for v in values], (first_cell, values)


@claim("warmup-slices")
def check_warmup_slices():
    text = tagged("warmup-slices")
    syn = _synthetic_slices()
    _assert_row("warmup-slices", "synthetic, voluntary: WAKE", syn["WAKE"])
    _assert_row("warmup-slices", "synthetic: first release", syn["first release"])
    baselines = {k: v for k, v in syn.items() if k in ("BMFLC", "E-BMFLC", "WFLC")}
    best = min(baselines, key=lambda k: baselines[k][-1])
    _assert_row("warmup-slices", f"synthetic: best baseline ({best})", syn[best])
    whole = text.split("lowers the whole-recording error on both sets:")[1]
    m = re.search(r"synthetic ([\d.]+) -> ([\d.]+)", whole)
    assert (number(m[1]), number(m[2])) == (round(syn["paper rule"][-1], 4), round(syn["WAKE"][-1], 4))
    # "In 0.5-1 s, before any HPA, BMFLC and WFLC are better on the synthetic set; from 1 s on WAKE is the lowest"
    assert syn["BMFLC"][0] < syn["WAKE"][0] and syn["WFLC"][0] < syn["WAKE"][0]
    assert all(syn["WAKE"][i] <= min(v[i] for v in baselines.values()) for i in range(1, 5))
    if pads_dir() is None:
        pytest.skip(f"the synthetic rows hold; the PADS rows need the recordings: {NO_PADS}")
    pads, flags = _pads_runs()
    _assert_row("warmup-slices", "PADS, tremor: WAKE", pads["WAKE"])
    _assert_row("warmup-slices", "PADS: first release", pads["first release"])
    base = {k: v for k, v in pads.items() if k in ("BMFLC", "E-BMFLC", "WFLC")}
    best = min(base, key=lambda k: base[k][-1])
    _assert_row("warmup-slices", f"PADS: best baseline ({best})", pads[best])
    _assert_row("warmup-slices", "PADS: zero tremor estimate (voluntary = x)", pads["zero tremor estimate"])
    _assert_row("warmup-slices", "PADS: zero prediction (voluntary = 0)", pads["zero prediction"])
    m = re.search(r"PADS ([\d.]+) -> ([\d.]+)", whole)
    assert (number(m[1]), number(m[2])) == (round(pads["paper rule"][-1], 3), round(pads["WAKE"][-1], 3))
    fallback = ("no_tremor_peak", "no_valley", "silent")
    shares = {k: round(100 * np.mean([f in fallback for f in flags[k]])) for k in ("WAKE", "paper rule")}
    assert f"on PADS {shares['WAKE']} % of HPA windows stay on the constant 2 Hz instead of " \
           f"{shares['paper rule']} % with the paper's rule" in text
    zero, wake = pads["zero tremor estimate"], pads["WAKE"]
    assert zero[0] < min(v[0] for k, v in pads.items() if k != "zero tremor estimate")  # lower than every method
    assert zero[1] < min(v[1] for k, v in pads.items() if k != "zero tremor estimate")  # ... before 2 s
    assert wake[2] < zero[2] and wake[3] < zero[3] and wake[4] < zero[4]  # from 2 s on, and whole
    assert all(w < z for w, z in zip(wake, pads["zero prediction"]))


@claim("baselines")
def check_baselines():
    from wake.eval.evaluate import evaluate_synthetic

    text = tagged("baselines")
    syn = evaluate_synthetic(["reference"] + (["c"] if _has_core() else []))
    rows = syn["rows"]
    names = ("BMFLC", "E-BMFLC", "WFLC", "WAKE-ref")
    means = {n: np.mean([r["methods"][n]["nrmse"] for r in rows]) for n in names}
    cells = table("baselines", "Synthetic, 10 signals (voluntary)")
    assert [number(c) for c in cells[:4]] == [round(means[n], 4) for n in names]
    m = re.search(r"WAKE is best on (\d+) of the 10 synthetic signals: on signal (\d+) \(SNR [-\d.]+ dB\) "
                  r"(\S+) scores (\d+\.\d+) against WAKE's (\d+\.\d+)", text)
    assert m, "the README's synthetic comparison sentence is missing or reworded"
    wins = [r["signal"] for r in rows
            if r["methods"]["WAKE-ref"]["nrmse"] < min(v["nrmse"] for k, v in r["methods"].items()
                                                      if not k.startswith("WAKE"))]
    assert len(wins) == int(m[1]) and sorted(set(range(1, 11)) - set(wins)) == [int(m[2])]
    row = rows[int(m[2]) - 1]["methods"]
    assert round(row[m[3]]["nrmse"], 4) == float(m[4]) and round(row["WAKE-ref"]["nrmse"], 4) == float(m[5])
    from wake.eval.evaluate import ablation_literal_rtp

    abl = ablation_literal_rtp()
    literal = min(float(np.mean(v)) for k, v in abl["nrmse"].items() if k.startswith("literal"))
    ratio = abl["ops"]["literal"] / abl["ops"]["wake_inert"]
    assert f"scores {literal:.3f} against our {float(np.mean(abl['nrmse']['WAKE RTP'])):.3f} and costs about " \
           f"{round(ratio)}x the multiply-adds" in text
    if pads_dir() is None:
        pytest.skip(f"the synthetic claims hold; the PADS claims need the recordings: {NO_PADS}")
    from wake.eval.evaluate import evaluate_real

    real = evaluate_real(pads_dir(), ["reference", "c"] if _has_core() else ["reference"])["rows"]
    pads_row = table("baselines", "PADS, 60 recording-axes (tremor)")
    cols = ("BMFLC", "E-BMFLC", "WFLC", "WAKE-ref", "WAKE")
    assert [number(c) for c in pads_row] == [round(float(np.mean([r["methods"][n] for r in real])), 4) for n in cols]
    base = ("BMFLC", "E-BMFLC", "WFLC")
    beats = {w: sum(r["methods"][w] < min(r["methods"][b] for b in base) for r in real) for w in ("WAKE", "WAKE-ref")}
    assert f"is lower than all three baselines on {beats['WAKE']} of the {len(real)}, and so is the float reference" \
           in text and beats["WAKE-ref"] == beats["WAKE"]
    names = ("BMFLC", "E-BMFLC", "WFLC", "WAKE-ref", "WAKE")
    best = [names[int(np.argmin([r["methods"][n] for n in names]))] for r in real]
    assert f"splits those {beats['WAKE']} as {best.count('WAKE')} for the C core and {best.count('WAKE-ref')} " \
           "for the float reference" in text
    assert best.count("WAKE") + best.count("WAKE-ref") == beats["WAKE"]
    # the exceptions, named axis by axis: "WFLC is better on four axes of 040 and on 105 gyro_x, E-BMFLC on ..."
    losses = {}
    for r in real:
        rival = min(base, key=lambda b: r["methods"][b])
        if r["methods"]["WAKE"] >= r["methods"][rival]:
            losses.setdefault(rival, []).append(f"{r['recording'][:3]} {r['axis']}")
    wflc = [a for a in losses.get("WFLC", []) if not a.startswith("040")]
    assert sum(a.startswith("040") for a in losses.get("WFLC", [])) == 4 and wflc == ["105 gyro_x"], losses
    said = re.search(r"E-BMFLC on (.*?); the report's per-axis table", text)[1]
    named = [a.replace(" (by less than 0.0001)", "").strip() for a in re.split(r", | and ", said)]
    assert named == losses["E-BMFLC"], (named, losses)


def _has_core():
    from wake.rtp import c_backend_available

    return c_backend_available()


@claim("stream-inline")
def check_stream_inline_equals_run(tmp_path):
    from wake.eval.synthetic import make_signal

    text = tagged("stream-inline")
    assert "`--hpa-mode inline` makes the output equal to `wake run` bit for bit" in text
    s = make_signal(5.0, seed=4, duration=8.0)
    rows = "".join(f"{v!r}\n" for v in s.measurement.tolist())
    (tmp_path / "in.csv").write_text("g\n" + rows)
    env = {"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"}
    streamed = subprocess.run([sys.executable, "-m", "wake", "stream", "--stdin", "--stdout", "--fs", "100",
                               "--hpa-mode", "inline", "--header", "--status", "0"], input="g\n" + rows,
                              capture_output=True, text=True, timeout=120, cwd=tmp_path, env=env)
    assert streamed.returncode == 0, streamed.stderr
    out = tmp_path / "out.csv"
    ran = subprocess.run([sys.executable, "-m", "wake", "run", "in.csv", "--fs", "100", "--out", str(out)],
                         capture_output=True, text=True, timeout=120, cwd=tmp_path, env=env)
    assert ran.returncode == 0, ran.stderr
    got = np.array([[float(v) for v in line.split(",")] for line in streamed.stdout.splitlines()[1:]])
    written = np.loadtxt(out, delimiter=",", skiprows=1)
    assert np.array_equal(got, written)  # the same columns (time, g, g_voluntary, g_tremor), bit for bit


@claim("profile")
def check_profile(tmp_path):
    import json

    for tool in ("arm-none-eabi-gcc",):
        if shutil.which(tool) is None:
            pytest.skip(f"{tool} is not installed: the firmware figures cannot be recomputed here")
    for module in ("unicorn", "capstone"):
        pytest.importorskip(module, reason=f"{module} is not installed (pip install \".[profile]\")")
    res = subprocess.run([sys.executable, str(ROOT / "bench" / "firmware_cost.py"), "--quick", "--json",
                          str(tmp_path / "p.json")], capture_output=True, text=True, timeout=600, cwd=ROOT)
    assert res.returncode == 0, res.stderr
    data = json.loads((tmp_path / "p.json").read_text())
    text = tagged("profile")
    for target, label in (("m4-O2", "Cortex-M4 @ 64 MHz"), ("m0plus-O2", "Cortex-M0+ @ 16 MHz")):
        for kalman, kind in ((False, "inert (`q = 0`, the default)" if target == "m4-O2" else "inert"),
                             (True, "active (`q > 0`)" if target == "m4-O2" else "active")):
            p = next(p for p in data["profiles"] if p["target"] == target and p["kalman"] is kalman and not p["build"])
            row = re.search(re.escape(f"| {label} | {kind} |") + r"([^|]*)\|([^|]*)\|([^|]*)\|", text)
            assert row, (label, kind)
            assert (number(row[1]), number(row[2]), number(row[3])) == \
                (p["max"], p["bound_instructions"], p["bound_cycles"]), (target, kalman)
    fp = data["footprint"]
    assert f"`sizeof(wake_rtp_t)` = {fp['m4-O2']['state']} B" in text
    assert f"code {fp['m4-O2']['code']:,} B at `-O2`, {fp['m4-Os']['code']:,} B at `-Os`" in text
    assert f"{fp['m4-Os-no-kalman']['code']:,} B at `-Os` for firmware that keeps the Kalman inert" in text
    lean = {(p["target"], p["kalman"]): p for p in data["profiles"] if p["build"] == "WAKE_RTP_AHEAD=0"}
    assert f"{fp['m4-O2']['state'] - fp['m4-O2-no-ahead']['state']} B of it the tremor ahead" in text
    assert f"with the predictor and the gate {p_m4_active(data):,} ≤ 650" in text
    assert f"(active {lean[('m4-O2', True)]['bound_instructions']:,} ≤ 800, inert " \
           f"{lean[('m4-O2', False)]['bound_instructions']:,} ≤ 450)" in text
    assert f"the M0+ active bound ({lean[('m0plus-O2', True)]['bound_instructions']:,} ≤ 2,000)" in text
    assert f"state {fp['m4-O2-no-ahead']['state']} B ≤ 512 B" in text
    assert f"({fp['m4-Os-no-ahead']['code']:,} B, {3072 - fp['m4-Os-no-ahead']['code']} B to spare" in text


def p_m4_active(data):
    """The static bound of the default build's step on Cortex-M4 -O2 with the Kalman active."""
    return next(p["bound_instructions"] for p in data["profiles"]
                if p["target"] == "m4-O2" and p["kalman"] and not p["build"])


# --- records: measurements that depend on the machine --------------------------------------------------


@claim("latency-record")
def check_latency_record():
    text = _record("latency-record", "python bench/stream_end_to_end.py --echo-baseline",
                   options=("--echo-baseline", "--hpa-mode", "--transport"))
    assert "one run on this 2-core shared machine" in text


SPEED_ROW = re.compile(r"^\| `(?P<name>[^`]+)` \| [^|]+ \| (?P<unit>[^|]+?) \| (?P<ratio>[\d,.]+) \| "
                       r"(?P<ceiling>[\d,.]+) \| (?P<verdict>within|ABOVE) \|", re.M)


def _speed_rows(text):
    return [(m["name"], m["unit"], float(m["ratio"].replace(",", "")), float(m["ceiling"].replace(",", "")),
             m["verdict"]) for m in SPEED_ROW.finditer(text)]


@claim("host-speed-record")
def check_host_speed_record():
    """The host speed is stated as ratios, in the table bench/speed_gate.py writes: its measures, units and
    ceilings are the script's (CEILINGS), each verdict follows from its ratio, and docs/studies/profiling.md carries the
    same table. The ratios themselves are a record of one run (timed, so never recomputed by a unit test)."""
    text = tagged("host-speed-record")
    assert "`python bench/speed_gate.py --update-docs`" in text and "medians" in text and "ratios" in text
    assert "`pytest bench/ --benchmark-only`" in text
    spec = importlib.util.spec_from_file_location("speed_gate", ROOT / "bench" / "speed_gate.py")
    gate = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gate)
    rows = _speed_rows(tagged("host-speed-record", fold=False))
    assert [r[0] for r in rows] == list(gate.CEILINGS), "the README's speed table is not the gate's measures"
    for name, unit, ratio, ceiling, verdict in rows:
        assert (unit, ceiling) == gate.CEILINGS[name][:2], (name, unit, ceiling, gate.CEILINGS[name])
        assert verdict == ("within" if ratio <= ceiling else "ABOVE"), (name, ratio, ceiling, verdict)
    assert re.search(r"load average [\d.]+, [\d.]+, [\d.]+ before", text), "the table's run does not say its load"
    assert _speed_rows((ROOT / "docs" / "studies" / "profiling.md").read_text()) == rows, \
        "docs/studies/profiling.md's speed table differs from the README's (python bench/speed_gate.py --update-docs)"
    # no absolute host time stated beside the table: ratios only (the times column is the table's own)
    prose = re.sub(r"^\|.*$", "", tagged("host-speed-record", fold=False), flags=re.M)
    assert not re.search(r"\d\s*(ms|µs|us|ns)\b|samples/s", prose), "an absolute host time in the prose"


@claim("hpa-c-record")
def check_hpa_c_record():
    text = tagged("hpa-c-record")
    assert "`make -C csrc standalone-check`" in text
    assert "standalone-check:" in (ROOT / "csrc" / "Makefile").read_text()
    assert (ROOT / "bench" / "hpa_c_agreement.py").is_file() and "docs/studies/hpa_c.md" in text


@claim("faults-record")
def check_faults_record():
    text = tagged("faults-record")
    assert "`python bench/fault_streams.py`" in text and (ROOT / "bench" / "fault_streams.py").is_file()
    for test_file in re.findall(r"`(tests/[\w/]+\.py)`", text):
        assert (ROOT / test_file).is_file(), test_file


@claim("packaging")
def check_packaging():
    text = tagged("packaging")
    for path in ("csrc/CMakeLists.txt", "csrc/cmake/arm-cortex-m4.cmake", "csrc/cmake/arm-cortex-m0plus.cmake",
                 "library.json", "zephyr/module.yml", "docs/reference/packaging.md", "docs/studies/verification.md"):
        assert (ROOT / path).is_file(), path
    from wake.firmware.layouts import LAYOUTS

    said = re.search(r"--layout \{([\w,]+)\}", text)[1].split(",")
    assert said == list(LAYOUTS), (said, LAYOUTS)


@claim("export-compiles")
def check_export_compiles():
    text = tagged("export-compiles")
    cited = re.search(r"`(tests/firmware/test_wheel_install\.py)` checks exactly this", text)
    assert cited, "the export-c paragraph no longer cites the test that compiles the exported folder"
    source = (ROOT / cited[1]).read_text()
    for flag in ("-mcpu=cortex-m4", "-Werror", "export-c"):
        assert flag in source, f"{cited[1]} does not use {flag}"


@claim("warmup-bound")
def check_warmup_bound():
    text = tagged("warmup-bound")
    assert "`python bench/warmup_bound.py`" in text and (ROOT / "bench" / "warmup_bound.py").is_file()
    # the synthetic half is recomputed by tests/test_warmup.py (test_truth_fitted_bound_*); its figures:
    source = (ROOT / "tests" / "test_warmup.py").read_text()
    assert "truth_fitted_prediction" in source


# --- the reference pages of the documentation (docs/reference/) ----------------------------------------


@claim("architecture-layers")
def check_architecture_layers():
    from test_architecture import LAYERS

    rows = {}
    for line in tagged("architecture-layers", fold=False).splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells[0].isdigit():
            rows[int(cells[0])] = tuple(re.findall(r"`([\w.]+)`", cells[1]))
    assert rows == dict(enumerate(LAYERS)), "docs/reference/architecture.md's layers differ from tests/test_architecture.py"


@claim("architecture-size")
def check_architecture_size():
    from test_architecture import MAX_FUNCTION_BODY_LINES, MAX_MODULE_LINES

    text = tagged("architecture-size")
    assert f"no module in `wake/` over {MAX_MODULE_LINES} lines" in text
    assert f"no function body over {MAX_FUNCTION_BODY_LINES} lines" in text


@claim("design-defaults")
def check_design_defaults():
    import ast
    import dataclasses

    from wake import WakeConfig
    from wake.cli import _stream_parser

    text = tagged("design-defaults")
    defaults = {f.name: f.default for f in dataclasses.fields(WakeConfig)}
    said = []
    for line in tagged("design-defaults", fold=False).splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.lstrip().startswith("|") and len(cells) == 4:  # choice | the code's default | alternatives | study
            said += re.findall(r"`(\w+)=([^`,]+)`", cells[1])
    assert len(said) >= 6, said
    for name, value in said:
        assert ast.literal_eval(value) == defaults[name], f"the default of {name} is {defaults[name]!r}, not {value}"
    # the paper's structure, stated as the defaults kept
    said = re.search(r"the paper's `(\w+)`, `J = (\d+)`, `L = (\d+) s`, `p = (\d+)`", text)
    assert said and (said[1], int(said[2]), float(said[3]), int(said[4])) == (
        defaults["wavelet"], defaults["level"], defaults["window_s"], defaults["ar_order"])
    mode = _stream_parser().parse_args(["--stdin", "--stdout", "--fs", "100"]).hpa_mode
    assert f"`--hpa-mode {mode}` for `wake stream`" in text


@claim("cutoff-rules")
def check_cutoff_rules():
    from wake.registry import get_cutoff_rule

    text = tagged("cutoff-rules", fold=False)
    said = re.findall(r"^\* `(\w+)`: (.+) \(`\w+`, `\w+`\)$", text, re.M)
    assert said, "no rule listed"
    import wake  # noqa: F401  (registers the built-in rules)
    from wake.registry import cutoff_rules

    built_in = [rule.name for rule in cutoff_rules() if rule.function.__module__ == "wake.hpa.cutoff"]
    assert [name for name, _ in said] == built_in
    for name, description in said:
        assert description == get_cutoff_rule(name).description, name


@claim("cutoff-flags")
def check_cutoff_flags():
    from wake.hpa import CUTOFF_FLAGS

    said = re.findall(r"^\| `(\w+)` \|", tagged("cutoff-flags", fold=False), re.M)
    assert sorted(said) == sorted(CUTOFF_FLAGS)


@claim("cmake-options")
def check_cmake_options():
    cmake = (ROOT / "csrc" / "CMakeLists.txt").read_text(encoding="utf-8")
    said = re.findall(r"`(WAKE_\w+)` \((\w+)", tagged("cmake-options"))
    assert len(said) == 6
    for name, value in said:
        found = re.search(rf'^(?:set\({name} "(\w+)" CACHE|option\({name} "[^"]*" (\S+)\))', cmake, re.M)
        assert found, f"csrc/CMakeLists.txt has no cache option {name}"
        default = found[1] or found[2]
        assert default == value or default.startswith("${"), (name, value, default)


@claim("export-layouts")
def check_export_layouts():
    from wake.firmware.layouts import LAYOUTS

    said = re.findall(r"^\| `(\w+)`", tagged("export-layouts", fold=False), re.M)
    assert said == list(LAYOUTS)


@claim("verification-commands")
def check_verification_commands():
    text = tagged("verification-commands")
    makefile = (ROOT / "csrc" / "Makefile").read_text(encoding="utf-8")
    targets = re.findall(r"`make -C csrc ([\w-]+)`", text)
    assert len(targets) >= 7
    for target in targets:
        assert re.search(rf"^{target}:", makefile, re.M), f"csrc/Makefile has no target {target}"
    for script in re.findall(r"`python (bench/\w+\.py)", text):
        assert (ROOT / script).is_file(), script
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    for target in targets:   # make's own options (-j2, -s) may stand between
        assert re.search(rf"make (-\S+ )*-C csrc (-\S+ )*{target}\b", ci), f".ci/run does not run make -C csrc {target}"


@claim("q-formats")
def check_q_formats():
    from wake.rtp import qformat

    rows = [line for line in tagged("q-formats", fold=False).splitlines() if line.startswith("| ") and "`" in line]
    said = [(int(m[1]), m[2]) for row in rows for m in re.finditer(r"Q(\d+)[^(|]*\(`(\w+)`", row)]
    assert len(said) == 8, said
    for bits, name in said:
        assert getattr(qformat, name) == bits, f"wake.rtp.qformat.{name} is {getattr(qformat, name)}, not {bits}"
    text = tagged("q-formats")
    assert f"within ±{qformat.WEIGHT_MAX:g}" in text and f"{qformat.AHEAD_TAPS} taps" in text


#: the claims whose check recomputes a whole evaluation or emulates firmware (a minute or more of CPU): marked slow
SLOW_CLAIMS = {"baselines", "warmup-slices", "profile"}


@claim("extension-configuration")
def check_extension_configuration():
    from support import load_build_ffi

    build_ffi = load_build_ffi()

    headers = "\n".join((ROOT / "csrc" / h).read_text() for h in build_ffi.HEADERS)
    config = dict(build_ffi.CONFIGURATION)
    rows = {cells[0].strip("`"): [c.strip("`") for c in cells[1:3]] for cells in
            ([c.strip() for c in line.strip().strip("|").split("|")]
             for line in tagged("extension-configuration", fold=False).splitlines() if line.startswith("| `WAKE_"))}
    assert set(rows) >= set(config), f"definitions of the build not listed: {set(config) - set(rows)}"
    for name, (extension, default) in rows.items():
        # the header's default: `#ifndef NAME` followed by `#define NAME value`
        m = re.search(rf"#ifndef {name}\n#define {name} (\d+)\n", headers)
        assert m, f"{name}: no default in {', '.join(build_ffi.HEADERS)}"
        assert default == m[1], (name, default, m[1])
        assert extension == config.get(name, m[1]), (name, extension, config.get(name, m[1]))
    assert f"windows longer than `{rows['WAKE_HPA_MAX_WINDOW'][1]}` samples" in tagged("extension-configuration")
    # the standalone firmware is built with the extension's definitions, as build_ffi.py --defines prints them
    assert build_ffi.defines().split() == [f"-D{k}={v}" for k, v in build_ffi.CONFIGURATION]
    makefile = (ROOT / "csrc" / "Makefile").read_text()
    assert "EXT_DEFS = $(shell cd .. && $(PYTHON) build_ffi.py --defines)" in makefile
    assert "$(BUILD)/standalone_host $(BUILD)/standalone_m4f.elf: DEFS += $(EXT_DEFS)" in makefile
    assert "python build_ffi.py --defines" in " ".join(tagged("extension-configuration").split())


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n in SLOW_CLAIMS else n
                                  for n in sorted(CHECKS)])
def test_claim(name, tmp_path):
    fn = CHECKS[name]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if "tmp_path" in fn.__code__.co_varnames[:fn.__code__.co_argcount]:
            fn(tmp_path)
        else:
            fn()


