"""Building: a :class:`~..spec.TreeSpec` -> plain py_trees behaviours, in one pass.

:mod:`.build` walks the spec once and makes each node: a plugin from the registry, a
BT.CPP or Nav2 kind through :mod:`.control_build`, a script node or pre/post-condition
wrapper through :mod:`.scripted_build`. Leaves get their ports as
:class:`~.port_values.PortValues`; :mod:`.clock_timeout` is ``timeout`` on the build
context's clock.
"""
