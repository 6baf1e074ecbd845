"""Embedded Nav2 stand-in: a map, robots on it, and nodes that speak Nav2's surface.

It runs on any map_server map (``map_yaml``; the course's by default), the robots spawned
where their parameters or the fleet file say. It knows no mission.

ROS-free core (plain Python + numpy)::

    world       obstacle geometry of a world file (walls, debris, robot), map_writer's input
    occupancy   load map_server maps as map_server does; rasterise a world; inflate
    map_writer  write a map_server map (PGM + yaml)
    planner     A* on the inflated grid
    drive       differential-drive model and path follower, stepped by dt
    clock       simulated time paced by a speed factor
    faults      fault-injection params (reject, abort Nth, delay, blocked areas, phantoms)
    costmaps    the two costmaps' phantom layer: what clearing removes, walls that stay
    progress_checker  the stuck-controller fault as Nav2's progress checker sees it
    plugin_ids  the planner/controller/checker/smoother ids of config/nav2_params.yaml
    geometry    nearest points on paths, pruning a path to the robot
    params      the simulator's parameter table (SPEED: the speed's one default and rule)
    navigation  one goal at a time: plan, drive, decide the outcome as Nav2 would
    traffic     a fleet's other robots as obstacles (global costmap, controller)
    detour      planning next to them: NavFn's goal tolerance, replanning a held robot
    fleet_file  the fleet file: robot names (namespaces) and spawn poses
    trace       JSON Lines trace of the robot's path and goal events

ROS nodes (rclpy)::

    sim_node           the simulator: physics thread, /clock, one RobotStack per robot
    robot_stack        one robot's Nav2 nodes (root or its namespace), its TF and odometry
    settings           its parameters declared from the table, validated
    live_params        run-time parameter changes (speed, phantoms, stuck, walls)
    lifecycle          Nav2LifecycleNode: rclpy lifecycle, action servers need ACTIVE
    lifecycle_manager  lifecycle_manager_localization / _navigation (manage_nodes, is_active)
    goal_actions       serve a navigator goal as an action (feedback, cancel, result)
    nav_server         bt_navigator: navigate_to_pose, navigate_through_poses
    planning_servers   planner_server, smoother_server
    costmap_servers    the costmap nodes' clearing services, is_path_valid
    motion_servers     controller_server, behavior_server, waypoint_follower
    map_server         map_server: /map latched on activation
    amcl               /initialpose -> /amcl_pose, updates as the robot moves
    messages           message builders
    __main__           the ``sar-sim`` console script

What it offers of Nav2's surface, and what not: docs/reference/nav2-surface.md.
"""
