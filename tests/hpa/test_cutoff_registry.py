"""Adding a cut-off rule is one Python function, one C function and one registry line (docs/reference/architecture.md)."""

import numpy as np
import pytest

from support import has_c_backend
from wake import WakeConfig, WakeFilter
from wake.cli import build_parser
from wake.hpa.cutoff import Spectrum, find_cutoff
from wake.registry import cutoff_rule_names, get_cutoff_rule, register_cutoff_rule, unregister_cutoff_rule


@pytest.fixture
def halfway_rule():
    """A rule registered for the test: f_d halfway between cutoff_range[0] and the tremor peak."""

    @register_cutoff_rule("halfway", c_name="WAKE_HPA_RULE_HALFWAY", description="halfway to the tremor peak")
    def halfway(s: Spectrum):
        if s.fallback is not None:
            return float(s.default_cutoff), s.fallback
        return float((s.cutoff_range[0] + s.freqs[s.peak]) / 2), "valley"

    yield halfway
    unregister_cutoff_rule("halfway")


def cutoff_rule_choices():
    run = build_parser()._subparsers._group_actions[0].choices["run"]
    return next(a for a in run._actions if a.dest == "cutoff_rule").choices


def test_a_registered_rule_is_a_choice_everywhere(halfway_rule):
    assert cutoff_rule_names()[-1] == "halfway"
    assert "halfway" in cutoff_rule_choices()
    assert WakeConfig(cutoff_rule="halfway").cutoff_rule == "halfway"
    f = np.linspace(0, 50, 501)
    psd = np.exp(-f / 0.5) + np.exp(-((f - 8) ** 2) / 2)
    assert find_cutoff(f, psd, rule="halfway") == (pytest.approx((0.5 + 8.0) / 2), "valley")
    res = WakeFilter(backend="reference", cutoff_rule="halfway").run(np.sin(np.arange(1200) / 7.0))
    assert {u.cutoff_flag for u in res.hpa[0]} <= {"valley", "no_tremor_peak", "no_valley"}


def test_a_rule_is_gone_once_unregistered(halfway_rule):
    unregister_cutoff_rule("halfway")
    assert "halfway" not in cutoff_rule_choices()
    with pytest.raises(ValueError, match="unknown cutoff_rule 'halfway'"):
        WakeConfig(cutoff_rule="halfway")
    register_cutoff_rule("halfway", c_name="WAKE_HPA_RULE_HALFWAY", description="again")(halfway_rule)


def test_a_rule_without_its_c_function_is_named_by_the_mirror_check(halfway_rule):
    if not has_c_backend():
        pytest.skip("the compiled C core wake._rtp is not built")
    from wake._rtp import lib
    from wake.hpa.c_port import c_mirror_problems

    problems = c_mirror_problems(lib)
    assert len(problems) == 1 and "'halfway'" in problems[0] and "WAKE_HPA_RULE_HALFWAY" in problems[0]
    with pytest.raises(ValueError, match="cutoff_rule 'halfway' has no C function"):
        WakeFilter(cutoff_rule="halfway", hpa_backend="c")


def test_names_and_c_identifiers_are_unique(halfway_rule):
    with pytest.raises(ValueError, match="clashes"):
        register_cutoff_rule("halfway", c_name="WAKE_HPA_RULE_OTHER", description="")(halfway_rule)
    with pytest.raises(ValueError, match="clashes"):
        register_cutoff_rule("other", c_name="WAKE_HPA_RULE_FLOOR", description="")(halfway_rule)
    with pytest.raises(ValueError, match="unknown cut-off rule 'nope'"):
        get_cutoff_rule("nope")


def test_the_docs_list_every_built_in_rule():
    from pathlib import Path

    text = (Path(__file__).resolve().parents[2] / "docs" / "reference" / "design.md").read_text()
    for name in ("paper", "shallow", "floor"):
        assert f"`{name}`: {get_cutoff_rule(name).description}" in text
