"""Kept for the tests that import it: the code lives in :mod:`sar_framework.testing.processes`."""

from sar_framework.testing.processes import NodeProcess

__all__ = ["NodeProcess"]
