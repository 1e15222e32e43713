"""csrc/tests/prove/assigns_check.py reads the outputs Frama-C prints for each step (-out-external) and refuses a
write that run_step's assigns list does not hold (docs/studies/verification.md, "Termination", "What the steps write").
The logs below follow the shapes of Frama-C 25's messages; no Frama-C is needed."""

from support import prove_script


def _check():
    return prove_script("assigns_check")


LOG = """[inout] Out (external) for function step_lag_end:
    hpa{.phase; .t; .diag; .r[0..17]; .wsum[0..31]}
[inout] Out (external) for function any_sums:
    Frama_C_entropy_source; hpa{{.sum; .prefix_rows}; .mean}
[inout] Out (external) for function step_solve:
    hpa{{.attempts; .factor}; .weights[0..4]; .result{.weights[0..4]; .cutoff}; .ready}
"""


def test_the_nested_shapes_are_read():
    check = _check()
    locs, others = check.written("hpa{.runs; {.work; .index}; .r[0..17]; .result{.weights[0..4]; .cutoff}}")
    assert locs == [("runs", None), ("work", None), ("index", None), ("r", (0, 17)), ("result.weights", (0, 4)),
                    ("result.cutoff", None)]
    assert others == []
    assert check.written("Frama_C_entropy_source; hpa.t") == ([("t", None)], ["Frama_C_entropy_source"])
    assert check.written("\\nothing") == ([], [])


def test_the_contract_is_read_and_a_write_beyond_it_is_refused():
    check = _check()
    listed = check.listed_assigns(check.header_values())
    assert listed["phase"] is None and listed["r"] == (0, 24) and listed["gram"] == (0, 35)
    assert "order" not in listed and "cfg" not in listed
    steps = ["step_lag_end", "step_solve"]
    assert check.check({"e": LOG}, listed, steps) == []
    beyond = LOG.replace(".r[0..17]", ".r[0..30]").replace(".ready}", ".ready; .order}")
    problems = check.check({"e": beyond}, listed, steps)
    assert any("r[0..30]" in p for p in problems) and any("order" in p for p in problems)
    assert check.check({"e": LOG}, listed, steps + ["step_sums"]) == ["step_sums: no entry reached it"]
    assert any("not understood" in p for p in check.check({"e": LOG.replace(".ready}", "[bits 0 to 7]}")}, listed,
                                                          steps))
