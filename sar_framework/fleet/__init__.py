"""A fleet of robots on one mission (issue 23): the zone coordinator and its rules."""
