""".ci/constraints-lowest.txt pins exactly the floors pyproject.toml declares (issue 43, item 4), so that
`bash .ci/run-lowest` tests the lowest set a user can get."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _floors():
    """name -> floor of every dependency of the package and of its test and plot extras (a regex, not tomllib:
    the lowest Python allowed has none)."""
    text = (ROOT / "pyproject.toml").read_text()
    wanted = re.search(r"^dependencies = \[(.*?)\]", text, re.S | re.M).group(1)
    for extra in ("test", "plot"):
        wanted += re.search(rf"^{extra} = \[(.*?)\]$", text, re.S | re.M).group(1)
    # an entry with an environment marker ("x>=1; python_version>='3.10'") is not installable on the lowest Python
    return {name.lower(): floor for name, floor in re.findall(r'"([A-Za-z0-9_.-]+)>=([0-9.]+)"', wanted)}


def _pins():
    lines = (ROOT / ".ci" / "constraints-lowest.txt").read_text().splitlines()
    return dict(line.split("==") for line in (ln.strip() for ln in lines) if line and not line.startswith("#"))


def test_the_lowest_constraints_pin_the_floors_of_pyproject():
    floors, pins = _floors(), {k.lower(): v for k, v in _pins().items()}
    assert set(floors) == set(pins), f"pyproject floors {sorted(floors)} vs pins {sorted(pins)}"
    for name, floor in floors.items():
        pad = lambda v: tuple(int(p) for p in v.split(".")) + (0,) * (3 - v.count(".") - 1)  # noqa: E731
        assert pad(pins[name]) == pad(floor), f"{name}: pyproject says >={floor}, the constraints pin {pins[name]}"


def test_the_release_script_uses_the_constraints():
    script = (ROOT / ".ci" / "run-lowest").read_text()
    assert "-c .ci/constraints-lowest.txt" in script
    assert ".ci/run-lowest" not in (ROOT / ".ci" / "run").read_text()   # not per submission
