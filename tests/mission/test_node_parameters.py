"""A node's parameter table declared on a real rclpy node: descriptors, ranges, one rule."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

from sar_framework.engine.param import Param
from sar_framework.mission.params_file import ParamsError, check_params_file

pytestmark = pytest.mark.ros

TABLE = (
    Param("rate", float, 2.0, "ticks per second", exclusive_minimum=0.0, maximum=10.0,
          unit="Hz"),
    Param("mode", str, "auto", "how", enum=("auto", "once")),
    Param("count", int, 3, "how many", minimum=1),
    Param("ids", list[str], None, "which"),
    Param("path", str | list[str], "", "where"),
    Param("zones.*.x", float, None, "left to the node"),
    Param("use_sim_time", bool, False, "ROS's own"),
)


@contextmanager
def node(*overrides: str, params_file: Path | None = None,
         auto_declare: bool = False) -> Iterator[object]:
    import rclpy
    from rclpy.context import Context
    from rclpy.node import Node

    args = ["test", "--ros-args"]
    if params_file is not None:
        args += ["--params-file", str(params_file)]
    for override in overrides:
        args += ["-p", override]
    context = Context()
    rclpy.init(args=args, context=context)
    made = Node("table_test", context=context,
                automatically_declare_parameters_from_overrides=auto_declare,
                allow_undeclared_parameters=auto_declare)
    try:
        yield made
    finally:
        made.destroy_node()
        rclpy.shutdown(context=context)


def test_defaults_and_descriptors_with_ranges() -> None:
    from sar_framework.ros.parameters import declare_table

    with node("rate:=4", "ids:=['a', 'b']") as n:
        values = declare_table(n, TABLE)
        assert values == {"rate": 4, "mode": "auto", "count": 3, "ids": ["a", "b"],
                          "path": "", "use_sim_time": False}
        rate = n.describe_parameter("rate")
        assert rate.description == "ticks per second [Hz]"
        assert rate.additional_constraints == "> 0 and <= 10"
        assert (rate.floating_point_range[0].from_value,
                rate.floating_point_range[0].to_value) == (0.0, 10.0)
        assert n.describe_parameter("count").integer_range[0].from_value == 1
        assert n.describe_parameter("mode").additional_constraints == "one of auto, once"
        assert not n.has_parameter("zones.*.x")
        # rclpy now enforces the range on a later set too.
        from rclpy.parameter import Parameter

        result = n.set_parameters([Parameter("rate", value=11.0)])[0]
        assert not result.successful


@pytest.mark.parametrize(("override", "message"), [
    ("rate:=0.0", "parameters: rate: must be > 0 and <= 10, got 0.0"),
    ("mode:=onse", "parameters: mode: must be one of auto, once, got 'onse' "
     "(did you mean 'once'?)"),
    ("count:=0", "parameters: count: must be >= 1, got 0"),
    ("path:=3", "parameters: path: must be a string or a list of strings, got 3"),
])
def test_a_value_the_rule_rejects_is_one_error_naming_the_key(override: str,
                                                              message: str) -> None:
    from sar_framework.ros.parameters import declare_table

    with node(override, auto_declare=True) as n, pytest.raises(ParamsError) as err:
        declare_table(n, TABLE)
    assert str(err.value) == message


def test_a_file_value_keeps_its_value_gets_the_descriptor_and_is_located(
        tmp_path: Path) -> None:
    from sar_framework.ros.parameters import declare_table

    good = tmp_path / "good.yaml"
    good.write_text("/**:\n  ros__parameters:\n    rate: 5.0\n    path: [a, b]\n")
    with node(params_file=good, auto_declare=True) as n:
        values = declare_table(n, TABLE)
        assert values["rate"] == 5.0 and values["path"] == ["a", "b"]
        assert n.describe_parameter("rate").floating_point_range[0].to_value == 10.0
    bad = tmp_path / "bad.yaml"
    bad.write_text("/**:\n  ros__parameters:\n    rate: 50.0\n")
    locations = check_params_file(bad)
    with node(params_file=bad, auto_declare=True) as n, pytest.raises(ParamsError) as err:
        declare_table(n, TABLE, source=str(bad), locations=locations)
    assert str(err.value) == f"{bad}:3:5: rate: must be > 0 and <= 10, got 50.0"
