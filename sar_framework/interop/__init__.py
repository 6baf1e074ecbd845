"""BehaviorTree.CPP v4 / Groot2 interop: export a tree file as BT.CPP XML, import it back.

* :func:`~sar_framework.interop.btcpp_export.export_btcpp` turns a validated
  :class:`~sar_framework.engine.spec.TreeSpec` into BT.CPP 4 XML with a
  ``<TreeNodesModel>`` (every leaf's ports), which Groot2 opens and edits;
* :func:`~sar_framework.interop.btcpp_import.import_btcpp` turns BT.CPP 4 XML into
  our YAML tree format, or a list of ``file:line:col`` problems.

The mapping between the two formats is one table, :mod:`.mapping`, documented in
``docs/reference/btcpp-interop.md``. Nothing here imports ROS.
"""
