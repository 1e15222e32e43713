"""Every Python snippet of the README runs as written, and so does every `wake run` / `wake export-*` line
of its command-line block, on a recording this test writes."""

import re
import shlex
from pathlib import Path

import numpy as np
import pytest

from wake.cli import main
from wake.eval.synthetic import make_signal

README = Path(__file__).resolve().parents[1] / "README.md"


def _blocks(lang):
    return re.findall(rf"```{lang}\n(.*?)```", README.read_text(encoding="utf-8"), re.S)


@pytest.fixture
def workdir(tmp_path, monkeypatch):
    s = make_signal(5.0, seed=1, duration=12.0)
    t = np.arange(s.measurement.size) / s.fs
    rows = "\n".join(f"{a:.2f},{b!r},{-b!r}" for a, b in zip(t.tolist(), s.measurement.tolist()))
    (tmp_path / "recording.csv").write_text("time [s],gyro_x [rad/s],gyro_y [rad/s]\n" + rows + "\n")
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_the_readme_has_python_snippets():
    assert len(_blocks("python")) >= 1


@pytest.mark.parametrize("index", range(len(_blocks("python"))))
def test_python_snippet_runs(workdir, index, capsys):
    code = _blocks("python")[index]
    exec(compile(code, f"README.md python block {index + 1}", "exec"), {"__name__": "__readme__"})
    if "read_recording" in code:
        assert "100.0 ('gyro_x', 'gyro_y') ('rad/s', 'rad/s') (1200, 2)" in capsys.readouterr().out


def _command_lines():
    """The README's `wake run` and `wake export-*` example lines, optional parts taken."""
    lines = []
    for block in _blocks("sh"):
        for line in block.splitlines():
            line = line.split("  #")[0].strip()
            if re.match(r"wake (run|export-header|export-c) ", line):
                lines.append(line.replace("[", "").replace("]", ""))
    return lines


def test_the_readme_shows_run_and_export_lines():
    assert {line.split()[1] for line in _command_lines()} == {"run", "export-header", "export-c"}


@pytest.mark.parametrize("line", _command_lines())
def test_command_line_runs(workdir, line):
    if "--plot" in line:
        pytest.importorskip("matplotlib", reason="the --plot example needs matplotlib (pip install \".[plot]\")")
    args = shlex.split(line)[1:]
    assert main(args) == 0, line
    if "--out" in args:
        assert (workdir / args[args.index("--out") + 1]).is_file()
