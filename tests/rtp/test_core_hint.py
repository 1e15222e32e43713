"""When the compiled core is missing, the message says why: a source tree shadowing the installed package,
or no build at all.

The trees are real folders with real package metadata on a patched ``sys.path`` (no patched lookup): after
``pip install .`` a checkout holds ``wake_tremor.egg-info``, which the metadata lookup finds before the
installed copy's ``.dist-info`` (issue 43, item 9).
"""

import sys
from pathlib import Path

import pytest

import wake._core as rtp_pkg

SO = "_rtp.cpython-311-x86_64-linux-gnu.so"


def _source_tree(tmp_path, egg_info=True):
    """A checkout after ``pip install .``: pyproject.toml, the package without its core, and the egg-info."""
    tree = tmp_path / "checkout"
    (tree / "wake").mkdir(parents=True)
    (tree / "pyproject.toml").write_text("[project]\nname = 'wake-tremor'\n")
    (tree / "wake" / "_core.py").write_text("")
    if egg_info:
        info = tree / "wake_tremor.egg-info"
        info.mkdir()
        (info / "PKG-INFO").write_text("Metadata-Version: 2.1\nName: wake-tremor\nVersion: 0.2.0\n")
        (info / "SOURCES.txt").write_text("pyproject.toml\nwake/__init__.py\nwake/_core.py\n")
    return tree


def _installed(tmp_path, record=True):
    """site-packages with wake and its compiled core (and its .dist-info unless ``record`` is False)."""
    site = tmp_path / "site-packages"
    (site / "wake").mkdir(parents=True)
    (site / "wake" / SO).write_bytes(b"")
    if record:
        info = site / "wake_tremor-0.2.0.dist-info"
        info.mkdir()
        (info / "METADATA").write_text("Metadata-Version: 2.1\nName: wake-tremor\nVersion: 0.2.0\n")
        (info / "RECORD").write_text(f"wake/__init__.py,,\nwake/{SO},,\nwake_tremor-0.2.0.dist-info/RECORD,,\n")
    return site


@pytest.mark.parametrize("record", [True, False], ids=["pip-install", "pip-install-target"])
def test_a_source_tree_shadowing_the_installed_core_is_named(tmp_path, monkeypatch, record):
    tree, site = _source_tree(tmp_path), _installed(tmp_path, record)
    monkeypatch.setattr(rtp_pkg, "__file__", str(tree / "wake" / "_core.py"))
    monkeypatch.setattr(sys, "path", [str(tree), str(site)])  # `python` started in the checkout
    assert rtp_pkg.shadowed_install() == (site / "wake").resolve()
    hint = rtp_pkg.missing_core_hint()
    assert f"imported the source tree {tree.resolve()}" in hint and str((site / "wake").resolve()) in hint
    assert "pip install -e ." in hint and "run from another directory" in hint


def test_without_an_install_the_hint_is_to_build(tmp_path, monkeypatch):
    tree = _source_tree(tmp_path)
    monkeypatch.setattr(rtp_pkg, "__file__", str(tree / "wake" / "_core.py"))
    monkeypatch.setattr(sys, "path", [str(tree), str(tmp_path / "empty-site")])
    assert rtp_pkg.shadowed_install() is None
    assert rtp_pkg.missing_core_hint() == rtp_pkg.BUILD_HINT


def test_an_installed_package_is_not_a_source_tree(tmp_path, monkeypatch):
    site = _installed(tmp_path)
    monkeypatch.setattr(rtp_pkg, "__file__", str(site / "wake" / "_core.py"))
    monkeypatch.setattr(sys, "path", [str(site)])
    assert rtp_pkg.shadowed_install() is None
    assert Path(rtp_pkg.__file__).parent == site / "wake"


def test_an_installed_copy_without_the_core_is_not_a_shadowed_one(tmp_path, monkeypatch):
    tree, site = _source_tree(tmp_path), _installed(tmp_path)
    (site / "wake" / SO).unlink()  # installed on a machine without a compiler
    monkeypatch.setattr(rtp_pkg, "__file__", str(tree / "wake" / "_core.py"))
    monkeypatch.setattr(sys, "path", [str(tree), str(site)])
    assert rtp_pkg.shadowed_install() is None
