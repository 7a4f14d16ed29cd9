"""The epistemic state of a group of agents over a fixed space of worlds, updated by the
events each agent observed: what the simulator's robots know and believe, and what each
thinks the others know and believe.

- :mod:`~.observation`: :class:`Observation`, one event, what it teaches and who saw it;
- :mod:`~.state`: :class:`EpistemicState`, the record, answered per group of agents (the
  group semantics);
- :mod:`~.explicit`: worlds as a table, sets as boolean masks, the group Kripke model;
- :mod:`~.symbolic`: worlds as a BDD law, sets as BDDs, the group knowledge structure.
"""

from epistemica.del_.state.observation import Observation
from epistemica.del_.state.state import EpistemicState, History

__all__ = ["EpistemicState", "History", "Observation"]
