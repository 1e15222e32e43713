"""The cut-off rule registry: name -> Python function, C identifier, description.

A cut-off rule decides the HPA's ``f_d`` from a window's spectrum (docs/studies/design.md,
"Cut-off on real wear").  Every place that lists the rules derives the list
from here: the configuration's validation (:class:`wake.WakeConfig`), the
command line's choices (``--cutoff-rule``), the C HPA's rule number
(:mod:`wake.hpa.c_port`, checked against ``wake_hpa_rule_t`` of
csrc/wake_hpa.h) and docs/studies/design.md's list (checked by a test).

Adding a rule is one Python function, decorated with
:func:`register_cutoff_rule` (the registry line), and one C function
(``wake_hpa_rule_t`` enumerator and its case in csrc/wake_hpa_spectrum.c).  The
built-in rules are registered by :mod:`wake.hpa.cutoff`, in the order of
their C enumerators.

This module sits in the lowest layer (docs/reference/architecture.md): it imports
nothing from the package.

Examples
--------
>>> from wake.registry import cutoff_rule_names, get_cutoff_rule
>>> import wake.hpa.cutoff                     # registers the built-in rules
>>> cutoff_rule_names()
('paper', 'shallow', 'floor')
>>> get_cutoff_rule("floor").c_name
'WAKE_HPA_RULE_FLOOR'
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

__all__ = ["CutoffRule", "register_cutoff_rule", "unregister_cutoff_rule", "cutoff_rule_names",
           "get_cutoff_rule", "cutoff_rules"]


@dataclass(frozen=True)
class CutoffRule:
    """One cut-off rule."""

    name: str             #: the value of ``WakeConfig.cutoff_rule`` and ``--cutoff-rule``
    function: Callable    #: ``function(spectrum) -> (f_d, flag)`` on a :class:`wake.hpa.cutoff.Spectrum`
    c_name: str           #: its ``wake_hpa_rule_t`` enumerator; its number is its place in the registry
    description: str      #: one line for the command line's help and the docs


_RULES: dict[str, CutoffRule] = {}


def register_cutoff_rule(name: str, *, c_name: str, description: str):
    """Decorator: register ``function`` as the cut-off rule ``name`` (returns it unchanged).

    Raises ``ValueError`` when ``name`` or ``c_name`` is taken already.
    """
    if not name.isidentifier():
        raise ValueError(f"a cut-off rule name must be an identifier, got {name!r}")

    def register(function):
        for rule in _RULES.values():
            if name == rule.name or c_name == rule.c_name:
                raise ValueError(f"cut-off rule {name!r} ({c_name}) clashes with the registered "
                                 f"{rule.name!r} ({rule.c_name})")
        _RULES[name] = CutoffRule(name, function, c_name, description)
        return function

    return register


def unregister_cutoff_rule(name: str) -> None:
    """Remove rule ``name`` (for experiments and tests; the built-in rules stay in use elsewhere)."""
    get_cutoff_rule(name)
    del _RULES[name]


def cutoff_rules() -> tuple:
    """Every registered :class:`CutoffRule`, in registration order (the C enumerators' order)."""
    return tuple(_RULES.values())


def cutoff_rule_names() -> tuple:
    """The names of the registered rules, in registration order."""
    return tuple(_RULES)


def get_cutoff_rule(name: str) -> CutoffRule:
    """The rule ``name``, or ``ValueError`` listing the valid choices."""
    try:
        return _RULES[name]
    except (KeyError, TypeError):
        raise ValueError(f"unknown cut-off rule {name!r}; valid choices: {', '.join(_RULES)}") from None
