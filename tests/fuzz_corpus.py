"""A fuzz corpus for spec files and the parameters of check, show and plan.

Each case is a mutation of a shipped spec (specs/puzzles, specs/planning) and a command
line drawn for it; it is run in this process through ``epistemica.cli.main``, with a time
limit per case, and its exit status recorded. The contract: every status is 0, 1 or 2
(never 3, an internal error), within the time limit. Run as a script in a worker process
whose address space is limited (``--memory-gib``), so that memory is bounded too:

    python tests/fuzz_corpus.py --cases 200 --seed 1

prints one JSON object: the counts by status, the slowest case, and every bad case (the
mutation is reproducible from its seed). tests/test_fuzz.py runs a small corpus in CI;
benchmarks/fuzz_cli.py runs 10,000.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import resource
import signal
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SPECS = sorted(p for p in ROOT.glob("specs/**/*.epi") if p.parent.name in ("puzzles", "planning"))
# The generated puzzles are 0.1 to 1 MB: mutated as a prefix of this many characters.
MAX_TEXT = 20_000

# What a mutation inserts: the languages' words and symbols, and input that is not text.
PIECES = [
    "agents", "atoms", "observes", "law", "actual", "world", "relation", "knowledge",
    "partition", "designated", "action", "goal", "check", "public", "private", "sense",
    "assign", "by", "to", "when", "pre", "effect", "event", "full", "partial", "oblivious",
    "expect", "true", "false", "mission", "robot", "K[a]", "C[", "E[a, b]", "[!", "<!", "]",
    "[", "(", ")", "{", "}", ":", ",", "..", ":=", "->", "<->", "&", "|", "~", "#", '"',
    "m1..m999999999", "x[1..1000000]", "9" * 40, "p q", "\x00", "\ufeff", "\u00e9", "\t",
    "\n", " ", "→", "⊤", "at(r1, g1)", "a..z", "K", "EB[", "CB[a]",
]  # fmt: skip
BAD_BYTES = [b"\xff", b"\xc3", b"\x00" * 8, b"\xef\xbb\xbf"]


class CaseTimeout(BaseException):
    """A case ran past its time limit (not an Exception: the CLI's guard must not eat it)."""


def mutate(text: str, rng: np.random.Generator) -> bytes:
    """One to four random edits of ``text``, as bytes (some edits are not UTF-8)."""
    data = text[:MAX_TEXT]
    for _ in range(int(rng.integers(1, 5))):
        n = len(data)
        at = int(rng.integers(0, n + 1))
        span = int(rng.integers(1, 40))
        kind = int(rng.integers(0, 7))
        if kind == 0:  # delete a span
            data = data[:at] + data[at + span :]
        elif kind == 1:  # insert a piece of the languages
            data = data[:at] + str(rng.choice(PIECES)) + data[at:]
        elif kind == 2:  # duplicate a span
            data = data[:at] + data[at : at + span] * int(rng.integers(2, 4)) + data[at:]
        elif kind == 3:  # swap two lines
            lines = data.split("\n")
            i, j = rng.integers(0, len(lines), size=2)
            lines[i], lines[j] = lines[j], lines[i]
            data = "\n".join(lines)
        elif kind == 4:  # replace a character
            data = data[:at] + chr(int(rng.integers(32, 127))) + data[at + 1 :]
        elif kind == 5:  # truncate
            data = data[:at]
        else:  # repeat a line many times
            lines = data.split("\n")
            i = int(rng.integers(0, len(lines)))
            lines[i:i] = [lines[i]] * int(rng.integers(2, 200))
            data = "\n".join(lines)
    raw = data.encode("utf-8")
    if rng.random() < 0.05:
        at = int(rng.integers(0, len(raw) + 1))
        raw = raw[:at] + BAD_BYTES[int(rng.integers(len(BAD_BYTES)))] + raw[at:]
    return raw


def _names(text: str, keyword: str) -> list[str]:
    out = []
    for line in text.splitlines():
        words = line.split()
        if len(words) > 1 and words[0] == keyword:
            out.append(words[1].rstrip(":({"))
    return out


def _formula(text: str, rng: np.random.Generator) -> str:
    claims = [line.split(":", 1)[1] for line in text.splitlines() if line.startswith("check ")]
    claims = [c for c in claims if c.strip()] or ["p", "K[a] p"]
    f = str(rng.choice(claims)).strip()
    if rng.random() < 0.5:
        f = mutate(f, rng).decode("utf-8", errors="replace")
    return f


def command(path: str, text: str, rng: np.random.Generator, out_dir: str) -> list[str]:
    """A command line of check, show or plan for the spec at ``path``."""
    actions = _names(text, "action") or ["go"]
    which = str(rng.choice(["check", "check", "show", "plan"]))
    argv = [which, path]
    if which in ("check", "show") and rng.random() < 0.4:
        argv += ["--backend", str(rng.choice(["auto", "explicit", "symbolic", "bogus"]))]
    if which == "check" and rng.random() < 0.5:
        argv += ["--formula", _formula(text, rng)]
        if rng.random() < 0.5:
            argv += ["--where", "--limit", str(rng.choice(["1", "5", "0", "-3", "x", "10**12"]))]
    if which == "show":
        if rng.random() < 0.6:
            steps = list(rng.choice(actions, size=int(rng.integers(0, 4))))
            if rng.random() < 0.3:
                steps.append("nonexistent")
            argv += ["--after", ",".join(steps)]
        if rng.random() < 0.4:
            argv += ["--limit", str(rng.choice(["1", "3", "100", "0", "abc"]))]
        output = rng.random()
        if output < 0.3:
            argv += ["--json"]
        elif output < 0.5:
            argv += ["--dot", str(Path(out_dir) / "m.dot"), "--force"]  # written each time
    if which == "plan":
        argv += ["--max-depth", str(rng.choice(["0", "1", "2", "3", "-1", "x"]))]
        if rng.random() < 0.3:
            argv += ["--search", str(rng.choice(["bfs", "astar", "greedy", "dfs"]))]
        if rng.random() < 0.3:
            argv += ["--verify", ",".join(rng.choice(actions, size=int(rng.integers(1, 4))))]
        if rng.random() < 0.3:
            argv += ["--implicit"]
        if rng.random() < 0.2:
            argv += ["--explain"]
    if rng.random() < 0.3 and "--json" not in argv and "--dot" not in argv:
        argv += ["--json"]
    if rng.random() < 0.1:
        argv += ["--memory-budget", str(rng.choice(["0.001", "1", "nan", "-1"]))]
    return argv


def run_case(argv: list[str], limit: float) -> tuple[int, float]:
    """Exit status and seconds of ``epistemica argv`` in this process."""
    from epistemica.cli import main

    def expire(signum, frame):
        raise CaseTimeout

    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, limit)
    start = time.perf_counter()
    sink = io.StringIO()
    try:
        with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
            try:
                code = main(argv)
            except SystemExit as exc:  # argparse's usage errors
                code = exc.code if isinstance(exc.code, int) else 2
    except CaseTimeout:
        code = -1
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    return code, time.perf_counter() - start


def run_corpus(cases: int, seed: int, limit: float) -> dict:
    """Run ``cases`` fuzz cases drawn from ``seed``; every spec in turn."""
    counts: dict[str, int] = {}
    bad = []
    slowest = (0.0, None)
    texts = {p: p.read_text(encoding="utf-8") for p in SPECS}
    with tempfile.TemporaryDirectory() as out_dir:
        for k in range(cases):
            rng = np.random.default_rng([seed, k])
            path = SPECS[k % len(SPECS)]
            text = texts[path][:MAX_TEXT]
            target = Path(out_dir) / f"case{k % 7}.epi"
            target.write_bytes(mutate(text, rng) if rng.random() < 0.85 else text.encode())
            argv = command(str(target), text, rng, out_dir)
            code, seconds = run_case(argv, limit)
            counts[str(code)] = counts.get(str(code), 0) + 1
            if seconds > slowest[0]:
                slowest = (seconds, {"case": k, "spec": path.name, "argv": argv[0:1] + argv[2:]})
            if code not in (0, 1, 2):
                bad.append({"case": k, "seed": seed, "spec": path.name, "code": code,
                            "argv": argv[0:1] + argv[2:]})  # fmt: skip
    return {"cases": cases, "seed": seed, "counts": counts, "bad": bad,
            "slowest_seconds": round(slowest[0], 3), "slowest": slowest[1]}  # fmt: skip


def main(corpus=run_corpus, description: str = __doc__, cases: int = 200) -> None:
    """Run ``corpus(cases, seed, limit)`` under the address-space limit; print its JSON."""
    parser = argparse.ArgumentParser(description=description.splitlines()[0])
    parser.add_argument("--cases", type=int, default=cases)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--limit", type=float, default=20.0, help="seconds per case")
    parser.add_argument("--memory-gib", type=float, default=4.0, help="address space limit")
    args = parser.parse_args()
    gib = int(args.memory_gib * 2**30)
    resource.setrlimit(resource.RLIMIT_AS, (gib, gib))
    result = corpus(args.cases, args.seed, args.limit)
    result["max_rss_mib"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss // 1024
    print(json.dumps(result))


if __name__ == "__main__":
    sys.exit(main())
