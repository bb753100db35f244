"""The PEP 517 build backend of the invfem Python package (apps/python/pyproject.toml).

It builds the CMake target invfem_python in the clone's build folder and writes a wheel of the
package invfem/: the extension module _invfem, __init__.py, the type stubs __init__.pyi and
py.typed. It uses the standard library only, so pip's isolated build environment installs nothing
and `pip install --no-index ./apps/python` works offline.

The build folder is $INVFEM_BUILD_DIR when set, otherwise <clone>/build (as apps/quickstart.sh and
tests/run.sh use it): an existing build is reused, so a second install only links what changed. A
folder without a CMake cache is configured first (Release).

pip builds a local folder in place (pip >= 21.3), so the clone is two folders above this package.
"""

import base64
import hashlib
import os
import re
import subprocess
import sys
import sysconfig
import tomllib
import zipfile
from importlib.machinery import EXTENSION_SUFFIXES
from pathlib import Path

PACKAGE_SOURCE = Path(__file__).resolve().parent.parent  # apps/python
ROOT = PACKAGE_SOURCE.parent.parent
PACKAGE = "invfem"
# The package's files besides the extension module, from apps/python/invfem.
PACKAGE_FILES = ("__init__.py", "__init__.pyi", "py.typed")
TARGET = "invfem_python"
# Wheel entries get one fixed time, so the same build gives the same wheel.
ZIP_TIME = (1980, 1, 1, 0, 0, 0)


class BuildError(RuntimeError):
    """A build that cannot go on; its message names the path and what to do."""


# --- metadata ------------------------------------------------------------------------------------


def _version():
    """The project's version, from the top CMakeLists.txt's project(invfem VERSION X.Y.Z)."""
    cmakelists = ROOT / "CMakeLists.txt"
    try:
        text = cmakelists.read_text()
    except OSError as e:
        raise BuildError(f"{cmakelists}: cannot read it ({e.strerror}); the backend must run inside an invfem "
                         "clone (pip install ./apps/python from its root)") from None
    match = re.search(r"project\(\s*invfem\s+VERSION\s+([0-9][0-9.]*)", text)
    if not match:
        raise BuildError(f"{cmakelists}: no `project(invfem VERSION X.Y.Z)` to take the version from")
    return match.group(1)


def _project():
    """pyproject.toml's [project] table."""
    with open(PACKAGE_SOURCE / "pyproject.toml", "rb") as f:
        return tomllib.load(f)["project"]


def _metadata():
    """The core metadata (METADATA file) of the distribution."""
    project = _project()
    lines = ["Metadata-Version: 2.1", f"Name: {project['name']}", f"Version: {_version()}",
             f"Summary: {project['description']}", f"Requires-Python: {project['requires-python']}"]
    lines += [f"Requires-Dist: {d}" for d in project.get("dependencies", [])]
    return "\n".join(lines) + "\n"


def _tag():
    """The wheel tag of the running interpreter, which the module is built for (cp311-cp311-linux_x86_64)."""
    if sys.implementation.name != "cpython":
        raise BuildError(f"the module is a CPython extension; this is {sys.implementation.name}")
    python = f"cp{sys.version_info.major}{sys.version_info.minor}"
    platform = sysconfig.get_platform().replace("-", "_").replace(".", "_")
    return f"{python}-{python}{sys.abiflags}-{platform}"


def _wheel_file():
    """The WHEEL file: a platform wheel (it holds a compiled module)."""
    return f"Wheel-Version: 1.0\nGenerator: invfem_build\nRoot-Is-Purelib: false\nTag: {_tag()}\n"


def _dist_info():
    return f"{PACKAGE}-{_version()}.dist-info"


# --- the CMake build -------------------------------------------------------------------------------


def _build_dir():
    env = os.environ.get("INVFEM_BUILD_DIR")
    return Path(env).resolve() if env else ROOT / "build"


def _run(command, what, hint=""):
    """Runs a command, its output going to pip's log (shown by pip -v or on failure)."""
    print("invfem_build:", " ".join(str(c) for c in command), flush=True)
    try:
        done = subprocess.run([str(c) for c in command], stderr=subprocess.STDOUT)
    except FileNotFoundError:
        raise BuildError(f"{command[0]}: not found; {what} needs it (apps/deps.sh installs it)") from None
    if done.returncode != 0:
        raise BuildError(f"{what} failed (exit {done.returncode}): {' '.join(str(c) for c in command)}{hint}")


def _build_module():
    """Configures the build folder when it has no cache, builds the module, returns its path."""
    build = _build_dir()
    if not (build / "CMakeCache.txt").exists():
        # The module is built for this interpreter (its base one inside a venv).
        python = getattr(sys, "_base_executable", sys.executable)
        _run(["cmake", "-S", ROOT, "-B", build, "-DCMAKE_BUILD_TYPE=Release", f"-DPYTHON_EXECUTABLE={python}"],
             f"configuring {build}")
    jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
    _run(["cmake", "--build", build, "--target", TARGET, "--parallel", jobs], f"building the module in {build}",
         "; the target needs pybind11-dev (apps/deps.sh) and INVFEM_BUILD_PYTHON=ON")
    return _find_module(build / "apps" / "python" / PACKAGE)


def _find_module(package_dir):
    """The built extension module in package_dir, checked to be one this interpreter loads."""
    suffix = EXTENSION_SUFFIXES[0]
    built = sorted(package_dir.glob("_invfem*.so"))
    if not built:
        raise BuildError(f"{package_dir}: no _invfem module after building {TARGET}")
    for path in built:
        if path.name == "_invfem" + suffix:
            return path
    raise BuildError(f"{built[0]}: built for another Python than this one (Python "
                     f"{sys.version_info.major}.{sys.version_info.minor}, modules *{suffix}); "
                     "set INVFEM_BUILD_DIR to a build folder of its own for this interpreter")


# --- the wheel -------------------------------------------------------------------------------------


def _record_hash(data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"sha256={digest}"


def _write_zip(path, entries):
    """A zip of (name, bytes) entries, regular files readable by all, with RECORD last."""
    dist_info = _dist_info()
    record = "".join(f"{name},{_record_hash(data)},{len(data)}\n" for name, data in entries)
    record += f"{dist_info}/RECORD,,\n"
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        for name, data in entries + [(f"{dist_info}/RECORD", record.encode())]:
            info = zipfile.ZipInfo(name, ZIP_TIME)
            info.external_attr = 0o100644 << 16
            info.compress_type = zipfile.ZIP_DEFLATED
            z.writestr(info, data)


def _wheel_entries(module):
    entries = [(f"{PACKAGE}/{name}", (PACKAGE_SOURCE / PACKAGE / name).read_bytes()) for name in PACKAGE_FILES]
    entries.append((f"{PACKAGE}/{module.name}", module.read_bytes()))
    entries += [(f"{_dist_info()}/METADATA", _metadata().encode()), (f"{_dist_info()}/WHEEL", _wheel_file().encode())]
    return entries


# --- PEP 517 hooks ---------------------------------------------------------------------------------


def get_requires_for_build_wheel(config_settings=None):
    """Nothing to install: the backend uses the standard library, the build CMake and apt's packages."""
    return []


def prepare_metadata_for_build_wheel(metadata_directory, config_settings=None):
    """Writes the .dist-info folder (METADATA, WHEEL) without building; returns its name."""
    folder = Path(metadata_directory) / _dist_info()
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "METADATA").write_text(_metadata())
    (folder / "WHEEL").write_text(_wheel_file())
    return folder.name


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    """Builds the module and writes the wheel into wheel_directory; returns its file name."""
    module = _build_module()
    name = f"{PACKAGE}-{_version()}-{_tag()}.whl"
    Path(wheel_directory).mkdir(parents=True, exist_ok=True)
    _write_zip(Path(wheel_directory) / name, _wheel_entries(module))
    return name
