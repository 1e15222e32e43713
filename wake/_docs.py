"""Docstrings shared between classes, written once."""

from __future__ import annotations

__all__ = ["parameters_doc"]


def parameters_doc(cls) -> str:
    """The numpydoc ``Parameters`` entries of ``cls``'s docstring (without the heading), indented as written.

    :class:`~wake.WakeFilter` takes every :class:`WakeConfig` setting, and its docstring shows them from
    this one text, so ``help(WakeFilter)`` documents every parameter the way ``help(WakeConfig)`` does.
    """
    doc = cls.__doc__ or ""
    head = "Parameters\n    ----------\n"
    if head not in doc:
        return ""
    body = doc.split(head, 1)[1]
    return body.split("\n\n    Examples", 1)[0].split("\n\n    Notes", 1)[0].rstrip() + "\n"
