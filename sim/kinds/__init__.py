"""Kinds of mission: what a mission asks of the team, one module per kind.

A kind says which configurations (or tasks) a mission ranges over, when it holds, which
levels play it, its parameters and how its trials are traced and drawn; the registry
:data:`~epistemica.sim.kinds.registry.KINDS` maps each kind's name to its object.
"""
