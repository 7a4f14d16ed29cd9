"""Dynamic epistemic logic: formulas, Kripke models, announcements, action models,
bisimulation contraction and epistemic planning. Pure logic, no robots.

Imported as ``epistemica.del_`` (``del`` is a Python keyword). The modules are grouped in
families: ``language/`` (formulas and their grammar), ``explicit/`` (Kripke models as
arrays and their algorithms), ``symbolic/`` (knowledge structures on BDDs), ``models.py``
(the public model classes of both backends), ``spec/`` (the ``.epi`` language),
``formats/`` (EPDDL and SMCDEL's text format) and ``planning/``; see
docs/architecture.md. Import public names from here.
"""

import importlib

# Each public name and the submodule it lives in. They are loaded on first use (PEP 562),
# so that importing the package, and with it the command line's --help, does not pay
# for numpy, scipy, networkx, lark and oxidd before they are needed.
_SOURCES = {
    "explicit.action": (
        "ActionModel",
        "private_announcement",
        "product_update",
        "public_announcement",
        "public_assignment",
        "range_names",
        "semi_private_sensing",
    ),
    "explicit.bisimulation": ("bisimilar", "bisimulation_classes", "minimize"),
    "explicit.checker": ("evaluate",),
    "planning.coordination": (
        "CoordinationReport",
        "check_implicit_coordination",
        "plan_implicitly_coordinated",
    ),
    "explicit.describe": ("describe_model",),
    "errors": (
        "EpistemicState",
        "EpistemicaError",
        "InvalidArgumentError",
        "ModelError",
        "ParseError",
        "SourceError",
        "SpecError",
    ),
    "explicit.export": ("to_dot", "to_networkx"),
    "formats.epddl": ("EpddlTask", "load_epddl", "parse_epddl"),
    "formats.epddl_export": ("to_epddl",),
    "formats.smcdel": ("SmcdelFile", "load_smcdel", "parse_smcdel", "to_smcdel"),
    "language.formula": (
        "And",
        "Atom",
        "Bottom",
        "Formula",
        "Iff",
        "Implies",
        "Not",
        "Or",
        "Top",
        "canonical_atom",
        "conjunction",
        "disjunction",
    ),
    "language.modalities": (
        "After",
        "Announce",
        "AnnounceDiamond",
        "Believe",
        "Common",
        "CommonBelief",
        "ConditionalBelief",
        "ConservativeUpgrade",
        "Distributed",
        "Everybody",
        "EverybodyBelieves",
        "Know",
        "KnowWhether",
        "RadicalUpgrade",
        "SafeBelief",
    ),
    "explicit.observability": ("observability_action",),
    "language.parser": (
        "FORMULA_GRAMMAR",
        "FormulaBuilder",
        "as_formula",
        "build_imported_formula",
        "parse_formula",
    ),
    "planning.planner": ("PlanResult", "Validation", "plan", "plan_with_stats", "validate"),
    "planning.policy": ("Decision", "Policy", "check_policy", "plan_policy"),
    "planning.symbolic_search": ("plan_symbolic", "plan_symbolic_with_stats", "validate_symbolic"),
    "spec._document": ("Check", "Spec", "load_spec", "parse_spec"),
    "spec._names": ("range_names",),
    "state.observation": ("Observation",),
    "state.state": ("EpistemicState",),
    "models": ("KnowledgeStructure", "KripkeModel"),
    "explicit.plausibility": ("PlausibilityModel",),
    "symbolic.plausibility": ("PlausibilityStructure",),
}
_WHERE = {name: module for module, names in _SOURCES.items() for name in names}


def __getattr__(name: str):
    module = _WHERE.get(name)
    if module is not None:
        value = getattr(importlib.import_module(f"{__name__}.{module}"), name)
    elif not name.startswith("__"):  # a submodule, e.g. epistemica.del_.explicit.checker
        try:
            value = importlib.import_module(f"{__name__}.{name}")
        except ModuleNotFoundError as exc:
            if exc.name != f"{__name__}.{name}":
                raise
            raise AttributeError(f"module {__name__!r} has no attribute {name!r}") from None
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})


__all__ = [
    "FORMULA_GRAMMAR",
    "ActionModel",
    "After",
    "And",
    "Announce",
    "AnnounceDiamond",
    "Atom",
    "Believe",
    "Bottom",
    "Check",
    "Common",
    "CommonBelief",
    "ConditionalBelief",
    "ConservativeUpgrade",
    "CoordinationReport",
    "Decision",
    "Distributed",
    "EpddlTask",
    "EpistemicState",
    "EpistemicaError",
    "Everybody",
    "EverybodyBelieves",
    "Formula",
    "FormulaBuilder",
    "Iff",
    "Implies",
    "InvalidArgumentError",
    "Know",
    "KnowWhether",
    "KnowledgeStructure",
    "KripkeModel",
    "ModelError",
    "Not",
    "Observation",
    "Or",
    "ParseError",
    "PlanResult",
    "PlausibilityModel",
    "PlausibilityStructure",
    "Policy",
    "RadicalUpgrade",
    "SafeBelief",
    "SmcdelFile",
    "SourceError",
    "Spec",
    "SpecError",
    "Top",
    "Validation",
    "as_formula",
    "bisimilar",
    "bisimulation_classes",
    "build_imported_formula",
    "canonical_atom",
    "check_implicit_coordination",
    "check_policy",
    "conjunction",
    "describe_model",
    "disjunction",
    "evaluate",
    "load_epddl",
    "load_smcdel",
    "load_spec",
    "minimize",
    "observability_action",
    "parse_epddl",
    "parse_formula",
    "parse_smcdel",
    "parse_spec",
    "plan",
    "plan_implicitly_coordinated",
    "plan_policy",
    "plan_symbolic",
    "plan_symbolic_with_stats",
    "plan_with_stats",
    "private_announcement",
    "product_update",
    "public_announcement",
    "public_assignment",
    "range_names",
    "semi_private_sensing",
    "to_dot",
    "to_epddl",
    "to_networkx",
    "to_smcdel",
    "validate",
    "validate_symbolic",
]
