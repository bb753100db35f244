"""`pip install ./apps/python` offline, as README.md ("Python") says: in a venv made with
--system-site-packages (NumPy from Debian's python3-numpy), with --no-index so that nothing can be
downloaded, from the build tree CTest runs in (INVFEM_BUILD_DIR: the module is already built, so
the install takes seconds). Exits 77 (skipped) where venv or pip is missing.

What it must show: pip installs the package from the in-tree backend; the installed invfem is the
venv's (not PYTHONPATH's) and steps a scene; the package holds the module, __init__.py, the stubs
and py.typed; the wheel's RECORD has the right sha256 of each file, its tag is this interpreter's,
its METADATA is prepare_metadata_for_build_wheel's; and, where mypy is installed, mypy reads the
installed stubs (a wrong type is reported, right types pass).
"""

import base64
import csv
import hashlib
import importlib.machinery
import io
import json
import os
import subprocess
import sys
import sysconfig
import tempfile
import unittest
import zipfile

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BUILD = os.environ.get("INVFEM_BUILD_DIR", os.path.join(ROOT, "build"))
VENV = os.environ.get("INVFEM_TEST_VENV", os.path.join(BUILD, "tests", "python", "pip_venv"))
SUFFIX = importlib.machinery.EXTENSION_SUFFIXES[0]
PACKAGE_FILES = {"__init__.py", "__init__.pyi", "py.typed", "_invfem" + SUFFIX}


def clean_env():
    """The environment without PYTHONPATH (the installed package must be the one imported)."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env.update(INVFEM_BUILD_DIR=BUILD, PIP_DISABLE_PIP_VERSION_CHECK="1", PIP_NO_INPUT="1")
    return env


def run(command, **kwargs):
    done = subprocess.run(command, capture_output=True, text=True, env=clean_env(), timeout=600, **kwargs)
    if done.returncode != 0:
        raise AssertionError("%s: exit %d\n%s%s" % (" ".join(command), done.returncode, done.stdout[-4000:],
                                                   done.stderr[-4000:]))
    return done


def venv_python():
    return os.path.join(VENV, "bin", "python")


def skip_without_venv_and_pip():
    try:
        import ensurepip  # noqa: F401  (python3-venv)
        import venv  # noqa: F401
    except ImportError as e:
        print("skipped: %s (apt install python3-venv python3-pip)" % e)
        sys.exit(77)


def load_backend():
    sys.path.insert(0, os.path.join(ROOT, "apps", "python", "backend"))
    try:
        import invfem_build
    finally:
        sys.path.pop(0)
    return invfem_build


class PipInstallTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        run([sys.executable, "-m", "venv", "--clear", "--system-site-packages", VENV])
        cls.install = run([venv_python(), "-m", "pip", "install", "--no-index", "--no-cache-dir", "./apps/python"],
                          cwd=ROOT)
        cls.site = run([venv_python(), "-c", "import sysconfig; print(sysconfig.get_path('platlib'))"]).stdout.strip()

    def test_the_installed_package_steps_a_scene(self):
        code = ("import json, invfem\n"
                "sim = invfem.Simulation('apps/scenes/cloth_drape.json', quick=True, set={'frames': 2})\n"
                "r = [sim.step_frame() for _ in range(2)][-1]\n"
                "print(json.dumps({'file': invfem.__file__, 'frame': r['frame'], "
                "'shape': sim.positions('cloth').shape, 'version': invfem.__version__}))\n")
        out = json.loads(run([venv_python(), "-c", code], cwd=ROOT).stdout.strip().splitlines()[-1])
        self.assertEqual(os.path.dirname(out["file"]), os.path.join(self.site, "invfem"))
        self.assertEqual(out["frame"], 2)
        self.assertEqual(out["shape"], [289, 3])
        self.assertEqual(out["version"], load_backend()._version())

    def test_the_package_holds_the_module_stubs_and_py_typed(self):
        self.assertEqual(set(os.listdir(os.path.join(self.site, "invfem"))) - {"__pycache__"}, PACKAGE_FILES)
        dist_info = os.path.join(self.site, "invfem-%s.dist-info" % load_backend()._version())
        with open(os.path.join(dist_info, "METADATA")) as f:
            metadata = f.read()
        self.assertIn("Name: invfem\n", metadata)
        self.assertIn("Requires-Dist: numpy\n", metadata)

    def test_the_wheel_is_well_formed(self):
        backend = load_backend()
        self.assertEqual(backend.get_requires_for_build_wheel(), [])
        with tempfile.TemporaryDirectory() as tmp:
            metadata_dir = backend.prepare_metadata_for_build_wheel(tmp)
            with open(os.path.join(tmp, metadata_dir, "METADATA")) as f:
                metadata = f.read()
            name = backend.build_wheel(tmp)
            with zipfile.ZipFile(os.path.join(tmp, name)) as z:
                files = {n: z.read(n) for n in z.namelist()}
        python = "cp%d%d" % sys.version_info[:2]
        platform = sysconfig.get_platform().replace("-", "_").replace(".", "_")
        self.assertEqual(name, "invfem-%s-%s-%s%s-%s.whl" % (backend._version(), python, python, sys.abiflags, platform))
        dist_info = metadata_dir
        self.assertEqual(set(files), {"invfem/" + f for f in PACKAGE_FILES} |
                         {dist_info + "/" + f for f in ("METADATA", "WHEEL", "RECORD")})
        self.assertEqual(files[dist_info + "/METADATA"].decode(), metadata)
        self.assertIn("Tag: %s-%s%s-%s\n" % (python, python, sys.abiflags, platform), files[dist_info + "/WHEEL"].decode())
        self.assertIn("Root-Is-Purelib: false\n", files[dist_info + "/WHEEL"].decode())
        record = list(csv.reader(io.StringIO(files[dist_info + "/RECORD"].decode())))
        self.assertEqual(sorted(row[0] for row in record), sorted(files))
        for path, digest, size in record:
            if path == dist_info + "/RECORD":
                self.assertEqual((digest, size), ("", ""))
                continue
            expected = base64.urlsafe_b64encode(hashlib.sha256(files[path]).digest()).rstrip(b"=").decode()
            self.assertEqual((digest, int(size)), ("sha256=" + expected, len(files[path])), path)

    def test_mypy_reads_the_installed_stubs(self):
        if subprocess.run([venv_python(), "-c", "import mypy"], capture_output=True).returncode != 0:
            self.skipTest("mypy is not installed (python3-mypy)")
        good = ("import numpy as np\nimport numpy.typing as npt\nimport invfem\n"
                "sim = invfem.Simulation('scene.json', quick=True, set={'frames': 2})\n"
                "x: npt.NDArray[np.float64] = sim.positions('cloth')\n"
                "total: int = invfem.check([(x, sim.surface('cloth')['triangles'])])['total']\n")
        bad = "import invfem\nname: str = invfem.Simulation('scene.json').frame\n"
        with tempfile.TemporaryDirectory() as tmp:
            for file, text in (("good.py", good), ("bad.py", bad)):
                with open(os.path.join(tmp, file), "w") as f:
                    f.write(text)
            mypy = [venv_python(), "-m", "mypy", "--cache-dir", os.path.join(tmp, "cache"), "--config-file", os.devnull]
            run(mypy + ["good.py"], cwd=tmp)
            done = subprocess.run(mypy + ["bad.py"], cwd=tmp, capture_output=True, text=True, env=clean_env(), timeout=600)
        self.assertEqual(done.returncode, 1, done.stdout + done.stderr)
        self.assertIn('Incompatible types in assignment (expression has type "int", variable has type "str")', done.stdout)


if __name__ == "__main__":
    skip_without_venv_and_pip()
    unittest.main()
