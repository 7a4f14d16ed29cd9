"""Write the missions where nested knowledge decides by construction (specs/nested/).

Five missions at 3 and 5 robots (``moved`` is ``relocated`` with the new place fixed 6 m
from the old one, added after ``relocated`` missed its target: docs/results.md §7). In
each, what a robot knows that a teammate does not know (and knows that the teammate does
not know) decides where the team can meet or who takes which goal, and the robots see each
other only within a few metres: they cannot read from motion what they cannot see.

    python benchmarks/nested_suite.py            # rewrites specs/nested/*.epi
    python benchmarks/nested_suite.py --tried DIR   # and the missions tried, not kept

Tried and not kept (docs/results.md §7): ``closed_goal``, the issue's own example of an
asymmetric observation, a goal closing seen only nearby. It separates no level.
"""

from __future__ import annotations

import argparse
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "specs" / "nested"
LEVELS = "convention, rules_first, rules_third_shared, rules_third, third"

HEADER = {
    "private_goal": """\
# Second-order private knowledge (rendezvous, {n} robots). r1 alone knows of goal g4, at
# the centre of the workspace: the cheapest meeting place for most starts. The others do
# not know of it, and r1 knows that they do not (it knows they cannot have seen it). From
# its own view (first order), or taking its teammates to know what it knows
# (rules_third_shared), r1 heads for g4 whenever it is cheapest, and waits there for a team that
# never comes (they see each other only within 6 m). Third order predicts each teammate's
# choice over the goals that teammate knows, and meets it there.""",
    "relocated": """\
# False belief (a robots' Sally-Anne; rendezvous, {n} robots). The team's meeting place,
# g4 at the centre, is moved at step 0 to g5 (closed until then, placed at random): g4
# closes and g5 opens. Only robots within 10 m of either place see it; the others still
# believe g4 open and do not know g5 exists, and those who saw it know that. A robot that
# saw it and heads for g5 (rules_first, rules_third_shared) waits for teammates who will go to
# g4, find it shut and choose among the goals they know. Third order predicts that
# choice and goes there.""",
    "moved": """\
# False belief, the place moved a few metres (a robots' Sally-Anne; rendezvous, {n}
# robots). The team's meeting place, g4 at the centre, is moved at step 0 to g5, 6 m east
# of it: g4 closes and g5 opens. Only robots within 10 m of either place see it; the
# others still believe g4 open and do not know g5 exists, and those who saw it know that.
# A robot that did not see it goes to g4 and finds it shut, but from there sees neither
# g5 (3 m) nor a robot waiting at it (4 m), and chooses among the goals it knows. g5 lies
# near the centre, so it is the cheapest goal for a robot that saw the move in most
# trials: that robot (rules_first, rules_third_shared) waits at g5 for teammates who never
# come. Third order predicts where they go once they find g4 shut, and goes there.""",
    "new_goal": """\
# Asymmetric observation (rendezvous, {n} robots). At the start a new goal opens at the centre
# of the workspace, g4, the cheapest meeting place for most starts; only robots within 10 m
# see it open, and they know who else did. A robot that saw it and heads for it (first
# order, or rules_third_shared, which takes every teammate to have seen it) waits for teammates
# who do not know it exists. Third order meets them at a goal they know.""",
    "commitment": """\
# Commitment before motion reveals intent (rendezvous, {n} robots). The robots see each
# other only within 4 m and nobody sees a teammate settle: each must commit to a goal from
# what it knows of what the others know. Goals g1 and g2 are known to everyone (and
# everyone knows it); goals g3 to g5 are each known to two robots, who do not know who
# else knows them. A robot choosing from its own view (first order) or taking the others
# to know what it knows (rules_third_shared) goes to a goal some teammates have never heard of
# whenever it is cheaper; third order predicts each teammate's choice over the goals it
# knows the teammate knows, and meets the team at one of those.""",
}


TRIED = {
    "closed_goal": """\
# Asymmetric observation of a closing (rendezvous, {n} robots; tried, not kept). The
# meeting place everyone knows, g4 at the centre, closes at step 0; only robots within
# 10 m see it, and they know who else did. The others head for g4, see it shut there and
# choose again among g1-g3, which everyone knows.""",
}


#: The false-belief missions: where the meeting place moves (g5), and the trial of the
#: claim checked after the move (one where r1 saw it and r2 did not).
MOVES = {"relocated": ("at random", 1), "moved": ("at (21, 15)", 1000)}


def _robots(n: int) -> str:
    return ", ".join(f"r{i}" for i in range(2, n + 1))


def _central_goal(n: int) -> list[str]:
    """A rendezvous of ``n`` robots, goals g1-g3 at random and g4 at the centre."""
    return [
        "mission rendezvous",
        "workspace 30",
        f"robot r1..r{n}: random at random",
        "goal g1..g3 at random",
        "goal g4 at (15, 15)",
    ]


def mission(kind: str, n: int) -> str:
    """The text of one mission file."""
    lines = [{**HEADER, **TRIED}[kind].format(n=n, extra=n + 1)]
    if kind == "closed_goal":
        lines += [
            *_central_goal(n),
            "knows " + ", ".join(f"r{i}" for i in range(1, n + 1)) + ": g1, g2, g3, g4",
            "sensing model paper noise 0.5 range 4 discovery 3",
            "event closing {",
            "    when step 0",
            "    closes g4",
            "    announces closed(g4)",
            "    full robots if near(g4, 10)",
            "}",
        ]
    elif kind == "commitment":
        pairs = [(1, 2), (2, 3), (1, 3)] if n == 3 else [(1, 2), (3, 4), (2, 5)]
        lines += [
            "mission rendezvous",
            "workspace 30",
            f"robot r1..r{n}: random at random",
            "goal g1..g5 at random",
            "knows " + ", ".join(f"r{i}" for i in range(1, n + 1)) + ": g1, g2",
        ]
        for goal, pair in zip((3, 4, 5), pairs, strict=True):
            lines.append(f"knows r{pair[0]}, r{pair[1]}: g{goal}")
        lines += [
            "sensing model paper noise 0.5 range 4 discovery 2",
            f'check "r{pairs[0][0]} knows g3 but believes r3 does not conceive of it":',
            f"    ~B[r{pairs[0][0]}] closed(g3) & B[r{pairs[0][0]}] B[r3] closed(g3)",
        ]
    else:
        lines += _central_goal(n)
        if kind == "private_goal":
            lines += [
                "knows r1: g1, g2, g3, g4",
                f"knows {_robots(n)}: g1, g2, g3",
                "sensing model paper noise 0.5 range 6 discovery 3",
                "event settle seen by nearby",
                'check "r1 believes r2 does not conceive of meeting at g4":',
                "    B[r1] B[r2] closed(g4) & ~B[r1] closed(g4)",
            ]
        else:
            move = MOVES.get(kind)
            lines += [f"goal g5 {move[0]} closed"] if move else []
            if kind == "new_goal":
                lines[-1] = "goal g4 at (15, 15) closed"
            lines += [
                "knows "
                + ", ".join(f"r{i}" for i in range(1, n + 1))
                + (": g1, g2, g3" if kind == "new_goal" else ": g1, g2, g3, g4"),
                "sensing model paper noise 0.5 range 4 discovery 3",
            ]
            if move:
                lines += [
                    "event relocate {",
                    "    when step 0",
                    "    closes g4",
                    "    opens g5",
                    "    announces closed(g4)",
                    "    reveals g5",
                    "    full robots if near(g4, 10) | near(g5, 10)",
                    "}",
                ]
            else:
                lines += [
                    "event opening {",
                    "    when step 0",
                    "    opens g4",
                    "    reveals g4",
                    "    full robots if near(g4, 10)",
                    "}",
                ]
            claim = (
                ("no robot conceives of meeting at g4 before it opens", "B[r1] closed(g4)")
                if kind == "new_goal"
                else ("every robot believes the team may meet at g4", "~B[r1] closed(g4)")
            )
            nested = "B[r2] B[r1] closed(g4)" if kind == "new_goal" else "~B[r2] B[r1] closed(g4)"
            lines += [f'check "at the start {claim[0]}":', f"    {claim[1]} & {nested}"]
            # A trial where r1 saw the event and r2 did not, and r1 knows it: the case in
            # which acting on its own view (first order, third_shared) splits the team.
            after = (
                ("r1 saw g4 open and believes r2 did not", 0,
                 "~B[r1] closed(g4) & B[r1] B[r2] closed(g4)")
                if kind == "new_goal"
                else ("r1 saw the move and believes r2 still heads for g4",
                      move[1],
                      "B[r1] closed(g4) & ~B[r1] closed(g5) & B[r1] B[r2] closed(g5)"
                      " & B[r1] ~B[r2] closed(g4)")
            )  # fmt: skip
            lines += [f'check "{after[0]}" after 1 steps seed {after[1]}:', f"    {after[2]}"]
    lines.append(f"simulate trials 100 seed 0 steps 60 levels {LEVELS}")
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tried", type=Path, help="also write the missions not kept here")
    args = parser.parse_args()
    targets = [(OUT, HEADER)] + ([(args.tried, TRIED)] if args.tried else [])
    for folder, kinds in targets:
        folder.mkdir(parents=True, exist_ok=True)
        for kind in kinds:
            for n in (3, 5):
                (folder / f"{kind}_{n}.epi").write_text(mission(kind, n), encoding="utf-8")
        print(f"wrote {2 * len(kinds)} missions to {folder}")


if __name__ == "__main__":
    main()
