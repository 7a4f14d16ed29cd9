"""Hand-worked examples of belief revision in plausibility models. Every expected value is
derived by hand in the comments, from the orders written out; both backends must agree."""

from __future__ import annotations

import numpy as np
import pytest

from epistemica.del_.explicit.plausibility import PlausibilityModel
from epistemica.del_.symbolic.plausibility import PlausibilityStructure

# -- Mary and John (the "cheating" scenario in the style of Baltag and Smets) -----------
# c: John cheats on Mary; s: John stayed late at the office. Mary observes neither; John
# observes both. Mary's plausibility order, most plausible first (one world per level):
#   w0 = ~c~s  <  w1 = ~c s  <  w2 = c s  <  w3 = c~s
# The actual world is w2 (he cheats, and stayed late to do so).
MARY = {"m": ["~c & ~s", "~c & s", "c & s", "c & ~s"], "j": []}
OBSERVES = {"m": [], "j": ["c", "s"]}


def backends(levels=MARY, observes=OBSERVES, actual=("c", "s"), atoms=("c", "s")):
    m = PlausibilityModel.from_levels(atoms, levels, observes, designated=actual)
    return m, PlausibilityStructure.from_explicit(m)


@pytest.mark.parametrize(
    "text, expected",
    [
        # Plain belief: the best world is w0 = ~c~s, so she believes ~c and ~s ...
        ("B[m] ~c & B[m] ~s", True),
        # ... and that is false at w2: belief is not knowledge.
        ("K[m] ~c", False),
        ("~c", False),
        # Conditional on s, the best s-world is w1 = ~c s: she would keep believing ~c.
        ("B[m | s] ~c", True),
        # Conditional on c, the best c-world is w2 = c s: she would then believe s.
        ("B[m | c] s", True),
        # ... and conditional on c & ~s (only w3) she believes ~s, trivially.
        ("B[m | c & ~s] ~s", True),
        # Safe belief at w2 (level 2): the worlds at least as plausible are w0, w1, w2.
        # c -> s holds at all three: safe. ~c fails at w2 itself: not safe (nor true).
        ("Sb[m] (c -> s)", True),
        ("Sb[m] ~c", False),
        # c -> s is believed (w0 satisfies it) and safely so, but not known (w3).
        ("K[m] (c -> s)", False),
        # John knows everything; his order is trivial, so he believes what he knows.
        ("K[j] c & B[j] c & Sb[j] (c & s)", True),
        # Mary believes John knows whether he cheats (he does in every world).
        ("B[m] Kw[j] c", True),
        # Mary believes that John believes ~c: at w0, John's cell is {w0}, where ~c holds.
        ("B[m] B[j] ~c", True),
    ],
)
def test_mary_and_john_static(text, expected):
    for backend in backends():
        assert backend.holds(text) is expected, text


@pytest.mark.parametrize(
    "text, expected",
    [
        # Radical upgrade with s (a colleague mentions he stayed late; soft information):
        # the s-worlds first, in their old order, then the ~s-worlds:
        #   w1 = ~c s  <  w2 = c s  <  w0 = ~c~s  <  w3 = c~s
        # so she now believes s, and still ~c (best is w1).
        ("[^^s] (B[m] s & B[m] ~c)", True),
        # Her conditional belief on ~s is untouched inside the ~s zone: best ~s is w0.
        ("[^^s] B[m | ~s] ~c", True),
        # A further radical upgrade with c: c-worlds first in the order just made,
        #   w2 = c s  <  w3 = c~s  <  w1 = ~c s  <  w0 = ~c~s
        # so she believes c & s, and her belief is now true and safe at w2 (level 0).
        ("[^^s] [^^c] (B[m] (c & s) & Sb[m] (c & s))", True),
        # Radical vs conservative upgrade with c from the original order.
        # Radical ^^c:  w2 < w3 < w0 < w1.  Conditional on ~(c & s), the best is w3: c.
        ("[^^c] B[m | ~(c & s)] c", True),
        # Conservative ^c: only the best c-world (w2) moves to the top,
        #   w2 = c s  <  w0 = ~c~s  <  w1 = ~c s  <  w3 = c~s
        # so conditional on ~(c & s) the best is w0: ~c. The two upgrades differ here.
        ("[^c] B[m | ~(c & s)] c", False),
        ("[^c] B[m | ~(c & s)] ~c", True),
        ("[^c] B[m] (c & s)", True),
        # A hard announcement of s removes w0 and w3: w1 < w2; she believes ~c still but
        # now knows s.
        ("[!s] (K[m] s & B[m] ~c & ~K[m] ~c)", True),
        # Upgrades are soft: no knowledge is gained.
        ("[^^s] K[m] s", False),
        ("[^^c] ~K[m] c", True),
    ],
)
def test_mary_and_john_revision(text, expected):
    for backend in backends():
        assert backend.holds(text) is expected, text


def test_mary_and_john_ranks_after_upgrades_by_hand():
    m, _ = backends()
    order = ["~c & ~s", "~c & s", "c & s", "c & ~s"]
    world = {f: int(np.flatnonzero(m.truth(f))[0]) for f in order}

    def levels(model):
        return [int(model.ranks["m"][world[f]]) for f in order]

    assert levels(m) == [0, 1, 2, 3]
    # ^^s:  w1 < w2 < w0 < w3  (ranks of w0, w1, w2, w3)
    assert levels(m.radical_upgrade(m.truth("s"))) == [2, 0, 1, 3]
    # ^c:   w2 < w0 < w1 < w3
    assert levels(m.conservative_upgrade(m.truth("c"))) == [1, 2, 0, 3]
    # ^^c:  w2 < w3 < w0 < w1
    assert levels(m.radical_upgrade(m.truth("c"))) == [2, 3, 0, 1]


# -- Two agents and a coin: a false belief about another agent's knowledge --------------
# h: the coin shows heads. Bob has looked (observes h); Alice has not and finds tails more
# plausible (levels ~h, then h). Actual world: heads.
COIN = {"alice": ["~h", "h"], "bob": []}


@pytest.mark.parametrize(
    "text, expected",
    [
        ("B[alice] ~h & K[bob] h", True),
        # Alice believes Bob knows tails: at the ~h world Bob's cell is {~h}.
        ("B[alice] K[bob] ~h", True),
        # Alice's belief is false, so not safe: at h (level 1) both worlds count.
        ("Sb[alice] ~h", False),
        # Bob knows Alice's belief is false (in his cell {h}, Alice believes ~h).
        ("K[bob] (B[alice] ~h & h)", True),
        # After a radical upgrade with h, Alice believes h and believes Bob knows it,
        # but knows neither.
        ("[^^h] (B[alice] h & B[alice] K[bob] h & ~K[alice] h)", True),
        # Conservative and radical upgrades agree when the condition is a single world
        # per cell: both make h the top.
        ("[^h] B[alice] h <-> [^^h] B[alice] h", True),
        # Upgrading with ~h (a false hint) keeps her belief ~h; revising back with h
        # restores h: the most recent radical upgrade wins.
        ("[^^~h] [^^h] B[alice] h", True),
        ("[^^h] [^^~h] B[alice] ~h", True),
    ],
)
def test_coin(text, expected):
    for backend in backends(COIN, {"alice": [], "bob": ["h"]}, ("h",), ("h",)):
        assert backend.holds(text) is expected, text


def test_symbolic_scales_past_enumeration():
    # 60 coins (2^60 worlds); Alice finds "all tails" most plausible (level 0) and every
    # other world equally less plausible (level 1). The actual world: only h1 heads.
    # A conservative upgrade with h1: every h1-world is at level 1, so all tie as the best
    # h1-worlds and all move to the top: she believes h1 and has no opinion about h2.
    # A radical upgrade with h1 & ~h2 puts exactly those worlds first.
    atoms = [f"h{i}" for i in range(1, 61)]
    tails = " & ".join(f"~{a}" for a in atoms)
    s = PlausibilityStructure.from_levels(atoms, {"alice": [tails]}, designated=atoms[:1])
    assert s.holds("B[alice] ~h2 & B[alice] ~h60 & ~K[alice] ~h1")
    assert s.holds("[^h1] (B[alice] h1 & ~B[alice] ~h2 & ~B[alice] h2)")
    assert s.holds("[^^h1 & ~h2] B[alice] (h1 & ~h2)")
    # Safe belief at the actual world (level 1, every world): only validities are safe.
    assert not s.holds("Sb[alice] ~h2")
    assert s.holds("Sb[alice] (h2 | ~h2)")
