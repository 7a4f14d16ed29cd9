"""Dynamic epistemic logic: formulas, Kripke models, announcements, action models,
bisimulation contraction and epistemic planning. Pure logic, no robots.

Imported as ``epistemica.del_`` (``del`` is a Python keyword).
"""

from epistemica.del_.action import (
    ActionModel,
    private_announcement,
    product_update,
    public_announcement,
    public_assignment,
    semi_private_sensing,
)
from epistemica.del_.bisimulation import bisimilar, bisimulation_classes, minimize
from epistemica.del_.checker import evaluate
from epistemica.del_.coordination import (
    CoordinationReport,
    check_implicit_coordination,
    plan_implicitly_coordinated,
)
from epistemica.del_.describe import describe_model
from epistemica.del_.errors import (
    EpistemicaError,
    InvalidArgumentError,
    ModelError,
    ParseError,
    SourceError,
    SpecError,
)
from epistemica.del_.export import to_dot, to_networkx
from epistemica.del_.formula import (
    After,
    And,
    Announce,
    AnnounceDiamond,
    Atom,
    Believe,
    Bottom,
    Common,
    CommonBelief,
    Distributed,
    Everybody,
    EverybodyBelieves,
    Formula,
    Iff,
    Implies,
    Know,
    KnowWhether,
    Not,
    Or,
    Top,
    canonical_atom,
    conjunction,
    disjunction,
)
from epistemica.del_.kripke import KripkeModel
from epistemica.del_.observability import observability_action
from epistemica.del_.parser import FORMULA_GRAMMAR, FormulaBuilder, parse_formula
from epistemica.del_.planner import PlanResult, Validation, plan, plan_with_stats, validate
from epistemica.del_.spec import Check, Spec, load_spec, parse_spec
from epistemica.del_.symbolic import KnowledgeStructure

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
    "CoordinationReport",
    "Distributed",
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
    "Or",
    "ParseError",
    "PlanResult",
    "SourceError",
    "Spec",
    "SpecError",
    "Top",
    "Validation",
    "bisimilar",
    "bisimulation_classes",
    "canonical_atom",
    "check_implicit_coordination",
    "conjunction",
    "describe_model",
    "disjunction",
    "evaluate",
    "load_spec",
    "minimize",
    "observability_action",
    "parse_formula",
    "parse_spec",
    "plan",
    "plan_implicitly_coordinated",
    "plan_with_stats",
    "private_announcement",
    "product_update",
    "public_announcement",
    "public_assignment",
    "semi_private_sensing",
    "to_dot",
    "to_networkx",
    "validate",
]
