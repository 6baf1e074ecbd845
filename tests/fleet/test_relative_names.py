"""Every leaf finds its servers relative to the runner's namespace.

A runner started with ``--ros-args -r __ns:=/robot1`` must reach ``/robot1/navigate_to_pose``
and the robot's other servers, as a namespaced Nav2 stack's nodes do. So no built-in leaf
(our mission leaves and ``plugins/nav2``) may default to an absolute server, topic or action
name, nor hard-code one (``SERVER``). The exceptions serve the whole fleet
(docs/how-to/fleet.md): the base station's report service and the zone coordinator's survivor
registry.
"""

from __future__ import annotations

from sar_framework.engine.ports import NO_DEFAULT
from sar_framework.engine.registry import discover

FLEET_WIDE = {("NotifyBase", "service_name"), ("RegisterSurvivor", "service_name"),
              ("ClaimZone", "server_name"), ("CompleteZone", "server_name"),
              ("ReleaseZone", "server_name")}
"""(leaf, param): names that stay absolute, one server for every robot."""

_NAME_KEYS = ("server_name", "service_name", "action_name", "topic_name", "service",
              "action", "topic")


def _names() -> list[tuple[str, str, str]]:
    registry = discover(["sar_plugins.sar.leaves"], entry_points=False)
    found: list[tuple[str, str, str]] = []
    for name in registry.names():
        spec = registry.get(name)
        assert spec is not None
        for param in spec.params:
            if param.name in _NAME_KEYS and isinstance(param.default, str):
                found.append((name, param.name, param.default))
        for port in spec.ports:
            if port.name in _NAME_KEYS and port.default is not NO_DEFAULT \
                    and isinstance(port.default, str):
                found.append((name, port.name, port.default))
        server = getattr(spec.cls, "SERVER", None)
        if isinstance(server, str):
            found.append((name, "SERVER", server))
    return found


def test_the_audit_sees_the_leaves_that_name_servers() -> None:
    leaves = {leaf for leaf, _, _ in _names()}
    assert {"NavigateToPose", "ComputePathToPose", "Spin", "DetectSurvivor",
            "NotifyBase"} <= leaves


def test_no_leaf_names_a_server_absolutely() -> None:
    absolute = [(leaf, key, value) for leaf, key, value in _names()
                if value.startswith("/") and (leaf, key) not in FLEET_WIDE]
    assert absolute == []
