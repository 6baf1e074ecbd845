"""The search-and-rescue app's event kinds: its own names, its fields in ``fields``.

The events travel as any app's do (a ``MissionEvent`` with the kind's name and the fields
``zone_id`` and ``survivor_id`` as key/value pairs), so the message knows none of them.
"""

from __future__ import annotations

import enum


class SarKind(str, enum.Enum):
    """What a search-and-rescue event says happened (emit it like a core kind)."""

    ZONE_REACHED = "zone_reached"
    """The robot reached ``zone_id`` (position: the zone)."""
    ZONE_UNREACHED = "zone_unreached"
    """The mission moved past ``zone_id`` without reaching it."""
    BASE_REACHED = "base_reached"
    """The robot reached the base station (position: the base)."""
    DETECTION = "detection"
    """A detection answered for ``zone_id`` (status ``FOUND``/``NONE``; position: the find)."""
    SURVIVOR_BROADCAST = "survivor_broadcast"
    """``survivor_id``'s frame was broadcast at position."""
    SURVIVOR_REPORTED = "survivor_reported"
    """The base acknowledged ``survivor_id``."""
    SURVIVOR_REFUSED = "survivor_refused"
    """The base refused ``survivor_id`` (message: the base's reason)."""


SAR_KINDS = frozenset(SarKind)
"""The app's event kinds."""
