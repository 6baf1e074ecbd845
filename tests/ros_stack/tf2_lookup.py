"""What ``tf2_echo`` does, as a Python program: a tf2_ros Buffer + TransformListener look-up.

::

    python tests/ros_stack/tf2_lookup.py map survivor_1 survivor_2 --timeout 15

prints one line per child frame, ``map -> survivor_1: -2.500 3.200 0.000``, and exits 0;
exits 1 with the tf2 error when a frame cannot be looked up within the timeout.
"""

from __future__ import annotations

import argparse
import sys
import time


def main() -> int:
    """Look up parent -> child for every child frame named on the command line."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("parent")
    parser.add_argument("children", nargs="+")
    parser.add_argument("--timeout", type=float, default=15.0)
    args = parser.parse_args()

    import rclpy
    from rclpy.duration import Duration
    from rclpy.time import Time
    from tf2_ros import Buffer, TransformException, TransformListener

    rclpy.init()
    node = rclpy.create_node("tf2_lookup_probe")
    buffer = Buffer()
    listener = TransformListener(buffer, node, spin_thread=True)
    deadline = time.monotonic() + args.timeout
    try:
        for child in args.children:
            remaining = max(0.1, deadline - time.monotonic())
            try:
                transform = buffer.lookup_transform(args.parent, child, Time(),
                                                    timeout=Duration(seconds=remaining))
            except TransformException as err:
                print(f"cannot look up {args.parent} -> {child}: {err}", file=sys.stderr)
                return 1
            t = transform.transform.translation
            print(f"{args.parent} -> {child}: {t.x:.3f} {t.y:.3f} {t.z:.3f}", flush=True)
        return 0
    finally:
        listener.unregister()
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    sys.exit(main())
