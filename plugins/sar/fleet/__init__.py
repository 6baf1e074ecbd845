"""A fleet of robots on one mission: what one robot cannot decide alone.

``auction`` (the zone ledger and its sequential single-item auction), ``coordinator_node``
(the ``zone_coordinator`` node), ``survivor_registry`` (fleet-wide survivor ids, who
reports each) and ``survivor_service`` (the registry as the
``/zone_coordinator/register_survivor`` service). See docs/how-to/fleet.md.
"""
