"""README.md's first Python example, run exactly as written, from the clone's root with PYTHONPATH
at the built package as apps/quickstart.sh leaves it, so that the README cannot drift from the
module. The block is the ```python one between the markers <!-- python-first-example --> and
<!-- /python-first-example -->.

What it must show: the example runs to the end and prints the certificate's count, 0; the README's
PYTHONPATH (build/apps/python) is where the build puts the package; the quickstart builds it.
"""

import os
import re
import subprocess
import sys
import unittest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BUILD = os.environ.get("INVFEM_BUILD_DIR", os.path.join(ROOT, "build"))
README = os.path.join(ROOT, "README.md")


def first_example():
    with open(README) as f:
        text = f.read()
    match = re.search(r"<!-- python-first-example -->\s*```python\n(.*?)```\s*<!-- /python-first-example -->", text, re.S)
    if not match:
        raise AssertionError(README + ": no ```python block between <!-- python-first-example --> and "
                             "<!-- /python-first-example -->")
    return match.group(1)


class ReadmeExampleTest(unittest.TestCase):
    def test_the_first_example_runs_as_written(self):
        env = dict(os.environ, PYTHONPATH=os.path.join(BUILD, "apps", "python"))
        done = subprocess.run([sys.executable, "-c", first_example()], cwd=ROOT, env=env, capture_output=True,
                              text=True, timeout=600)
        self.assertEqual(done.returncode, 0, done.stderr[-4000:])
        self.assertEqual(done.stdout.strip().splitlines()[-1], "0")  # the certificate: no intersecting pair

    def test_the_readme_path_is_where_the_build_puts_the_package(self):
        self.assertIn("PYTHONPATH=build/apps/python", first_example())
        self.assertTrue(os.path.isfile(os.path.join(BUILD, "apps", "python", "invfem", "__init__.py")))

    def test_the_quickstart_builds_the_module(self):
        with open(os.path.join(ROOT, "apps", "quickstart.sh")) as f:
            builds = [line for line in f if re.match(r"\s*cmake --build .*--target", line)]
        self.assertEqual(len(builds), 1, builds)
        self.assertIn("invfem_python", builds[0].split())


if __name__ == "__main__":
    unittest.main()
