"""The wait for a missing Nav2 server, shared by the action and service leaves."""

from __future__ import annotations

from sar_plugins.nav2._common import server_missing, wait_for_service_s


def test_the_wait_is_the_navigators_setting_in_seconds() -> None:
    assert wait_for_service_s(None) == 1.0  # Nav2's default: 1000 ms


def test_a_missing_server_fails_once_the_wait_is_over() -> None:
    assert server_missing(None, 10.0, 10.5, '"spin" action server') is None
    assert server_missing(None, 10.0, 11.0, '"spin" action server') is None
    assert server_missing(None, 10.0, 11.25, '"spin" action server') == (
        '"spin" action server not available after waiting for 1 s')
