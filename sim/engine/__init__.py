"""The simulator's engine: the world of a trial and the one loop that steps it.

- :mod:`~epistemica.sim.engine.scenario`: :class:`Scenario`, the world and its rules;
  :mod:`~epistemica.sim.engine.draws` and ``_streams``: the seeded draws of a trial;
- :mod:`~epistemica.sim.engine.dynamics`, :mod:`~epistemica.sim.engine.obstacles`: motion
  and contacts; :mod:`~epistemica.sim.engine.sensing`: what each robot perceives;
- :mod:`~epistemica.sim.engine.events`: observation events; :mod:`~epistemica.sim.engine.knowledge`:
  the team's epistemic state (``epistemica.del_``) by robot and goal index;
  :mod:`~epistemica.sim.engine.worlds`: configurations as worlds of the logic;
- :mod:`~epistemica.sim.engine.missions`: when a goal mission holds;
- :mod:`~epistemica.sim.engine.simulate`: :func:`simulate` and :class:`TrialRun`, the one loop;
  :mod:`~epistemica.sim.engine.trial`: :class:`Trial`, its record;
- :mod:`~epistemica.sim.engine.env`: the same loop as PettingZoo / Gymnasium environments.
"""
