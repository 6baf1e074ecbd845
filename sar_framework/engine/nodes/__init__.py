"""The node kinds: what a tree may hold besides plugins, declared and implemented.

- :mod:`.kind_model`: the shape of a kind (attrs, rules); :mod:`.node_kinds`: the table
  of kinds and top-level keys; :mod:`.control_kinds`: BT.CPP's nodes as kinds.
- :mod:`.controls`, :mod:`.decorators`: behaviours that tick as BT.CPP 4.7.3's do.
- :mod:`.script_nodes`: Script, ScriptCondition, Precondition and pre/post conditions.
- :mod:`.skipping`: the SKIPPED mark.
"""
