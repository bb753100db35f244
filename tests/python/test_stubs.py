"""The type stubs (apps/python/invfem/__init__.pyi) against the built module, run by CTest with
PYTHONPATH at the built package and INVFEM_STUBS at the stub file.

What it must show: every public name of the module and of Simulation has a stub and every stub a
name at run time; properties are properties and methods methods; each function's arguments (names,
keyword-only, which have defaults) are those pybind11 reports in its signature line; every stub has
a one-line docstring; and, where mypy is installed (python3-mypy), mypy's stubtest finds nothing.
"""

import ast
import inspect
import os
import subprocess
import sys
import tempfile
import unittest

import invfem

STUBS = os.environ.get("INVFEM_STUBS",
                       os.path.join(os.path.dirname(__file__), "..", "..", "apps", "python", "invfem", "__init__.pyi"))


def public(names):
    return {n for n in names if not n.startswith("_")}


def stub_tree():
    with open(STUBS) as f:
        return ast.parse(f.read(), STUBS)


def stub_members(body):
    """{name: node} of the functions, classes and annotated names defined in a stub body."""
    members = {}
    for node in body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            members[node.name] = node
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            members[node.target.id] = node
    return members


def arguments(function):
    """What a caller sees of a function's arguments: positional names, keyword-only names, and the
    names that have defaults."""
    a = function.args
    positional = [x.arg for x in a.posonlyargs + a.args]
    defaulted = positional[len(positional) - len(a.defaults):] if a.defaults else []
    defaulted += [x.arg for x, d in zip(a.kwonlyargs, a.kw_defaults) if d is not None]
    return positional, [x.arg for x in a.kwonlyargs], sorted(defaulted)


def runtime_signature(obj, name):
    """The signature line pybind11 puts first in a function's docstring, parsed as a def."""
    line = (obj.__doc__ or "").strip().splitlines()[0]
    if not line.startswith(name + "("):
        raise AssertionError("%s: no signature line in its docstring: %r" % (name, line))
    return ast.parse("def " + line + ": ...").body[0]


class StubTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.members = stub_members(stub_tree().body)
        cls.simulation = stub_members(cls.members["Simulation"].body)

    def test_module_names_match(self):
        self.assertEqual(public(dir(invfem)), public(self.members))
        self.assertEqual(set(invfem.__all__), public(self.members) | {"__version__"})
        self.assertIn("__version__", self.members)
        self.assertIsInstance(invfem.__version__, str)

    def test_simulation_names_match(self):
        self.assertEqual(public(dir(invfem.Simulation)), public(self.simulation))

    def test_properties_and_methods_are_what_the_stubs_say(self):
        for name in public(self.simulation):
            stub = self.simulation[name]
            is_property = any(isinstance(d, ast.Name) and d.id == "property" for d in stub.decorator_list)
            runtime = inspect.getattr_static(invfem.Simulation, name)
            self.assertEqual(is_property, isinstance(runtime, property), name)

    def test_arguments_match_the_signatures(self):
        functions = [("check", invfem.check, self.members["check"])]
        for name, stub in self.simulation.items():
            if isinstance(stub, ast.FunctionDef) and not isinstance(getattr(invfem.Simulation, name), property):
                functions.append((name, getattr(invfem.Simulation, name), stub))
        self.assertIn("__init__", [f[0] for f in functions])
        for name, runtime, stub in functions:
            with self.subTest(name):
                self.assertEqual(arguments(runtime_signature(runtime, name)), arguments(stub))

    def test_every_stub_has_a_one_line_docstring(self):
        nodes = [self.members["Simulation"]] + [n for n in self.members.values() if isinstance(n, ast.FunctionDef)]
        nodes += [n for n in self.simulation.values() if isinstance(n, ast.FunctionDef)]
        for node in nodes:
            doc = ast.get_docstring(node)
            self.assertTrue(doc, node.name)
            self.assertNotIn("\n", doc, node.name)

    def test_mypy_stubtest(self):
        """mypy's own comparison of the stubs with the module, where mypy is installed."""
        try:
            import mypy.stubtest  # noqa: F401
        except ImportError:
            self.skipTest("mypy is not installed (python3-mypy)")
        package_dir = os.path.dirname(os.path.dirname(os.path.abspath(invfem.__file__)))
        allowlist = os.path.join(os.path.dirname(os.path.abspath(__file__)), "stubtest_allowlist.txt")
        with tempfile.TemporaryDirectory() as cache:
            env = dict(os.environ, MYPYPATH=package_dir, MYPY_CACHE_DIR=cache)
            done = subprocess.run([sys.executable, "-m", "mypy.stubtest", "invfem", "--allowlist", allowlist],
                                  capture_output=True, text=True, env=env, cwd=cache, timeout=600)
        self.assertEqual(done.returncode, 0, done.stdout + done.stderr)


if __name__ == "__main__":
    unittest.main()
