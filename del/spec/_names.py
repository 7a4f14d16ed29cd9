"""Names in spec files: ranges, predicate atoms, parameters and action schemas.

Helper of :mod:`epistemica.del_.spec._compiler`. A list of names may use ranges
(``m1..m4``, ``m[1..4]``); a predicate atom expands over the ranges of its arguments
(``at(r1..r2, g1)``); a parametrised action header ``action open(i in agents)`` expands
into one action per binding of its parameters, and the parameters are substituted in the
action's formulas (:func:`bind`) and lists. The functions take the spec compiler as their
first argument and raise its located :class:`~epistemica.del_.errors.SpecError`.

Examples
--------
>>> names_hint("alcie", ["alice", "bob"], "agent")
"declared agents: alice, bob; did you mean 'alice'?"
"""

from __future__ import annotations

import difflib
import itertools
import math
import re
from collections.abc import Callable, Iterable, Mapping
from typing import Any

from lark import Token, Tree

from epistemica.del_.language.parser import transform_iteratively

__all__ = [
    "MAX_ACTIONS",
    "MAX_DIGITS",
    "MAX_EXPANDED",
    "MAX_RANGE",
    "atom_items",
    "atom_ref",
    "bind",
    "check_count",
    "expand",
    "headers",
    "names_hint",
    "range_names",
]

# The limits below are checked before anything is allocated, so a typo in a bound cannot
# hang the compiler or eat the memory (docs/language.md, "Limits").

#: A range bound is a number of at most this many digits.
MAX_DIGITS = 9
#: A range such as m1..m1000000 is almost certainly a typo; refuse it before it eats memory.
MAX_RANGE = 100_000
#: At most this many names come from one list or one predicate atom, and a spec declares
#: at most this many agents and this many atoms.
MAX_EXPANDED = 1_000_000
#: A spec has at most this many actions, schemas expanded (each costs about 0.2 ms and
#: 2 kB to compile, so the limit is about 20 s and 200 MB).
MAX_ACTIONS = 100_000
_NUMBERED = re.compile(r"^(.*?)(\d+)$")


def expand(comp: Any, item: Tree | Token, env: Mapping[str, str]) -> list[tuple[str, Token]]:
    """Names of a ``names``/``name`` node with ranges expanded and parameters bound."""
    if isinstance(item, Token):
        return [(env.get(str(item), str(item)), item)]
    if item.data == "names" or item.data == "arguments":
        found: list[tuple[str, Token]] = []
        for child in item.children:
            found.extend(expand(comp, child, env))
            check_count(comp, len(found), child, "the list")
        return found
    if item.data in ("single", "number"):
        return expand(comp, item.children[0], env)
    if item.data == "indexed":
        stem, low, high = item.children
        return _range(
            comp, stem, str(stem), _bound(comp, str(low), low), _bound(comp, str(high), high),
            len(str(low)), high,
        )  # fmt: skip
    first, last = item.children  # span: m1..m4
    head, tail = _NUMBERED.match(str(first)), _NUMBERED.match(str(last))
    if head is None or tail is None or head.group(1) != tail.group(1):
        raise comp.error(
            f"cannot expand the range {first}..{last}",
            first,
            "a range joins two names that differ only in a final number, as in m1..m4",
        )
    digits = head.group(2)
    low, high = _bound(comp, digits, first), _bound(comp, tail.group(2), last)
    return _range(comp, first, head.group(1), low, high, len(digits), last)


class _Reporter:
    """The one method of a compiler that :func:`expand` calls."""

    def __init__(self, error: Callable[..., Exception]) -> None:
        self.error = error


def range_names(
    first: Token, last: Token, error: Callable[..., Exception]
) -> list[tuple[str, Token]]:
    """The names of the range ``first..last``, each with the token to blame, as spec files
    expand them (``r01..r03`` keeps its zero padding); ``error(message, token, hint)``
    makes the located error of the caller's language.

    Examples
    --------
    >>> from lark import Token
    >>> [n for n, _ in range_names(Token("NAME", "r01"), Token("NAME", "r03"), ValueError)]
    ['r01', 'r02', 'r03']
    """
    return expand(_Reporter(error), Tree("span", [first, last]), {})


def _bound(comp: Any, digits: str, token: Token) -> int:
    # Checked before int(): Python refuses to convert 4,300 digits and more (ValueError).
    if len(digits) > MAX_DIGITS:
        raise comp.error(
            f"a range bound of {len(digits)} digits; at most {MAX_DIGITS} are allowed",
            token,
            f"ranges run between numbers below 10^{MAX_DIGITS}, as in m1..m4 or m[1..4]",
        )
    return int(digits)


def check_count(
    comp: Any, count: int, where: Tree | Token, what: str, limit: int = MAX_EXPANDED
) -> None:
    """Refuse ``count`` names (or actions) from ``what`` when it exceeds ``limit``."""
    if count > limit:
        unit = "actions" if limit == MAX_ACTIONS else "names"
        raise comp.error(
            f"{what} expands to {count:,} {unit}; at most {limit:,} are allowed",
            where,
            "check the bounds of the ranges and the domains of the parameters",
        )


def _range(comp: Any, at: Token, stem: str, low: int, high: int, width: int, end: Token):
    if high < low:
        raise comp.error(f"empty range from {low} to {high}", end, "write the smaller first")
    if high - low >= MAX_RANGE:
        raise comp.error(
            f"the range has {high - low + 1} names, more than {MAX_RANGE}", end,
            "check the bounds of the range",
        )  # fmt: skip
    width = width if width > 1 else 1  # m01..m10 keeps its zero padding
    return [(f"{stem}{i:0{width}d}", at) for i in range(low, high + 1)]


def atom_items(comp: Any, node: Tree, env: Mapping[str, str]) -> list[tuple[str, Token]]:
    """Atom keys of an ``atoms`` node (predicates expanded over their argument ranges)."""
    found = []
    for child in node.children:
        if isinstance(child, Tree) and child.data == "predicate":
            stem, arguments = child.children
            options = [[n for n, _ in expand(comp, a, env)] for a in arguments.children]
            size = math.prod(len(option) for option in options)
            check_count(comp, size, stem, f"the predicate atom '{stem}'")
            check_count(comp, len(found) + size, stem, "the list of atoms")
            for combo in itertools.product(*options):
                found.append((f"{stem}({', '.join(combo)})", stem))
        else:
            found.extend(expand(comp, child, env))
            check_count(comp, len(found), child, "the list of atoms")
    return found


def atom_ref(comp: Any, node: Tree, env: Mapping[str, str]) -> tuple[str, Token]:
    """The key of an ``atom_ref`` node (the target of an assignment), parameters bound."""
    stem, arguments = node.children
    if arguments is None:
        return env.get(str(stem), str(stem)), stem
    args = [n for n, _ in expand(comp, arguments, env)]
    return f"{stem}({', '.join(args)})", stem


def bind(tree: Tree, env: Mapping[str, str]) -> Tree:
    """A copy of a formula tree with parameter names replaced, positions kept."""
    return transform_iteratively(_Bind(env), tree)


class _Bind:
    """Rebuilds every node (no rule has a method here) with the parameters replaced."""

    def __init__(self, env: Mapping[str, str]) -> None:
        self.env = env

    def __default__(self, data: str, children: list, meta: Any) -> Tree:
        env = self.env
        return Tree(data, [_substituted(child, env) for child in children], meta)


def _substituted(child: Any, env: Mapping[str, str]) -> Any:
    if isinstance(child, Token) and child.type in ("NAME", "INT") and str(child) in env:
        return child.update(value=env[str(child)])
    return child


def headers(comp: Any, decls: list[Tree], agents: tuple[str, ...]) -> dict[str, tuple]:
    """Action name -> (declaration, parameter binding), schemas expanded in order.

    A schema ``action tell(i in {a, b}, x in agents)`` contributes ``tell(a, a)``,
    ``tell(a, b)``, ... (the product of the domains, in the order written).
    """
    found: dict[str, tuple] = {}
    for decl in decls:
        name, parameters = decl.children[:2]
        bindings: list[dict[str, str]] = [{}]
        if parameters is not None:
            names, domains = [], []
            for param in parameters.children:
                pname, domain = param.children
                if str(pname) in names:
                    raise comp.error(f"parameter '{pname}' given twice", pname, "rename one")
                if str(pname) in agents:
                    raise comp.error(
                        f"parameter '{pname}' has the name of an agent", pname,
                        "rename the parameter, e.g. to 'i'",
                    )  # fmt: skip
                names.append(str(pname))
                if domain.data == "all_agents":
                    domains.append(list(agents))
                else:
                    domains.append(
                        list(dict.fromkeys(n for n, _ in expand(comp, domain.children[0], {})))
                    )
            size = math.prod(len(domain) for domain in domains)
            check_count(comp, size, name, f"the action schema '{name}'", MAX_ACTIONS)
            check_count(comp, len(found) + size, name, "the actions of the spec", MAX_ACTIONS)
            bindings = [
                dict(zip(names, combo, strict=True)) for combo in itertools.product(*domains)
            ]
        for env in bindings:
            key = str(name) if not env else f"{name}({', '.join(env.values())})"
            if key in found:
                first = found[key][0].children[0]
                raise comp.error(
                    f"action '{key}' declared twice", name,
                    f"first declared at {first.line}:{first.column}; rename one",
                )  # fmt: skip
            found[key] = (decl, env)
    return found


def names_hint(name: str, options: Iterable[str], kind: str = "name") -> str:
    """A hint listing the declared names, with the closest match to ``name`` if any."""
    options = sorted(set(options))
    listing = ", ".join(options[:12]) + (", ..." if len(options) > 12 else "")
    hint = f"declared {kind}s: {listing}" if options else f"no {kind}s are declared"
    match = difflib.get_close_matches(name, options, n=1)
    if match:
        hint += f"; did you mean '{match[0]}'?"
    return hint
