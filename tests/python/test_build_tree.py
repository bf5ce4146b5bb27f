"""Making the module importable without QUARRY_LIBRARY: the build tree's copy of the package
(PYTHONPATH=<build>/python) finds this build's libquarry.so through its generated
_library_path.py, and an installed tree (cmake --install) finds the installed library relative to
itself. ctest runs this with PYTHONPATH on the build's python folder and QUARRY_LIBRARY unset."""

import filecmp
import os
import shutil
import subprocess
import sys
import unittest

SOURCE = os.environ.get("QUARRY_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
BUILD_PYTHON = os.environ.get("QUARRY_BUILD_PYTHON_DIR")

# Prints where quarry came from and where its library is, after opening a simulation with it.
PROBE = (
    "import quarry\n"
    "with quarry.Simulation.empty() as sim:\n"
    "    print(quarry.__file__)\n"
    "    print(quarry.library_path)\n"
)


def probe(python_path):
    environment = dict(os.environ, PYTHONPATH=python_path)
    environment.pop("QUARRY_LIBRARY", None)
    result = subprocess.run(
        [sys.executable, "-c", PROBE], env=environment, capture_output=True, text=True
    )
    if result.returncode != 0:
        raise AssertionError("import quarry from %s failed:\n%s" % (python_path, result.stderr))
    return result.stdout.split("\n")[:2]


@unittest.skipUnless(BUILD_PYTHON, "QUARRY_BUILD_PYTHON_DIR is not set: run through ctest")
class Importable(unittest.TestCase):
    def test_from_the_build_tree(self):
        package, library = probe(BUILD_PYTHON)
        print("\nbuild tree: %s loads %s" % (package, library))
        self.assertEqual(os.path.dirname(package), os.path.join(BUILD_PYTHON, "quarry"))
        self.assertTrue(os.path.isfile(library))
        self.assertEqual(os.path.basename(library), "libquarry.so.1")
        sources = os.path.join(SOURCE, "python", "quarry")
        names = sorted(n for n in os.listdir(sources) if n.endswith(".py"))
        _, differ, missing = filecmp.cmpfiles(
            sources, os.path.join(BUILD_PYTHON, "quarry"), names, shallow=False
        )
        self.assertEqual(
            differ + missing, [], "the build's copy of the package is not the source's: rebuild"
        )

    def test_from_an_installed_tree(self):
        cmake, build = os.environ.get("QUARRY_CMAKE"), os.environ.get("QUARRY_BUILD_DIR")
        install_dir = os.environ.get("QUARRY_PYTHON_INSTALL_DIR")
        if not (cmake and build and install_dir):
            self.skipTest("QUARRY_CMAKE, QUARRY_BUILD_DIR or QUARRY_PYTHON_INSTALL_DIR is not set")
        prefix = os.path.join(build, "python_install")
        shutil.rmtree(prefix, ignore_errors=True)
        subprocess.run(
            [cmake, "--install", build, "--prefix", prefix], check=True, capture_output=True
        )
        package, library = probe(os.path.join(prefix, install_dir))
        print(
            "\ninstalled under %s: %s loads %s"
            % (prefix, os.path.relpath(package, prefix), os.path.relpath(library, prefix))
        )
        self.assertEqual(os.path.dirname(package), os.path.join(prefix, install_dir, "quarry"))
        self.assertEqual(library, os.path.join(prefix, "lib", "libquarry.so.1"))
        shutil.rmtree(prefix, ignore_errors=True)


if __name__ == "__main__":
    unittest.main()
