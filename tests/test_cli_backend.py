"""``epistemica check --backend``: the symbolic backend answers where the explicit one
cannot, and both give the same verdicts where both can."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from epistemica.cli import main

ROOT = Path(__file__).resolve().parents[1]
# The puzzles small enough for both backends (the generated large ones are symbolic only).
PUZZLES = sorted(p for p in (ROOT / "specs" / "puzzles").glob("*.epi") if p.stat().st_size < 20_000)


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def muddy_spec(n: int, muddy: int = 3) -> str:
    lines = [f"agents c1..c{n}", f"atoms m1..m{n}"]
    for i in range(1, n + 1):
        lines.append(f"observes c{i}: " + ", ".join(f"m{j}" for j in range(1, n + 1) if j != i))
    lines.append("actual {" + ", ".join(f"m{i}" for i in range(1, muddy + 1)) + "}")
    lines.append("action father: public " + " | ".join(f"m{i}" for i in range(1, n + 1)))
    nobody = " & ".join(f"~Kw[c{i}] m{i}" for i in range(1, n + 1))
    lines.append(f"action nobody_knows: public {nobody}")
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("path", PUZZLES, ids=[p.name for p in PUZZLES])
def test_every_puzzle_gets_the_same_verdicts(capsys, path):
    verdicts = {}
    for backend in ("explicit", "symbolic"):
        code, out, _ = run(capsys, "check", str(path), "--json", "--backend", backend)
        claims = json.loads(out)["claims"]
        verdicts[backend] = (code, [(c["name"], c["holds"]) for c in claims])
    assert verdicts["explicit"] == verdicts["symbolic"]


def test_thirty_children_need_the_symbolic_backend(capsys, tmp_path):
    path = tmp_path / "muddy30.epi"
    path.write_text(muddy_spec(30), encoding="utf-8")
    know = "[father][nobody_knows][nobody_knows] (K[c1] m1 & K[c2] m2 & K[c3] m3)"
    code, _, err = run(capsys, "check", str(path), "--backend", "explicit", "-f", know)
    assert code == 2 and "too many to enumerate" in err and "--backend symbolic" in err
    # With 3 muddy children, they know after the father and two rounds, not after one.
    code, out, _ = run(capsys, "check", str(path), "-f", know)
    assert code == 0 and "holds at 1 of 1" in out
    code, out, _ = run(
        capsys, "check", str(path), "--json", "-f", "[father][nobody_knows] K[c1] m1",
        "--expect", "true",
    )  # fmt: skip
    summary = json.loads(out)
    assert code == 1 and summary["holds"] is False
    assert (summary["format"], summary["version"]) == ("epistemica-check-formula", 1)
    assert summary["n_worlds"] == 2**30


def test_unknown_backend_is_a_usage_error(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["check", str(PUZZLES[0]), "--backend", "quantum"])
    assert exit_.value.code == 2
