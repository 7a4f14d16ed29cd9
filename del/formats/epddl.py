"""EPDDL tasks read into the objects a ``.epi`` spec compiles into.

EPDDL, the Epistemic Planning Domain Definition Language, is the input language of the plank
toolkit and of the first International Epistemic Planning Competition: a task is a domain
(types, predicates, events, actions), a problem (objects, agents, initial state, goal) and
the action-type libraries the domain names. :func:`load_epddl` compiles one into an
:class:`EpddlTask`, whose ``spec`` is a :class:`~epistemica.del_.spec.Spec` (initial
:class:`~epistemica.del_.KripkeModel`, one
:class:`~epistemica.del_.explicit.action.ActionModel` per ground action, the goal), so the
planner, the checker and ``epistemica show`` work on it unchanged. The semantics is
plank's; see ``docs/epddl.md`` for what is read and how it maps.

Ground actions are named like the actions of a spec schema, ``tell(C, A)`` (EPDDL's ``-``
written ``_``); :meth:`EpddlTask.plank_plan` gives plank's names (``tell_C_A``), which
``plank validate -a`` accepts.

Examples
--------
>>> domain = '''(define (domain coin)
...   (:predicates (heads))
...   (:event look-yes :precondition (heads))
...   (:event look-no :precondition (not (heads)))
...   (:action look :parameters (?i - agent)
...     :action-type (sense (look-yes) (look-no))
...     :observability-conditions (:and (?i Fully) (default Partially))))'''
>>> library = '''(define (action-type-library lib)
...   (:action-type sense :events (?y ?n) :observability-types (Fully Partially)
...     :relations (Fully (:forall (?e - event) (?e ?e))
...                 Partially (:forall (?e ?f - event) (?e ?f)))
...     :designated (?y ?n)))'''
>>> problem = '''(define (problem show-b) (:domain coin) (:agents a b)
...   (:init (:and (heads)))
...   (:goal (and ([Kw. b] (heads)) (not ([Kw. a] (heads))))))'''
>>> task = parse_epddl(domain.replace("(define (domain coin)",
...     "(define (domain coin) (:action-type-libraries lib)"), problem, [library])
>>> sorted(task.spec.actions), task.spec.model.n_worlds
(['look(a)', 'look(b)'], 2)
>>> from epistemica.del_ import plan
>>> steps = plan(task.spec.model, task.spec.actions, task.spec.goal)
>>> steps, task.plank_plan(steps)
(['look(b)'], ['look_b'])
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from lark import Tree

from epistemica.del_.formats._epddl_actions import ground_actions
from epistemica.del_.formats._epddl_formulas import conj
from epistemica.del_.formats._epddl_ground import Grounder
from epistemica.del_.formats._epddl_state import initial_state
from epistemica.del_.formats._epddl_syntax import Source, parse
from epistemica.del_.formats.kinds import is_epddl
from epistemica.del_.language.formula import Formula
from epistemica.del_.spec import Spec, check_token_count, read_source

__all__ = ["EpddlTask", "is_epddl", "load_epddl", "parse_epddl", "read_epddl_files"]


@dataclass(frozen=True)
class EpddlTask:
    """A compiled EPDDL task.

    Attributes
    ----------
    spec : Spec
        The initial model, the ground actions and the goal, as a spec file gives them (no
        claims, no owners: EPDDL has neither).
    plank_names : dict
        Epistemica action name -> the name plank gives the ground action.
    domain_name, problem_name : str
        The names in ``(define (domain ...))`` and ``(define (problem ...))``.
    """

    spec: Spec
    plank_names: dict[str, str] = field(repr=False)
    domain_name: str = ""
    problem_name: str = ""

    def plank_plan(self, plan: Iterable[str]) -> list[str]:
        """The plank names of the actions of ``plan`` (for ``plank validate -a``)."""
        return [self.plank_names[step] for step in plan]


def parse_epddl(
    domain: str,
    problem: str,
    libraries: Sequence[str] = (),
    filenames: Sequence[str] = ("<domain>", "<problem>"),
    library_names: Sequence[str] | None = None,
) -> EpddlTask:
    """Compile the texts of an EPDDL domain, problem and action-type libraries.

    The domain and the problem may be given in either order (each file says what it is).

    Raises
    ------
    ParseError
        A text does not follow the grammar (located in that text).
    SpecError
        It parses but means nothing: an unknown name, a wrong number of arguments, a
        missing library, an inconsistent initial state, ...
    """
    names = list(library_names or [f"<library {i + 1}>" for i in range(len(libraries))])
    texts = list(zip([domain, problem, *libraries], [*filenames, *names], strict=True))
    for text, name in texts:  # before parsing any: every token costs memory
        check_token_count(text, name, "EPDDL file")
    parsed = [(parse(text, name), Source(text, name)) for text, name in texts]
    return _compile(parsed[:2], parsed[2:])


def load_epddl(
    domain: str | Path, problem: str | Path, libraries: Iterable[str | Path] = ()
) -> EpddlTask:
    """Read and compile EPDDL files (see :func:`parse_epddl`)."""
    paths = [Path(domain), Path(problem), *map(Path, libraries)]
    texts = read_epddl_files(paths)
    return parse_epddl(
        texts[0], texts[1], texts[2:], [str(p) for p in paths[:2]], [str(p) for p in paths[2:]]
    )


def read_epddl_files(paths: Sequence[Path]) -> list[str]:
    """The texts of EPDDL files, each read once and bounded (:func:`read_source`: size
    limit, binary and encoding checks); an unreadable one is a :class:`SpecError` naming it."""
    return [read_source(path, "EPDDL file") for path in paths]


def _compile(main: list[tuple[Tree, Source]], libraries: list[tuple[Tree, Source]]) -> EpddlTask:
    kinds = {tree.data: (tree, src) for tree, src in main}
    if set(kinds) != {"domain", "problem"}:
        tree, src = main[1] if main[0][0].data == "domain" else main[0]
        raise src.error(
            f"expected a domain and a problem, found a {main[0][0].data} and a "
            f"{main[1][0].data}", tree,
            "give the domain and the problem files (in any order), libraries with -l",
        )  # fmt: skip
    g = Grounder(kinds["domain"], kinds["problem"], libraries)
    model = initial_state(g)
    actions, plank = ground_actions(g, model)
    goal = _goal(g)
    src = g.psrc
    spec = Spec(
        model=model,
        actions=actions,
        goal=goal,
        checks=(),
        agents=tuple(model.agents),
        atoms=tuple(g.atoms),
        filename=src.filename,
        source=src.text,
    )
    return EpddlTask(spec, plank, str(g.domain.children[0]), str(g.problem.children[0]))


def _goal(g: Grounder) -> Formula | None:
    goals = [item for item in g.problem.children[2:] if item.data == "goal"]
    if not goals:
        return None
    return conj(g.formula(item.children[0], {}, g.psrc) for item in goals)
