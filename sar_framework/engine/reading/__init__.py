"""Reading: a tree file and its includes become documents whose values keep line:col.

- :mod:`.yaml_source`: safe YAML composed into nodes with positions; YAML problems.
- :mod:`.document`: those nodes as plain values, each path's YAML node kept.
- :mod:`.tree_files`: the main file and, transitively, its includes; include cycles.
"""
