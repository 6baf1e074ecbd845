"""Checking: documents -> a :class:`~..spec.TreeSpec`, or every problem at file:line:col.

:mod:`.validate` runs the checks in order:

1. :mod:`.structure`: the plain values against the JSON Schema of :mod:`.schema`
   (node kinds + registered plugins), each error worded at its node.
2. :mod:`.semantics`: the walk that makes the specs. It reads what a kind or plugin
   declares (:mod:`.declarations`), copies subtrees (:mod:`.subtree_defs`), points
   references at leaves (:mod:`.references`), resolves leaf and subtree ports
   (:mod:`.bindings`) and scripts' variables (:mod:`.script_bindings`) per scope.
3. :mod:`.entries`: the one check of an entry, whoever reads it (a leaf's or a control's
   port, a script): scopes, keys, readers without a writer, types, did-you-mean.
"""
