"""How robots decide: the policy interface, the baselines, the active-inference levels and
their parts, the collaborative levels, and the one level registry
(:mod:`~epistemica.sim.policies.levels`)."""
