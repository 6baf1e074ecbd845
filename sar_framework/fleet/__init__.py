"""A fleet's shared parts (issue 23): what one robot cannot decide alone.

``survivor_registry`` (fleet-wide survivor ids, who reports each) and ``survivor_service``
(the registry as the ``/zone_coordinator/register_survivor`` service). See docs/fleet.md.
"""
