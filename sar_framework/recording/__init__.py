"""Mission recordings: a rosbag2-compatible MCAP file of a run, and its replay.

- :mod:`.recorder`: the recorder process (``python -m sar_framework.recording``);
- :mod:`.bag_writer`, :mod:`.msgdefs`: the MCAP file and its schemas;
- :mod:`.sources`: the run's tree files and local plugin sources, kept in the recording;
- :mod:`.readback`, :mod:`.replay`: reading a recording back, ``sar-tree replay``.

The tree's status per tick (``/sar_tree/status``) and the event topic are the runner's
outputs: :mod:`sar_framework.runner.tree_status`, :mod:`sar_framework.runner.event_topic`;
the servers' service events are turned on by :mod:`sar_framework.ros.introspection`.
"""
