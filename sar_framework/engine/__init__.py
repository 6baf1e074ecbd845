"""The tree engine core: parse, validate, build, render. Never imports ROS."""
