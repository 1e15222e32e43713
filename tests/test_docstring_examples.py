"""Every ``Examples`` section in the package runs and prints what it says.

The docstrings are the first documentation a user reads (``help(WakeFilter)``);
an example that went stale when the default changed (the warm-up HPAs added
five HPAs to a 50-s signal) must fail here, not in a user's session.
"""

import doctest
import importlib
import pkgutil

import pytest

import wake

#: Every module but the compiled core and ``python -m wake`` (importing it runs the command line).
MODULES = sorted(m.name for m in pkgutil.walk_packages(wake.__path__, "wake.")
                 if not m.name.startswith("wake._rtp") and m.name != "wake.__main__")


def test_modules_are_found():
    assert {"wake.filter", "wake.eval.warmup", "wake.hpa.prior"} <= set(MODULES)


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples_run(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE, verbose=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} docstring examples in {name} failed (run " \
                               f"python -m pytest --doctest-modules {module.__file__})"
