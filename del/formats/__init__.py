"""Foreign formats of the DEL engine: EPDDL (domains, problems, action-type libraries; the
input language of the plank toolkit and of the International Epistemic Planning
Competition) and SMCDEL's text format, read into and written from the objects a ``.epi``
spec compiles into.
"""
