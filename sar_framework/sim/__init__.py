"""Embedded Nav2 stand-in: the course world, its map, and nodes that speak Nav2's surface.

ROS-free core (plain Python + numpy)::

    world       the course world's geometry (maps/final_project_world.yaml)
    occupancy   rasterise it into a map_server map; load maps; inflate
    planner     A* on the inflated grid
    drive       differential-drive model and path follower, stepped by dt
    clock       simulated time paced by a speed factor
    faults      fault-injection params (reject, abort Nth, delay, blocked zones)
    navigation  one goal at a time: plan, drive, decide the outcome as Nav2 would
    trace       JSON Lines trace of the robot's path and goal events

ROS nodes (rclpy)::

    sim_node    the simulator: physics thread, /clock, /tf, /odom, /map
    nav_server  bt_navigator: the navigate_to_pose action server
    amcl        /initialpose -> /amcl_pose
    lifecycle   ~/get_state answering ACTIVE
    messages    message builders
    __main__    the ``sar-sim`` console script
"""
