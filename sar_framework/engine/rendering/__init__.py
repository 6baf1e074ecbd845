"""Rendering: a :class:`~..spec.TreeSpec` drawn, never built.

:mod:`.render` writes dot/svg/png/pdf with graphviz, :mod:`.text_tree` ASCII or
Unicode text; both word nodes, and the entry edges (writer -> reader), through
:mod:`.labels`.
"""
