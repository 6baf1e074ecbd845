"""A fleet's verdict: each robot's, then the fleet's, from events and reports (no ROS).

Each robot's verdict is the one a single robot gets (:mod:`.outcome`: its runner's events
and exit code). The fleet succeeds when every robot succeeded, every robot is home (its
``mission.json`` says ``at_base``: within reach of its own base, its spawn place) and every
zone was searched: exactly once when the zone coordinator shared the zones out (its
``searched`` events, read from its JSON Lines ``events_file``), at least once when each
robot walked every zone itself (the robots' ``zone_reached`` events, in ``mission.json``).
Never from log text.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from sar_framework.orchestrate.outcome import (
    EXIT_FAILURE,
    EXIT_INTERRUPTED,
    EXIT_OK,
    EXIT_USAGE,
    Outcome,
)


def zone_searchers(zone_ids: Sequence[str], summaries: Mapping[str, dict[str, Any]],
                   coordinator_events: Sequence[dict[str, Any]] | None
                   ) -> dict[str, list[str]]:
    """Zone id -> the robots that searched it, in order.

    Args:
        zone_ids: The mission's zones.
        summaries: Robot name -> its ``mission.json``.
        coordinator_events: The coordinator's events, or None when it did not run (then a
            zone is searched by every robot that reached it).
    """
    searched: dict[str, list[str]] = {zone: [] for zone in zone_ids}
    if coordinator_events is not None:
        for event in coordinator_events:
            if event.get("kind") == "searched":
                searched.setdefault(str(event.get("zone_id", "")), []).append(
                    str(event.get("robot", "")))
        return searched
    for name, summary in summaries.items():
        for zone in dict.fromkeys(z["id"] for z in summary.get("zones_visited", [])):
            searched.setdefault(zone, []).append(name)
    return searched


def fleet_outcome(robots: Mapping[str, Outcome], summaries: Mapping[str, dict[str, Any]],
                  searched: Mapping[str, list[str]], *, once: bool) -> Outcome:
    """The fleet's verdict.

    Args:
        robots: Robot name -> its verdict.
        summaries: Robot name -> its ``mission.json`` (``at_base``, ``final_position``).
        searched: :func:`zone_searchers`.
        once: Each zone must be searched exactly once (the coordinator shared them out).

    Returns:
        SUCCESS (exit 0) when every check holds; INTERRUPTED (130) when any robot was;
        ERROR with exit 2 when a robot's runner rejected its input; else FAILURE (1) with
        every problem in the reason.
    """
    if any(o.status == "INTERRUPTED" for o in robots.values()):
        return Outcome("INTERRUPTED", EXIT_INTERRUPTED, "interrupted (Ctrl-C)")
    problems = [f"{name}: {o.status}" + (f" ({o.reason})" if o.reason else "")
                for name, o in robots.items() if o.status != "SUCCESS"]
    for zone, by in searched.items():
        if not by:
            problems.append(f"{zone} was never searched")
        elif once and len(by) > 1:
            problems.append(f"{zone} was searched {len(by)} times ({', '.join(by)})")
    for name, summary in summaries.items():
        if robots.get(name, Outcome("SUCCESS", EXIT_OK)).status == "SUCCESS" \
                and summary.get("at_base") is not True:
            final = summary.get("final_position")
            where = f" (ends at ({final['x']:.2f}, {final['y']:.2f}))" if final else ""
            problems.append(f"{name} is not home{where}")
    if not problems:
        return Outcome("SUCCESS", EXIT_OK)
    usage = any(o.exit_code == EXIT_USAGE for o in robots.values())
    return Outcome("ERROR" if usage else "FAILURE", EXIT_USAGE if usage else EXIT_FAILURE,
                   "; ".join(problems))


def fleet_document(outcome: Outcome, robots: Mapping[str, Outcome],
                   summaries: Mapping[str, dict[str, Any]], searched: Mapping[str, list[str]],
                   *, coordinator: bool, wall_duration_s: float) -> dict[str, Any]:
    """``fleet.json``: the fleet's verdict, each robot's, and who searched which zone."""
    sims = [s.get("sim_duration_s") for s in summaries.values()]
    return {
        "outcome": outcome.status,
        "reason": outcome.reason,
        "coordinator": coordinator,
        "sim_duration_s": max((t for t in sims if isinstance(t, (int, float))), default=None),
        "wall_duration_s": round(wall_duration_s, 3),
        "zones": {zone: {"searched_by": list(by)} for zone, by in searched.items()},
        "robots": {name: {
            "outcome": o.status, "reason": o.reason,
            "zones_visited": [z["id"] for z in summaries.get(name, {}).get("zones_visited", [])],
            "at_base": summaries.get(name, {}).get("at_base"),
            "final_position": summaries.get(name, {}).get("final_position"),
            "sim_duration_s": summaries.get(name, {}).get("sim_duration_s"),
            "path_length_m": summaries.get(name, {}).get("path_length_m"),
            "report": f"{name}/mission.json"} for name, o in robots.items()},
    }
