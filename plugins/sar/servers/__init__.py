"""The mission's service servers: ``/detect_survivor`` and ``/report_survivor``.

Each is a console script and a module (``python -m sar_plugins.sar.servers.<module>``):

- :mod:`.detect_survivor_server` answers from a survivor table (:mod:`.survivors`);
- :mod:`.report_survivor_server` validates reports and records each acknowledged one
  durably (:mod:`.report_log`) before it answers.

Both declare their parameters from one table each (:mod:`.params`, no ROS).
"""
