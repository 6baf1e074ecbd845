"""``python -m sar_framework.recording``: the mission recorder (see :mod:`.recorder`)."""

from sar_framework.recording.recorder import main

if __name__ == "__main__":
    main()
