"""A fuzz corpus for mission files and the simulator's commands (run, check, sweep,
simulate, report).

Each case is a mutation of a shipped mission file (every ``specs/**/*.epi`` that starts
with ``mission``; the edits of :mod:`fuzz_corpus`, plus mission words and numbers at the
edges of their ranges) and a command line drawn for it, or a command line of ``simulate``
or ``report`` with mutated parameters. Cases run in this process through
``epistemica.cli.main`` (one worker process: ``--workers 1``), with a time limit per case;
the contract is the same as the spec corpus's: exit status 0, 1 or 2 only, within the
limit, in an address space limited by ``--memory-gib``:

    python tests/fuzz_missions.py --cases 120 --seed 1

prints one JSON object (counts by status, the slowest case, every bad case).
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from fuzz_corpus import main, mutate, run_case  # a script beside this one

ROOT = Path(__file__).resolve().parents[1]


def _is_mission(path: Path) -> bool:
    for line in path.read_text(encoding="utf-8").splitlines():
        words = line.split("#", 1)[0].split()
        if words:
            return words[0] == "mission"
    return False


MISSIONS = sorted(p for p in ROOT.glob("specs/**/*.epi") if _is_mission(p))
LEVELS = ["zero", "convention", "rules-first", "rules-third", "paper-first", "bogus", "zero,zero"]
# Mission words and values at the edges of what they accept.
MISSION_PIECES = [
    "robot r1..rN: random at random", "simulate robots 12", "simulate robots 0",
    "workspace 1", "workspace 0.001", "workspace 1e6", "goal g1..g64 at random",
    "robot r1..r12: range at random", "learns r1: assigned(r1, g1) | assigned(r1, g2)",
    "knows random", "teammate random follows zero", "sensing range 0", "sensing noise 1e6",
    "simulate steps 100000", "simulate trials 0", "valid false", "initially false",
    "event settle seen by nearby", "check \"x\" after 3 steps: K[r1] assigned(r1, g1)",
    "nan", "inf", "-1", "1e308", "needs 99", "closed", "policy horizon 1000000",
]  # fmt: skip


def _pick(rng: np.random.Generator, good: list[str], bad: list[str], p_bad=0.15) -> str:
    """A value: mostly one that is accepted (so the case runs deep), sometimes a bad one."""
    return str(rng.choice(bad if rng.random() < p_bad else good))


def _mutate_mission(text: str, rng: np.random.Generator) -> bytes:
    if rng.random() < 0.5:  # whole statements of the language, each on a line of its own
        lines = text.split("\n")
        for _ in range(int(rng.integers(1, 4))):
            at = int(rng.integers(0, len(lines) + 1))
            lines.insert(at, str(rng.choice(MISSION_PIECES)))
        return "\n".join(lines).encode("utf-8")
    return mutate(text, rng)


def _robots(text: str) -> list[str]:
    return [w for w in ("r1", "r2", "r3", "a", "r9") if w in text] or ["r1"]


def _claim(text: str, rng: np.random.Generator) -> str:
    claims = [line.split(":", 1)[1] for line in text.splitlines() if line.startswith("check ")]
    claims = [c for c in claims if c.strip()] or ["K[r1] assigned(r1, g1)"]
    formula = str(rng.choice(claims)).strip()
    if rng.random() < 0.4:
        formula = mutate(formula, rng).decode("utf-8", errors="replace")
    return formula


def mission_command(path: str, text: str, rng: np.random.Generator, out: str) -> list[str]:
    """A command line of run, check or sweep for the mission file at ``path``."""
    which = str(rng.choice(["check", "check", "run", "sweep"]))
    argv = [which, path]
    if which == "check":
        if rng.random() < 0.6:
            argv += ["--formula", _claim(text, rng)]
            if rng.random() < 0.3:
                argv += ["--expect", _pick(rng, ["true", "false"], ["maybe"])]
            if rng.random() < 0.3:
                argv += ["--robot", _pick(rng, _robots(text), ["r99", ""])]
        if rng.random() < 0.4:
            argv += ["--after", _pick(rng, ["0", "1", "5"], ["-1", "x", "10**9"])]
            argv += ["--seed", _pick(rng, ["0", "3"], ["-2", str(2**80)])]
            if rng.random() < 0.5:
                argv += ["--reasoning", _pick(rng, LEVELS[:5], ["bogus"])]
        if rng.random() < 0.3:
            argv += ["--json"]
    else:
        # levels that finish fast on ten robots too (third is exercised by check --after)
        levels = _pick(rng, ["zero", "convention", "zero,zero", "zero,convention"], ["bogus", ","])
        trials = _pick(rng, ["1", "2"], ["0", "-1", str(10**12)])
        seed = _pick(rng, ["0", "7"], [str(2**80), "-1"])
        argv += ["--trials", trials, "--seed", seed, "--workers", "1", "--no-traces"]
        if which == "run":
            argv += ["--levels", levels, "--no-gif", "--out", str(Path(out) / "run.sqlite")]
        else:
            argv[1:2] = ["--mission", path, "--reasoning", levels]
            argv += ["--out", str(Path(out) / "sweep.sqlite")]
            if rng.random() < 0.5:
                argv += ["--robots", _pick(rng, ["2", "2..3"], ["13", "0", "x"])]
        if rng.random() < 0.3:
            argv += ["--resume"]
    return argv


def parameter_command(rng: np.random.Generator, out: str) -> list[str]:
    """A command line of simulate or report with drawn (often bad) parameters."""
    if rng.random() < 0.3:
        target = Path(out) / "results.sqlite"
        if rng.random() < 0.5:
            target.write_bytes(rng.bytes(int(rng.integers(0, 4096))))
        return ["report", str(target), "--no-png"]
    kinds = ["rendezvous", "allocation", "multitask"]
    argv = ["simulate", "--mission", _pick(rng, kinds, ["capacity", "bogus"])]
    argv += ["--robots", _pick(rng, ["1", "2", "3", "5"], ["0", "-4", "13", "x"])]
    if rng.random() < 0.4:
        argv += ["--goals", _pick(rng, ["2", "4", "20"], ["0", "65", "1"])]
    argv += ["--seed", _pick(rng, ["0", "5"], [str(2**80), "-1"])]
    argv += ["--reasoning", _pick(rng, LEVELS[:5], ["bogus"])]
    if rng.random() < 0.3:
        argv += ["--max-steps", _pick(rng, ["1", "50"], ["0", str(10**12), "nan"])]
    if rng.random() < 0.3:
        argv += ["--sensing-range", _pick(rng, ["5", "10"], ["0", "-1", "nan", "inf", "1e308"])]
    if rng.random() < 0.3:
        argv += ["--position-noise", _pick(rng, ["0.5", "0"], ["-1", "nan", "1e308"])]
    if rng.random() < 0.2:
        argv += ["--observation", _pick(rng, ["paper", "honest"], ["bogus"])]
    if rng.random() < 0.2:
        argv += ["--gif", str(rng.choice(["/missing/dir/x.gif", str(Path(out))]))]
    if rng.random() < 0.3:
        argv += ["--json"]
    return argv


def run_corpus(cases: int, seed: int, limit: float) -> dict:
    """Run ``cases`` fuzz cases drawn from ``seed``: four mission cases to one of parameters."""
    counts: dict[str, int] = {}
    bad = []
    slowest = (0.0, None)
    texts = {p: p.read_text(encoding="utf-8") for p in MISSIONS}
    with tempfile.TemporaryDirectory() as out:
        for k in range(cases):
            rng = np.random.default_rng([seed, k])
            for stale in Path(out).glob("*.sqlite*"):
                stale.unlink()  # each case starts without results files (--resume varies)
            if k % 5 == 4:
                source, argv = "parameters", parameter_command(rng, out)
            else:
                path = MISSIONS[(k - k // 5) % len(MISSIONS)]
                text = texts[path]
                target = Path(out) / "case.epi"
                mutated = rng.random() < 0.7
                target.write_bytes(_mutate_mission(text, rng) if mutated else text.encode())
                source, argv = path.name, mission_command(str(target), text, rng, out)
            code, seconds = run_case(argv, limit)
            counts[str(code)] = counts.get(str(code), 0) + 1
            if seconds > slowest[0]:
                slowest = (seconds, {"case": k, "source": source, "argv": argv})
            if code not in (0, 1, 2):
                bad.append({"case": k, "seed": seed, "source": source, "code": code,
                            "argv": argv})  # fmt: skip
    return {"cases": cases, "seed": seed, "missions": len(MISSIONS), "counts": counts,
            "bad": bad, "slowest_seconds": round(slowest[0], 3), "slowest": slowest[1]}  # fmt: skip


if __name__ == "__main__":
    sys.exit(main(run_corpus, __doc__, cases=120))
