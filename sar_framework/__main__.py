"""``python -m sar_framework``: the same as the ``sar-tree`` command."""

import sys

from sar_framework.cli import main

sys.exit(main())
