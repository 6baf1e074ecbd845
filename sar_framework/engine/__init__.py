"""The tree engine: a tree file in, a py_trees tree out. Never imports ROS.

The stages, in the order a file goes through them (docs/architecture.md draws it)::

    api.load_tree(path)
      -> checking.validate   reading/ (YAML with positions, includes) then the checks
      -> TreeSpec            spec.py: the validated tree, input of every later stage
      -> building.build      behaviours of nodes/ (node kinds) and of the plugins
      -> LoadedTree          the running tree; rendering/ draws a TreeSpec,
                             reloading/ swaps a new file into a running tree

What plugins use stays at this level: plugin.py (``@leaf``), param.py (``Param``),
ports.py (``InputPort``...), api.py (``load_tree``, ``TreeLoadError``); registry.py finds
them. scripting/ is BT.CPP's script language (checking and the scripted nodes use it).
"""
