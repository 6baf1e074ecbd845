"""Building: a :class:`~..spec.TreeSpec` -> plain py_trees behaviours, in one pass.

:mod:`.build` walks the spec once and makes each node: a leaf plugin from the registry, a
node of a declared kind (py_trees', BT.CPP's, the script nodes, a plugin's control or
decorator) with the builder its declaration names (:mod:`.kind_builders`; the builders
that convert attributes are :mod:`.py_trees_build`'s and :mod:`.control_build`'s), and
the pre/post-condition wrapper of any node that has them. Leaves get their ports as
:class:`~.port_values.PortValues`; ``timeout`` runs on the build context's clock.
"""
