"""Turn on ROS 2 service introspection for a node's own services (rclpy Jazzy and later).

With it, each request and answer is also published on ``/<service>/_service_event``
(``pkg/srv/Name_Event``, full contents), which ``ros2 bag record`` and the mission
recorder store. The services every node has (parameters, type description) are left alone.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

#: Packages of the services rclpy gives every node.
INFRASTRUCTURE_PACKAGES = frozenset({"rcl_interfaces", "type_description_interfaces"})

if TYPE_CHECKING:
    from rclpy.node import Node


def enable_service_introspection(node: Node) -> list[str]:
    """Publish the request and answer contents of the services of ``node``.

    Args:
        node: A node whose services are created.

    Returns:
        The services now introspected (none on an rclpy without introspection).
    """
    try:
        from rclpy.qos import qos_profile_system_default
        from rclpy.service_introspection import ServiceIntrospectionState
    except ImportError:
        return []
    names = []
    for service in node.services:
        if service.srv_type.__module__.split(".")[0] in INFRASTRUCTURE_PACKAGES:
            continue
        service.configure_introspection(node.get_clock(), qos_profile_system_default,
                                        ServiceIntrospectionState.CONTENTS)
        names.append(service.srv_name)
    return names
