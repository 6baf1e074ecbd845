"""Building: a :class:`~..spec.TreeSpec` -> plain py_trees behaviours, in one pass.

:mod:`.build` walks the spec once and makes each node: a plugin from the registry, a
BT.CPP kind through :mod:`.control_build`, a plugin's control or decorator through its
builder, a script node from its scripts, and
the pre/post-condition wrapper of any node that has them. Leaves get their ports as
:class:`~.port_values.PortValues`; ``timeout`` runs on the build context's clock.
"""
