"""When the compiled core is missing, the message says why: a source tree shadowing the installed package,
or no build at all."""

import importlib.metadata
from pathlib import Path

import wake._core as rtp_pkg


class _FakeDist:
    def __init__(self, site):
        self.site = site
        self.files = [importlib.metadata.PackagePath("wake/__init__.py"),
                      importlib.metadata.PackagePath("wake/_rtp.abi3.so")]

    def locate_file(self, f):
        return self.site / f


def _source_tree(tmp_path):
    tree = tmp_path / "checkout"
    (tree / "wake").mkdir(parents=True)
    (tree / "pyproject.toml").write_text("[project]\nname = 'wake-tremor'\n")
    (tree / "wake" / "_core.py").write_text("")
    return tree


def _installed(tmp_path):
    site = tmp_path / "site-packages"
    (site / "wake").mkdir(parents=True)
    (site / "wake" / "_rtp.abi3.so").write_bytes(b"")
    return site


def test_a_source_tree_shadowing_the_installed_core_is_named(tmp_path, monkeypatch):
    tree, site = _source_tree(tmp_path), _installed(tmp_path)
    monkeypatch.setattr(rtp_pkg, "__file__", str(tree / "wake" / "_core.py"))
    monkeypatch.setattr(importlib.metadata, "distribution", lambda name: _FakeDist(site))
    assert rtp_pkg.shadowed_install() == (site / "wake").resolve()
    hint = rtp_pkg.missing_core_hint()
    assert f"imported the source tree {tree.resolve()}" in hint and str((site / "wake").resolve()) in hint
    assert "pip install -e ." in hint


def test_without_an_install_the_hint_is_to_build(tmp_path, monkeypatch):
    tree = _source_tree(tmp_path)
    monkeypatch.setattr(rtp_pkg, "__file__", str(tree / "wake" / "_core.py"))

    def missing(name):
        raise importlib.metadata.PackageNotFoundError(name)

    monkeypatch.setattr(importlib.metadata, "distribution", missing)
    assert rtp_pkg.shadowed_install() is None
    assert rtp_pkg.missing_core_hint() == rtp_pkg.BUILD_HINT


def test_an_installed_package_is_not_a_source_tree(tmp_path, monkeypatch):
    site = _installed(tmp_path)
    monkeypatch.setattr(rtp_pkg, "__file__", str(site / "wake" / "_core.py"))
    monkeypatch.setattr(importlib.metadata, "distribution", lambda name: _FakeDist(site))
    assert rtp_pkg.shadowed_install() is None
    assert Path(rtp_pkg.__file__).parent == site / "wake"
