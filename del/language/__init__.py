"""The formula language: formula trees (``formula.py``: the base class, atoms and the Boolean
connectives; ``modalities.py``: the modal nodes), walks over them (``walk.py``), the grammar
``formula.lark`` and its parser (``parser.py``) with located syntax errors
(``_syntax_errors.py``).

Depends only on :mod:`epistemica.del_.errors`. The public names are exported by
:mod:`epistemica.del_`.
"""
