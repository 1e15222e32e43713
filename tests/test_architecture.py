"""The package's shape (docs/reference/architecture.md): imports run down the layers, modules and functions stay small."""

import ast
import sys
from pathlib import Path

import pytest


PACKAGE = Path(__file__).resolve().parents[1] / "wake"

#: The layers of docs/reference/architecture.md, lowest first.  A module may import from its own layer and below,
#: never from above; every import counts, inside functions too.
LAYERS = (
    ("wake._rtp", "wake._validation", "wake._files", "wake._core", "wake._docs", "wake.limits", "wake.registry",
     "wake.target", "wake.ahead", "wake.sampling"),
    ("wake.io", "wake.wavelets"),
    ("wake.config",),
    ("wake.rtp",),
    ("wake.hpa", "wake.hpa.characterise"),
    ("wake.channel", "wake.rate"),
    ("wake.filter", "wake.state", "wake.result"),
    ("wake",),
    ("wake.eval",),
    ("wake.firmware",),
    ("wake.cli", "wake.__main__"),
)


def layer_of(module: str) -> int:
    """The layer of ``module`` (the deepest prefix listed in :data:`LAYERS`)."""
    best, depth = None, -1
    for i, names in enumerate(LAYERS):
        for name in names:
            if (module == name or module.startswith(name + ".")) and name.count(".") > depth:
                best, depth = i, name.count(".")
    if best is None:
        raise AssertionError(f"{module} is in no layer of tests/test_architecture.py: add it there and to "
                             "docs/reference/architecture.md")
    return best


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def imports_of(path: Path):
    """``(line, imported module)`` for every ``import wake...`` / ``from wake... import`` in ``path``."""
    tree = ast.parse(path.read_text(), filename=str(path))
    package = module_name(path) if path.name == "__init__.py" else module_name(path).rpartition(".")[0]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "wake":
                    yield node.lineno, alias.name
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:  # relative: resolve against this module's package
                parent = package.split(".")
                parent = parent[: len(parent) - node.level + 1]
                base = ".".join(parent + ([base] if base else []))
            if base.split(".")[0] != "wake":
                continue
            for alias in node.names:
                sub = f"{base}.{alias.name}"
                # `from wake import filter` imports a module; `from wake import WakeFilter` the package
                is_module = (PACKAGE.parent / sub.replace(".", "/")).with_suffix(".py").exists() or \
                    (PACKAGE.parent / sub.replace(".", "/") / "__init__.py").exists()
                yield node.lineno, sub if is_module else base


def upward_imports():
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        here = module_name(path)
        for line, target in imports_of(path):
            if layer_of(target) > layer_of(here):
                found.append(f"{path.relative_to(PACKAGE.parent)}:{line}: {here} (layer {layer_of(here)}) "
                             f"imports {target} (layer {layer_of(target)})")
    return found


def test_no_module_imports_from_a_higher_layer():
    assert upward_imports() == []


def test_the_walker_sees_an_upward_import(tmp_path, monkeypatch):
    """The check can fail: a function-level import of the CLI from wake.io is caught."""
    fake = tmp_path / "wake"
    (fake / "io").mkdir(parents=True)
    (fake / "__init__.py").write_text("")
    (fake / "cli.py").write_text("")
    (fake / "io" / "__init__.py").write_text("def f():\n    from wake.cli import main\n")
    monkeypatch.setattr(sys.modules[__name__], "PACKAGE", fake)
    assert [m.split(": ", 1)[1] for m in upward_imports()] == ["wake.io (layer 1) imports wake.cli (layer 10)"]


def test_the_layers_in_the_docs_are_these():
    text = (PACKAGE.parent / "docs" / "reference" / "architecture.md").read_text()
    for names in LAYERS:
        for name in names:
            assert f"`{name}`" in text, f"docs/reference/architecture.md does not place {name} in a layer"


# -- size -----------------------------------------------------------------------------------------------------
MAX_MODULE_LINES = 400
MAX_FUNCTION_BODY_LINES = 80
#: Left out of the size check, each with why: a whole module, or ``module::function``.  Remove an entry once
#: its reason is gone (test_the_exemptions_are_still_needed says when).
SIZE_EXEMPT = {
}


def sized_files():
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE.parent).as_posix()
        if rel not in SIZE_EXEMPT:
            yield rel, path


def test_the_exemptions_are_still_needed():
    for entry in SIZE_EXEMPT:
        rel, _, function = entry.partition("::")
        path = PACKAGE.parent / rel
        assert path.exists(), f"{rel} is exempt from the size check but no longer exists"
        if function:
            sizes = {name: n for name, _, n in function_bodies(path)}
            assert sizes.get(function, 0) > MAX_FUNCTION_BODY_LINES, f"{entry} fits the limit now: drop it"
        else:
            assert len(path.read_text().splitlines()) > MAX_MODULE_LINES, f"{rel} fits the limit now: drop it"


def test_no_module_is_over_the_line_limit():
    long = [f"{rel}: {n} lines" for rel, path in sized_files()
            if (n := len(path.read_text().splitlines())) > MAX_MODULE_LINES]
    assert long == [], f"modules over {MAX_MODULE_LINES} lines (split them by job)"


def function_bodies(path: Path):
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(getattr(first, "value", None), ast.Constant) \
                    and isinstance(first.value.value, str) and len(node.body) > 1:
                first = node.body[1]  # the docstring is not body
            yield node.name, node.lineno, node.end_lineno - first.lineno + 1


def test_no_function_body_is_over_the_line_limit():
    long = [f"{rel}:{line} {name}(): {n} lines" for rel, path in sized_files()
            for name, line, n in function_bodies(path)
            if n > MAX_FUNCTION_BODY_LINES and f"{rel}::{name}" not in SIZE_EXEMPT]
    assert long == [], f"function bodies over {MAX_FUNCTION_BODY_LINES} lines"


@pytest.mark.parametrize("limit", [MAX_FUNCTION_BODY_LINES])
def test_the_body_count_leaves_out_the_docstring(tmp_path, limit):
    f = tmp_path / "m.py"
    f.write_text('def g():\n    """doc\n    more"""\n' + "    x = 1\n" * limit + "\ndef h():\n    pass\n")
    assert [(n, b) for n, _, b in function_bodies(f)] == [("g", limit), ("h", 1)]
