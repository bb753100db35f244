"""The Python module `invfem` (apps/python), run by CTest with PYTHONPATH at the built module and
INVFEM_BIN at the command line, INVFEM_SCENES at apps/scenes.

What it must show: a scene stepped from Python writes the same frames, byte for byte, as `invfem
run`; a body driven from arrays (a callable or pushed frames) gives the same frames as the same
motion given as a mesh sequence; a bad field raises ValueError with its JSON path; arrays have the
documented shapes and dtypes; checkpoint and resume are bit-identical; the certificate on arrays;
stepping releases the GIL; calls on one Simulation from several threads run one at a time; a dict
scene's values are converted with their path named in errors; errors are Python exceptions.
"""

import copy
import filecmp
import json
import os
import subprocess
import sys
import tempfile
import threading
import unittest

import numpy as np

import invfem

BIN = os.environ.get("INVFEM_BIN", "invfem")
SCENES = os.environ.get("INVFEM_SCENES", os.path.join(os.path.dirname(__file__), "..", "..", "apps", "scenes"))


def write_obj(path, x, tris):
    """An OBJ whose coordinates read back as exactly these doubles (repr round-trips)."""
    with open(path, "w") as f:
        for p in x:
            f.write("v %r %r %r\n" % (float(p[0]), float(p[1]), float(p[2])))
        for t in tris:
            f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))


def box(half, center):
    """A closed box: 8 vertices (8, 3) and 12 outward triangles (12, 3)."""
    c = np.asarray(center, dtype=float)
    x = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float) * half + c
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = []
    for a, b, c_, d in quads:
        tris += [(a, b, c_), (a, c_, d)]
    return x, np.array(tris, dtype=np.int32)


def body_frame(k):
    """Frame k of a box that rises into a falling sheet and sways: (8, 3) float64."""
    x, _ = box(0.15, (0.02 * np.sin(0.7 * k), 0.2 + 0.03 * k, 0.0))
    return x


def sheet_scene(frames_pattern, last):
    return {
        "name": "sheet_on_box",
        "fps": 25,
        "frames": 8,
        "solver": {"integrator": "implicit"},
        "cloths": [{
            "name": "sheet",
            "grid": {"width": 0.6, "height": 0.6, "nx": 8, "ny": 8},
            "transform": {"translate": [0, 0.45, 0]},
            "material": {"young": 2e5, "poisson": 0.3, "density": 300, "thickness": 0.002, "damping": 0.005,
                         "bending_stiffness": 1e-4, "bending_damping": 1e-5},
        }],
        "colliders": [{
            "name": "body", "type": "sequence", "frames": {"pattern": frames_pattern, "first": 0, "last": last},
            "fps": 25, "friction": 0.3, "query_radius": 0.02,
        }],
    }


class ModuleTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.dir = cls.tmp.name
        _, tris = box(0.15, (0, 0, 0))
        cls.tris = tris
        cls.last = 10
        for k in range(cls.last + 1):
            write_obj(os.path.join(cls.dir, "body%d.obj" % k), body_frame(k), tris)
        cls.scene = sheet_scene("body{N}.obj", cls.last)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def simulation(self, **kwargs):
        return invfem.Simulation(self.scene, base_dir=self.dir, **kwargs)

    def run_frames(self, sim, n):
        return [sim.step_frame() for _ in range(n)]

    def test_scene_file_frames_match_invfem_run_byte_for_byte(self):
        scene = os.path.join(SCENES, "cloth_drape.json")
        with tempfile.TemporaryDirectory() as out:
            cli, py = os.path.join(out, "cli"), os.path.join(out, "py")
            subprocess.run([BIN, "run", scene, "--quick", "--set", "frames=6", "--out", cli, "--quiet"], check=True)
            sim = invfem.Simulation(scene, quick=True, set={"frames": 6}, out=py)
            self.run_frames(sim, sim.frames)
            names = sorted(os.listdir(os.path.join(cli, "frames", "cloth")))
            self.assertEqual(len(names), 7)
            self.assertEqual(names, sorted(os.listdir(os.path.join(py, "frames", "cloth"))))
            match, mismatch, errors = filecmp.cmpfiles(os.path.join(cli, "frames", "cloth"),
                                                       os.path.join(py, "frames", "cloth"), names, shallow=False)
            self.assertEqual((mismatch, errors), ([], []))
            self.assertTrue(filecmp.cmp(os.path.join(cli, "energies.csv"), os.path.join(py, "energies.csv"),
                                        shallow=False))

    def test_body_driven_from_arrays_matches_the_mesh_sequence(self):
        files = self.simulation()
        self.run_frames(files, 8)
        called = []

        def source(k):
            called.append(k)
            return body_frame(k)

        driven = self.simulation()
        driven.drive_body("body", source)
        self.run_frames(driven, 8)
        self.assertIn(8, called)
        pushed = self.simulation()
        for k in range(2):
            pushed.set_body_frame("body", k, body_frame(k))
        for f in range(1, 9):
            pushed.set_body_frame("body", f + 1, body_frame(f + 1))  # a step to frame f needs frame f + 1
            pushed.step_frame()
        reference = files.positions("sheet")
        self.assertGreater(np.abs(reference - self.simulation().positions("sheet")).max(), 1e-3)  # it moved
        for sim in (driven, pushed):
            self.assertTrue(np.array_equal(sim.positions("sheet"), reference))
            self.assertTrue(np.array_equal(sim.velocities("sheet"), files.velocities("sheet")))
            self.assertTrue(np.array_equal(sim.positions("body"), files.positions("body")))

    def test_a_bad_field_raises_value_error_with_its_json_path(self):
        bad = json.loads(json.dumps(self.scene))
        bad["cloths"][0]["material"]["young"] = -5
        with self.assertRaises(ValueError) as e:
            invfem.Simulation(bad, base_dir=self.dir)
        self.assertIn("cloths[0].material.young", str(e.exception))
        with self.assertRaises(ValueError) as e:
            self.simulation(set={"fps": "fast"})
        self.assertIn("fps", str(e.exception))
        with self.assertRaises(ValueError) as e:
            invfem.Simulation(os.path.join(self.dir, "missing.json"))
        self.assertIn("missing.json", str(e.exception))

    def test_arrays_have_the_documented_shapes_and_dtypes(self):
        sim = self.simulation()
        report = sim.step_frame()
        for key in ("substeps", "cg_iterations", "newton_iterations", "newton_capped", "newton_converged",
                    "self_collision", "seconds", "kinetic"):
            self.assertIn(key, report)
        self.assertEqual(report["frame"], 1)
        self.assertGreater(report["substeps"], 0)
        x = sim.positions("sheet")
        self.assertEqual((x.dtype, x.shape), (np.float64, (81, 3)))
        self.assertEqual(sim.velocities("sheet").shape, (81, 3))
        s = sim.surface("sheet")
        self.assertEqual((s["triangles"].dtype, s["triangles"].shape), (np.int32, (128, 3)))
        self.assertEqual(s["vertices"].shape, (81, 3))
        self.assertEqual(s["uv"].shape[1], 2)
        self.assertEqual(s["nodes"].shape, (81,))
        self.assertEqual(sim.tets("sheet").shape, (0, 4))
        body = sim.surface("body")
        self.assertTrue(np.array_equal(body["triangles"], self.tris))
        self.assertEqual(sim.objects, ["sheet"])
        self.assertEqual(sim.bodies, ["body"])
        self.assertAlmostEqual(sim.time, 1 / 25)
        x[:] = 0  # a copy: the simulation's state is untouched
        self.assertGreater(np.abs(sim.positions("sheet")).max(), 0)

        solid = invfem.Simulation(os.path.join(SCENES, "torus_puddle.json"), quick=True)
        solid.step_frame()
        tets = solid.tets("torus")
        self.assertEqual((tets.dtype, tets.shape[1]), (np.int32, 4))
        fields = solid.element_fields("torus")
        self.assertEqual(fields["det_F"].shape, (tets.shape[0],))
        self.assertEqual(fields["inverted"].shape, (tets.shape[0],))
        self.assertTrue(np.all(np.isfinite(fields["det_F"])))

    def test_checkpoint_and_resume_are_bit_identical(self):
        whole = self.simulation()
        self.run_frames(whole, 3)
        with tempfile.TemporaryDirectory() as ck:
            path = whole.save_checkpoint(ck)
            self.assertTrue(path.endswith("0003.ckpt"))
            self.run_frames(whole, 4)
            resumed = self.simulation()
            resumed.load_checkpoint(path)
            self.assertEqual(resumed.frame, 3)
            self.run_frames(resumed, 4)
        self.assertTrue(np.array_equal(resumed.positions("sheet"), whole.positions("sheet")))
        self.assertTrue(np.array_equal(resumed.velocities("sheet"), whole.velocities("sheet")))
        between = self.simulation()
        between.advance_to(0.05)
        with tempfile.TemporaryDirectory() as ck, self.assertRaises(Exception):
            between.save_checkpoint(ck)

    def test_check_on_arrays(self):
        tri = np.array([[0, 1, 2]], dtype=np.int32)
        a = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=float)
        crossing = np.array([[0.2, 0.2, -0.5], [0.2, 0.2, 0.5], [0.8, 0.8, 0.0]])
        apart = crossing + [0, 0, 2]
        c = invfem.check([(a, tri), (crossing, tri)])
        self.assertEqual(c["total"], 1)
        self.assertEqual(c["cross"], {(0, 1): 1})
        self.assertEqual(c["examples"], [(0, 0, 1, 0)])
        self.assertEqual(invfem.check([(a, tri), (apart, tri)])["total"], 0)
        with self.assertRaises(ValueError):
            invfem.check([(a[:, :2], tri)])
        with self.assertRaises(ValueError):
            invfem.check([(np.array([[0, 0, np.nan], [1, 0, 0], [0, 1, 0]]), tri)])

    def test_stepping_releases_the_gil(self):
        """Deterministic, not timed. With a switch interval of 1000 s no thread hands the GIL over by
        itself: the other thread, started then, runs until it blocks on `go`, and once `go` is set
        it can take the GIL, and set `ran`, only when the main thread releases it. A pure-Python
        loop first shows that it does not run then (the control); stepping must let it run."""
        scene = copy.deepcopy(self.scene)
        scene["colliders"] = []  # a falling sheet: any number of frames
        sim = invfem.Simulation(scene)
        go, ran = threading.Event(), threading.Event()

        def other():
            go.wait()
            ran.set()

        interval = sys.getswitchinterval()
        sys.setswitchinterval(1e3)
        t = threading.Thread(target=other)
        try:
            t.start()
            go.set()  # `other` now waits for the GIL alone
            busy = sum(i * i for i in range(200000))  # holds the GIL all along
            self.assertFalse(ran.is_set(), "the control: pure Python gave the GIL away (%d)" % busy)
            frames = 0
            while not ran.is_set() and frames < 200:
                sim.step_frame()
                frames += 1
        finally:
            sys.setswitchinterval(interval)
            go.set()
            t.join()
        self.assertTrue(ran.is_set(), "no other thread ran during %d frames of stepping" % frames)

    def test_threads_stepping_one_simulation_take_turns(self):
        """Two threads step and read one Simulation whose body is driven by a Python callable (which
        needs the GIL while the other thread waits for the Simulation). Run in a subprocess, so a
        crash or a deadlock is this test's failure: every report's frame is distinct and the
        frames reached add up."""
        script = r"""
import json, sys, threading
sys.path.insert(0, sys.argv[1])
import invfem
from test_module import body_frame, sheet_scene
sim = invfem.Simulation(sheet_scene("body{N}.obj", 10), base_dir=sys.argv[2])
sim.drive_body("body", body_frame)
frames, errors = [], []
def work():
    try:
        for _ in range(4):
            frames.append(sim.step_frame()["frame"])
            assert sim.positions("sheet").shape == (81, 3)
            assert sim.surface("body")["vertices"].shape == (8, 3)
            assert sim.frame >= 1 and sim.time > 0
    except BaseException as e:
        errors.append(repr(e))
threads = [threading.Thread(target=work) for _ in range(2)]
for t in threads: t.start()
for t in threads: t.join()
print(json.dumps({"frame": sim.frame, "frames": sorted(frames), "errors": errors}))
"""
        done = subprocess.run([sys.executable, "-c", script, os.path.dirname(os.path.abspath(__file__)), self.dir],
                              capture_output=True, text=True, timeout=300)
        self.assertEqual(done.returncode, 0, "the process ended with %d: %s" % (done.returncode, done.stderr[-2000:]))
        result = json.loads(done.stdout.strip().splitlines()[-1])
        self.assertEqual(result["errors"], [])
        self.assertEqual(result["frame"], 8)
        self.assertEqual(result["frames"], list(range(1, 9)))

    def test_a_call_from_a_drive_body_source_into_its_simulation_raises(self):
        sim = self.simulation()

        def source(k):
            sim.positions("sheet")  # would wait for the step that calls this source
            return body_frame(k)

        with self.assertRaises(RuntimeError) as e:
            sim.drive_body("body", source)
        self.assertIn("its own calls", str(e.exception))

    def test_dict_values_are_converted_with_their_path_in_errors(self):
        def refused(change, *where, set=None):
            scene = copy.deepcopy(self.scene)
            change(scene)
            with self.assertRaises(ValueError) as e:
                invfem.Simulation(scene, base_dir=self.dir, set=set or {})
            for text in where:
                self.assertIn(text, str(e.exception))
            return str(e.exception)

        refused(lambda s: s.update(gravity=[0, float("nan"), 0]), "$.gravity[1]", "nan")
        refused(lambda s: s["cloths"][0]["material"].update(young=float("inf")), "$.cloths[0].material.young", "inf")
        refused(lambda s: s["cloths"][0]["material"].update(young=np.float32("-inf")), "$.cloths[0].material.young")
        refused(lambda s: s.update(name=b"sheet"), "$.name", "bytes")
        refused(lambda s: s["cloths"][0]["transform"].update(translate={0, 0.45}), "$.cloths[0].transform.translate", "set")
        refused(lambda s: s.update(fps=object()), "$.fps", "object")
        refused(lambda s: s.update(fps=np.complex128(25)), "$.fps", "complex")
        refused(lambda s: s.update(frames=2 ** 70), "$.frames", "64-bit")
        refused(lambda s: s["cloths"][0].update({1: "one"}), "$.cloths[0]", "key 1", "int")
        refused(lambda s: s["colliders"][0].update({"my key": float("nan")}), '$.colliders[0]["my key"]')
        refused(lambda s: s.update(loop=s), "$.loop", "contains itself")
        refused(lambda s: None, 'set["gravity"][1]', set={"gravity": [0, float("nan"), 0]})
        refused(lambda s: None, 'set["fps"]', "bytes", set={"fps": b"25"})
        refused(lambda s: None, "set", "key 3", set={3: 1})

    def test_numpy_scalars_in_a_dict_scene_are_the_same_numbers(self):
        scene = copy.deepcopy(self.scene)
        scene["frames"] = np.int64(5)
        scene["fps"] = np.int32(25)
        scene["cloths"][0]["grid"].update(width=np.float32(0.625), nx=np.uint8(8))
        scene["cloths"][0]["material"]["young"] = np.float64(2e5)
        scene["cloths"][0]["self_collision"] = np.True_
        scene["cloths"][0]["transform"]["translate"] = (0, np.float16(0.5), 0)
        plain = json.loads(json.dumps(self.scene))
        plain["frames"] = 5
        plain["cloths"][0]["grid"]["width"] = 0.625
        plain["cloths"][0]["self_collision"] = True
        plain["cloths"][0]["transform"]["translate"] = [0, 0.5, 0]
        numpy_sim = invfem.Simulation(scene, base_dir=self.dir, set={"solver.max_dt": np.float64(0.01)})
        plain_sim = invfem.Simulation(plain, base_dir=self.dir, set={"solver.max_dt": 0.01})
        self.assertEqual((numpy_sim.frames, numpy_sim.fps), (5, 25.0))
        numpy_sim.step_frame()
        plain_sim.step_frame()
        self.assertTrue(np.array_equal(numpy_sim.positions("sheet"), plain_sim.positions("sheet")))
        self.assertEqual(invfem.Simulation(self.scene, base_dir=self.dir, set={"frames": np.int64(3)}).frames, 3)

    def test_a_body_with_no_surface_says_so(self):
        sim = invfem.Simulation(os.path.join(SCENES, "cloth_drape.json"), quick=True)
        self.assertIn("ground", sim.bodies)
        for read in (sim.positions, sim.velocities, sim.surface):
            with self.assertRaises(ValueError) as e:
                read("ground")
            self.assertIn('"ground" is a kinematic body with no surface (an infinite plane)', str(e.exception))
        self.assertEqual(sim.positions("ball").shape[1], 3)  # an analytic body has a drawn surface
        with self.assertRaises(KeyError):
            sim.positions("floor")

    def test_a_scene_over_its_memory_limit_or_with_a_warning_under_strict_is_refused(self):
        big = {"cloths.0.grid.nx": 400, "cloths.0.grid.ny": 400}
        with self.assertRaises(ValueError) as e:
            invfem.Simulation(os.path.join(SCENES, "cloth_drape.json"), set=big, memory_limit="50M")
        self.assertIn("more than the limit of 50 MB", str(e.exception))
        self.assertIn("cloths[0].grid.nx", str(e.exception))
        with self.assertRaises(ValueError):
            invfem.Simulation(os.path.join(SCENES, "cloth_drape.json"), quick=True, memory_limit="12Q")
        through = json.loads(json.dumps(self.scene))
        through["cloths"][0]["transform"]["translate"] = [0, 0.2, 0]  # the sheet through the box at frame 0
        self.assertEqual(invfem.Simulation(through, base_dir=self.dir).frame, 0)  # a warning only
        with self.assertRaises(ValueError) as e:
            invfem.Simulation(through, base_dir=self.dir, strict=True)
        self.assertIn('"sheet" starts through body "body"', str(e.exception))

    def test_errors_are_python_exceptions(self):
        sim = self.simulation()
        with self.assertRaises(KeyError):
            sim.positions("nobody")
        with self.assertRaises(ValueError):
            sim.drive_body("sheet", body_frame)
        sim.set_body_frame("body", 0, body_frame(0))
        sim.set_body_frame("body", 1, np.zeros((5, 3)))  # frame 0 has 8 vertices: checked when used
        with self.assertRaises(ValueError) as e:
            sim.step_frame()
        self.assertIn("5 vertices", str(e.exception))
        with self.assertRaises(ValueError) as e:
            self.simulation().set_body_frame("body", 1, np.zeros((8, 2)))
        self.assertIn("(8, 2)", str(e.exception))
        with self.assertRaises(IndexError):
            sim.set_body_frame("body", 99, body_frame(0))

        def failing(k):
            raise ZeroDivisionError("from the callback")

        fresh = self.simulation()
        fresh.set_body_frame("body", 0, body_frame(0))
        with self.assertRaises(TypeError):
            fresh.drive_body("body", 5)  # not callable: the pushed frames stay in use
        with self.assertRaises(ZeroDivisionError):
            fresh.drive_body("body", failing)
        for k in range(3):  # pushed frames again after the failed callback
            fresh.set_body_frame("body", k, body_frame(k))
        self.assertEqual(fresh.step_frame()["frame"], 1)
        nan = self.simulation()
        with self.assertRaises(ValueError):
            nan.drive_body("body", lambda k: body_frame(k) * np.nan)
        with self.assertRaises(ValueError):
            nan.advance_to(-1.0)


if __name__ == "__main__":
    unittest.main()
