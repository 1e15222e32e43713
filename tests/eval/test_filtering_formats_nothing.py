"""Nothing formats docstrings while a filter or a cohort task runs (issue 44): numpy.ma and scipy.signal, whose
imports run ``inspect.cleandoc`` (41 and 7,698 calls), stay unimported, and ``cleandoc`` is never called."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

CHILD = """
import inspect, json, sys
import numpy as np
from wake import WakeFilter
from wake.eval.compute import WAKE_PARAMS, Task, compute_task
from wake.eval.sources import cohort_sources
calls = []
real = inspect.cleandoc
inspect.cleandoc = lambda doc: calls.append(1) or real(doc)
fs = float(sys.argv[1])
t = np.arange(int(12 * fs)) / fs
gyro = np.sin(2 * np.pi * 0.4 * t) + 0.3 * np.sin(2 * np.pi * 6.0 * t)
accel = np.column_stack((9.81 + 0.5 * gyro, -1.0 + 0.1 * gyro))
for x in (gyro, accel):
    for backend in ("reference", "c"):
        WakeFilter(fs=fs, backend=backend).run(x)
rows = compute_task(Task(cohort_sources(1, duration_s=12.0)[0], tuple(WAKE_PARAMS.items()), ("reference", "c")))
print(json.dumps({"cleandoc": len(calls), "numpy.ma": "numpy.ma" in sys.modules,
                  "scipy.signal": "scipy.signal" in sys.modules, "error": rows[0]["error"], "rows": len(rows)}))
"""


@pytest.mark.parametrize("fs", [100.0, 1000.0])
def test_no_docstring_is_formatted_while_filtering(fs):
    pytest.importorskip("wake._rtp", reason="the C backend is part of what runs")
    out = subprocess.run([sys.executable, "-c", CHILD, str(fs)], cwd=ROOT, capture_output=True, text=True,
                         check=True, env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    seen = json.loads(out.stdout.strip().splitlines()[-1])
    assert seen["error"] == "" and seen["rows"] > 5
    assert seen == {"cleandoc": 0, "numpy.ma": False, "scipy.signal": False, "error": "", "rows": seen["rows"]}
