"""Runs test modules of the Python module (python/quarry) with unittest, for ctest: the names on
the command line (all test_*.py here without any). Exits 77 — ctest's SKIP for these tests —
when numpy is missing, saying so; 0 when every test passed, 1 otherwise."""

import importlib.util
import os
import sys
import unittest

if importlib.util.find_spec("numpy") is None:
    print(
        "SKIP: numpy is not installed for %s; the Python module needs it "
        "(Debian: apt install python3-numpy, or configure with -DQUARRY_PYTHON=/usr/bin/python3)"
        % sys.executable
    )
    sys.exit(77)

here = os.path.dirname(os.path.abspath(__file__))
loader = unittest.TestLoader()
suite = loader.loadTestsFromNames(sys.argv[1:]) if len(sys.argv) > 1 else loader.discover(here)
result = unittest.TextTestRunner(verbosity=2, stream=sys.stdout).run(suite)
sys.exit(0 if result.wasSuccessful() else 1)
