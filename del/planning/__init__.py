"""Epistemic planning over explicit models: search over states stored up to bisimulation,
plans and their validation, implicit coordination, and the configuration model of a
multi-robot mission.

The public names are exported by :mod:`epistemica.del_`.
"""
