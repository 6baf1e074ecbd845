"""The mission's event stream: the one contract between the runner and every reader.

The runner emits typed :class:`~.event.MissionEvent` records (tick statuses, reasons,
navigation goals, an app's own events, completion); they go out on a ROS topic
(:mod:`sar_framework.runner.event_topic`) and into ``events.jsonl`` in the report folder
(:mod:`.jsonl`). ``sar-tree run`` (progress, verdict, exit code), ``mission.json``, the
recording and replay read events, never log text; logs are for humans.

- :mod:`.event`: the kinds, the record, its JSON encoding (no ROS);
- :mod:`.jsonl`: the JSON-lines file, written and followed (no ROS);
- :mod:`.emitter`: the small API leaves and the runner emit through (no ROS).
"""
