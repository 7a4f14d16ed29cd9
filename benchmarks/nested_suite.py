"""Write the missions where nested knowledge decides by construction (specs/nested/).

Four missions at 3 and 5 robots. In each, what a robot knows that a teammate does not
know (and knows that the teammate does not know) decides where the team can meet or who
takes which goal, and the robots see each other only within 6 m:
they cannot read from motion what they cannot see.

    python benchmarks/nested_suite.py            # rewrites specs/nested/*.epi
"""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "specs" / "nested"
LEVELS = "convention, first, third_shared, third"

HEADER = {
    "private_goal": """\
# Second-order private knowledge (rendezvous, {n} robots). r1 alone knows of goal g4, at
# the centre of the workspace: the cheapest meeting place for most starts. The others do
# not know of it, and r1 knows that they do not (it knows they cannot have seen it). From
# its own view (first order), or taking its teammates to know what it knows
# (third_shared), r1 heads for g4 whenever it is cheapest, and waits there for a team that
# never comes (they see each other only within 6 m). Third order predicts each teammate's
# choice over the goals that teammate knows, and meets it there.""",
    "relocated": """\
# False belief (a robots' Sally-Anne; rendezvous, {n} robots). The team's meeting place,
# g4 at the centre, is moved at step 2 to g5 (closed until then, placed at random): g4
# closes and g5 opens. Only robots within 6 m of either place see it; the others still
# believe g4 open and do not know g5 exists, and those who saw it know that. A robot that
# saw it and heads for g5 (first order, third_shared) waits for teammates who will go to
# g4, find it shut and choose among the goals they know. Third order predicts that
# choice and goes there.""",
    "new_goal": """\
# Asymmetric observation (rendezvous, {n} robots). At step 2 a new goal opens at the centre
# of the workspace, g4, the cheapest meeting place for most starts; only robots within 6 m
# see it open, and they know who else did. A robot that saw it and heads for it (first
# order, or third_shared, which takes every teammate to have seen it) waits for teammates
# who do not know it exists. Third order meets them at a goal they know.""",
    "commitment": """\
# Commitment before motion reveals intent (allocation, {n} robots). The robots see each
# other only within 6 m, so motion tells little. r1 alone knows of an extra goal g{extra},
# at the centre;
# the others allocate themselves the goals they know, and r1 knows they do. First order
# (and third_shared) lets r1 compute the cheapest allocation over every goal it knows,
# which may send a teammate to g{extra}, a goal that teammate will never take, and r1 to
# the goal that teammate will take. Third order predicts each teammate's goal from the
# goals it knows and takes what is left.""",
}


def _robots(n: int) -> str:
    return ", ".join(f"r{i}" for i in range(2, n + 1))


def mission(kind: str, n: int) -> str:
    """The text of one mission file."""
    lines = [HEADER[kind].format(n=n, extra=n + 1)]
    if kind == "commitment":
        lines += [
            "mission allocation",
            "workspace 30",
            f"robot r1..r{n}: random at random",
            f"goal g1..g{n} at random",
            f"goal g{n + 1} at (15, 15)",
            f"knows r1: {', '.join(f'g{g}' for g in range(1, n + 2))}",
            f"knows {_robots(n)}: {', '.join(f'g{g}' for g in range(1, n + 1))}",
            "sensing model paper noise 0.5 range 6 discovery 3",
            "event settle seen by nearby",
            f'check "r1 believes r2 does not conceive of going to g{n + 1}":',
            f"    B[r1] B[r2] closed(g{n + 1})",
        ]
    else:
        lines += [
            "mission rendezvous",
            "workspace 30",
            f"robot r1..r{n}: random at random",
            "goal g1..g3 at random",
            "goal g4 at (15, 15)",
        ]
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
            lines += ["goal g5 at random closed"] if kind == "relocated" else []
            if kind == "new_goal":
                lines[-1] = "goal g4 at (15, 15) closed"
            lines += [
                "knows "
                + ", ".join(f"r{i}" for i in range(1, n + 1))
                + (": g1, g2, g3" if kind == "new_goal" else ": g1, g2, g3, g4"),
                "sensing model paper noise 0.5 range 6 discovery 3",
                "event settle seen by nearby",
            ]
            if kind == "relocated":
                lines += [
                    "event relocate {",
                    "    when step 2",
                    "    closes g4",
                    "    opens g5",
                    "    announces closed(g4)",
                    "    reveals g5",
                    "    full robots if near(g4, 6) | near(g5, 6)",
                    "}",
                ]
            else:
                lines += [
                    "event opening {",
                    "    when step 2",
                    "    opens g4",
                    "    reveals g4",
                    "    full robots if near(g4, 6)",
                    "}",
                ]
            claim = (
                ("no robot conceives of meeting at g4 before it opens", "B[r1] closed(g4)")
                if kind == "new_goal"
                else ("every robot believes the team may meet at g4", "~B[r1] closed(g4)")
            )
            nested = "B[r2] B[r1] closed(g4)" if kind == "new_goal" else "~B[r2] B[r1] closed(g4)"
            lines += [f'check "at the start {claim[0]}":', f"    {claim[1]} & {nested}"]
    lines.append(f"simulate trials 100 seed 0 steps 60 levels {LEVELS}")
    return "\n".join(lines) + "\n"


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    for kind in HEADER:
        for n in (3, 5):
            (OUT / f"{kind}_{n}.epi").write_text(mission(kind, n), encoding="utf-8")
    print(f"wrote {2 * len(HEADER)} missions to {OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
