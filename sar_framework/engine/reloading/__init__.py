"""Reloading: a running tree takes a new file between two ticks (docs/how-to/hot-reload.md).

:mod:`.tree_diff` compares two specs node by node (keep, rewire, build); :mod:`.hot_swap`
validates and builds what changed, then swaps it in.
"""
