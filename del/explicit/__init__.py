"""The explicit backend: Kripke models as arrays, their one evaluator, action models and
product update, bisimulation, canonical forms, description and export.

The public names are exported by :mod:`epistemica.del_`; see docs/architecture.md for the
model interface the algorithms here are written against.
"""
