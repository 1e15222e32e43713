"""csrc/tests/prove/prove_tier.py picks Frama-C's tier from a hash of exactly the full analysis's inputs: a change to
any analysed source, header, driver, check script or listed alarm (a comment included) chooses the full analysis; a
matching record, the quick tier. Run on a copy of csrc/ and docs/studies/verification.md; no Frama-C is needed (its version
string is then 'missing', itself an input)."""

import importlib.util
import json
import re
import shutil
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _load(csrc):
    path = csrc / "tests" / "prove" / "prove_tier.py"
    spec = importlib.util.spec_from_file_location(f"prove_tier_{abs(hash(str(csrc)))}", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture
def copy(tmp_path):
    """A copy of csrc/ (no build outputs) and docs/studies/verification.md, and prove_tier loaded from it."""
    shutil.copytree(ROOT / "csrc", tmp_path / "csrc", ignore=shutil.ignore_patterns("build", "__pycache__"))
    (tmp_path / "docs" / "studies").mkdir(parents=True)
    shutil.copy(ROOT / "docs" / "studies" / "verification.md", tmp_path / "docs" / "studies" / "verification.md")
    (tmp_path / "csrc" / "tests" / "prove" / "full_prove_record.json").unlink(missing_ok=True)
    return tmp_path, _load(tmp_path / "csrc")


def test_the_hashed_sources_are_the_analysed_ones_found_by_their_includes(copy):
    _, tier = copy
    sources = tier.analysed_sources()
    for name in ("wake_rtp.c", "wake_rtp.h", "wake_hpa.c", "wake_hpa_dft.c", "wake_hpa_ahead.c", "wake_hpa.h",
                 "internal/wake_hpa_internal.h", "internal/wake_bounds.h", "internal/wake_hpa_costs.h",
                 "tests/prove/eva_builtins.h",
                 "tests/prove/eva_rtp.c", "tests/prove/eva_hpa.c", "tests/prove/eva_hpa_steps.c",
                 "tests/prove/eva_hpa_ahead_steps.c"):
        assert name in sources, name
    assert "wake_rate.c" not in sources and "wake_rate.h" not in sources    # no analysis reads the front end
    items = tier.inputs()
    assert {"tests/prove/eva_check.py", "tests/prove/wp_check.py", "docs/studies/verification.md: Eva alarms",
            "frama-c -version", "why3 --version"} <= set(items)
    assert not any("timeout" in k for k in items)    # a time limit can fail a run, never pass one


@pytest.mark.parametrize("where, edit", [
    ("csrc/wake_rtp.c", lambda t: t.replace("*/", "*/ /* a comment */", 1)),
    ("csrc/wake_hpa.h", lambda t: t + "\n/* a comment */\n"),
    ("csrc/tests/prove/eva_hpa_steps.c", lambda t: t + "\n/* a comment */\n"),
    ("csrc/tests/prove/eva_check.py", lambda t: t.replace('"-eva-slevel", "400"', '"-eva-slevel", "401"', 1)),
], ids=["source comment", "header", "driver", "check script parameter"])
def test_any_change_to_an_input_chooses_the_full_analysis(copy, where, edit):
    root, tier = copy
    items = tier.inputs()
    tier.write_record(items, tier.digest(items), 1, "prove: OK\n")
    assert tier.choose()[0] == "quick"
    path = root / where
    before = path.read_text()
    path.write_text(edit(before))
    assert path.read_text() != before
    choice, reason, *_ = tier.choose()
    assert choice == "full"
    assert where.removeprefix("csrc/") in reason    # the reason names what changed


def test_the_listed_alarms_count_but_not_the_rest_of_verification_md(copy):
    root, tier = copy
    items = tier.inputs()
    tier.write_record(items, tier.digest(items), 1, "prove: OK\n")
    doc = root / "docs" / "studies" / "verification.md"
    doc.write_text(doc.read_text() + "\nA paragraph about something else.\n")
    assert tier.choose()[0] == "quick"
    text = doc.read_text()
    row = next(line for line in text.splitlines() if re.match(r"^\|\s*wake_\w+\.c\s*\|", line))
    doc.write_text(text.replace(row + "\n", ""))
    assert tier.choose()[0] == "full" and "Eva alarms" in tier.choose()[1]


def test_without_a_record_or_with_a_corrupt_one_the_full_analysis_runs(copy):
    root, tier = copy
    assert tier.choose()[0] == "full"
    tier.RECORD.write_text("{not json")
    assert tier.choose()[0] == "full"
    tier.RECORD.write_text(json.dumps({"inputs_sha256": "0" * 64}))
    assert tier.choose()[0] == "full"
