"""A fuzz corpus for the foreign formats and the viewer's inputs (issue 38).

Each case is one of: a mutated SMCDEL file (from ``export --smcdel`` of shipped specs and
a hand-written one; some grown by a job at an item limit: a chain of thousands of ``|``,
thousands of nested ``~``, a quantifier over every variable, a long ``ONEOF``), a mutated
EPDDL task (the test tasks in tests/data/epddl), or a
hostile trace for ``view`` (JSON with non-finite numbers, markup in strings, deep nesting;
truncated or inflating zlib blobs). Run through ``epistemica.cli.main`` in this process,
with a time limit per case, in a worker whose address space is bounded, like
tests/fuzz_corpus.py; the contract is the same: every status 0, 1 or 2.

    python tests/fuzz_formats.py --cases 150 --seed 1
"""

from __future__ import annotations

import json
import sys
import tempfile
import zlib
from pathlib import Path

import numpy as np
from fuzz_corpus import main, mutate, run_case  # a script beside this one

ROOT = Path(__file__).resolve().parents[1]
EPDDL = ROOT / "tests" / "data" / "epddl"
TASKS = [
    ("peek.epddl", "peek-1.epddl"),
    ("peek.epddl", "peek-2.epddl"),
    ("rooms.epddl", "rooms-1.epddl"),
]
SMCDEL_SEEDS = ["muddy_children", "muddy_children_4", "sum_and_product"]
HAND = """-- three children
VARS 1,2,3
LAW  Top
OBS  alice: 2,3
     bob:   1,3
     carol: 1,2
TRUE? {1,2} bob knows that 1 & ~ bob knows whether 2
VALID? [ ! (1|2|3) ] (alice, bob) comknow that (1|2|3)
VALID? Forall 1 (1 | ~1)
VALID? [ alice ! [ bob ! 2 ] 1 ] (1 -> alice knows that 1)
WHERE? < ! (1|2|3) > OR (alice knows whether 1, XOR (2, 3), ONEOF (1, 2, 3))
"""


def _smcdel_texts() -> list[str]:
    from epistemica.del_.formats.smcdel_export import to_smcdel
    from epistemica.del_.spec import load_spec

    texts = [HAND]
    for name in SMCDEL_SEEDS:
        texts.append(to_smcdel(load_spec(ROOT / "specs" / "puzzles" / f"{name}.epi")))
    return texts


def _grown(text: str, rng: np.random.Generator) -> str:
    """``text`` with one job appended that is deep, long or expands at an item limit."""
    n = int(rng.integers(1_000, 6_000))
    variables = text.split("VARS", 1)[1].split("LAW", 1)[0].split()
    jobs = [
        "VALID? " + "1|" * n + "1",
        "VALID? " + "~" * n + "(1 | ~1)",
        "VALID? Forall " + "".join(variables) + " (1 | ~1)",
        "VALID? ~ONEOF(" + ",".join(["1"] * (n // 4)) + ")",
    ]
    return text + jobs[int(rng.integers(len(jobs)))] + "\n"


def _trace(rng: np.random.Generator) -> bytes:
    """A trace-like JSON document or blob that no sweep wrote."""
    kind = int(rng.integers(0, 6))
    strange = [float("nan"), float("inf"), -float("inf"), 1e308, -0.0, "NaNo", "<!--<script>",
               "</script><b>", "\u2028", None, [], {}]  # fmt: skip
    doc = {"format": "epistemica-trace", "version": int(rng.choice([1, 2, 99])),
           "robots": [str(rng.choice(["r1", "NaNo", "<!--<script>"]))],
           "steps": int(rng.integers(-2, 4)),
           "poses": [[strange[int(rng.integers(len(strange)))] for _ in range(3)]]}  # fmt: skip
    text = json.dumps(doc, allow_nan=True)
    if kind == 0:
        return text.encode()
    if kind == 1:
        return mutate(text, rng)
    if kind == 2:
        return zlib.compress(text.encode())
    if kind == 3:  # truncated stream
        blob = zlib.compress(text.encode())
        return blob[: int(rng.integers(1, len(blob)))]
    if kind == 4:  # inflates far beyond the limit: 128 MiB of spaces in a small blob
        deflater = zlib.compressobj(9)
        chunk = b" " * (1 << 24)
        return b"".join([*(deflater.compress(chunk) for _ in range(8)), deflater.flush()])
    return ("[" * 50_000 + "]" * 50_000).encode()


def run_corpus(cases: int, seed: int, limit: float) -> dict:
    """Run ``cases`` cases drawn from ``seed``: SMCDEL, EPDDL and trace cases in turn."""
    counts: dict[str, int] = {}
    bad = []
    slowest = (0.0, None)
    smcdel = _smcdel_texts()
    epddl = {p.name: p.read_text(encoding="utf-8") for p in EPDDL.glob("*.epddl")}
    with tempfile.TemporaryDirectory() as out:
        for k in range(cases):
            rng = np.random.default_rng([seed, k])
            kind = ("smcdel", "epddl", "trace")[k % 3]
            if kind == "smcdel":
                target = Path(out) / "case.smcdel"
                text = smcdel[(k // 3) % len(smcdel)]
                if rng.random() < 0.2:
                    text = _grown(text, rng)
                target.write_bytes(mutate(text, rng) if rng.random() < 0.85 else text.encode())
                argv = ["check", str(target)]
                if rng.random() < 0.3:
                    argv += ["--backend", str(rng.choice(["explicit", "symbolic"]))]
            elif kind == "epddl":
                domain, problem = TASKS[(k // 3) % len(TASKS)]
                paths = []
                for name in (domain, problem, "library.epddl"):
                    path = Path(out) / name
                    text = epddl[name]
                    edit = rng.random() < 0.5
                    path.write_bytes(mutate(text, rng) if edit else text.encode())
                    paths.append(str(path))
                argv = ["plan", paths[0], paths[1], "-l", paths[2], "--max-depth", "3"]
            else:
                target = Path(out) / "trace.json"
                target.write_bytes(_trace(rng))
                argv = ["view", str(target), "-o", str(Path(out) / "page.html"), "--force"]
            code, seconds = run_case(argv, limit)
            counts[str(code)] = counts.get(str(code), 0) + 1
            if seconds > slowest[0]:
                slowest = (seconds, {"case": k, "kind": kind, "argv": argv[:1]})
            if code not in (0, 1, 2):
                bad.append({"case": k, "seed": seed, "kind": kind, "code": code})
    return {"cases": cases, "seed": seed, "counts": counts, "bad": bad,
            "slowest_seconds": round(slowest[0], 3), "slowest": slowest[1]}  # fmt: skip


if __name__ == "__main__":
    sys.exit(main(run_corpus, __doc__, cases=150))
