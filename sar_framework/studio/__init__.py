"""``sar-tree studio``: the mission in the browser.

Modules, from the bottom up:

- :mod:`.timeline`: a mission's ticks, events and poses, and the frame at any instant;
- :mod:`.tree_view` and :mod:`.world_view`: the tree diagram and the map the page draws;
- :mod:`.session`: what one studio shows (live or a recording), shared by its tabs;
- :mod:`.safety`: the session token, confined paths, checked websocket messages;
- :mod:`.server`: the Starlette app (page, assets, websocket);
- :mod:`.ros_feed`: the live feed from the ROS graph (the only module importing ROS);
- :mod:`.command`: the ``sar-tree studio live|replay|edit`` command line.

The page itself is ``static/`` (our own HTML, CSS and JavaScript; no framework, no CDN).
"""
