"""Rendering: a :class:`~..spec.TreeSpec` drawn, never built.

:mod:`.render` writes dot/svg/png/pdf (graphviz), :mod:`.text_tree` ASCII or Unicode
text; both take node words and entry edges (writer -> reader) from :mod:`.labels`.
"""
