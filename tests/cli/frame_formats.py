"""frame_formats.sh's readers of a run's frames, by tools nobody here wrote where they exist.

  frame_formats.py panels OUT NAME   the USD layer of NAME holds its OBJ frame's `g` panels as
                                     GeomSubsets (a structural check; plain python3)
  frame_formats.py vtk OUT...        VTK reads every .pvd entry of each run folder OUT and finds the
                                     run's values (python3's vtk module, Debian python3-vtk9)
  frame_formats.py pxr OUT NAME      USD reads NAME's panels (the pxr module, where installed)

Each mode exits 1 with a message on the first mismatch."""
import csv
import glob
import os
import re
import sys


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def check(cond, msg):
    if not cond:
        fail(msg)


def usd_identifier(name):
    """usd_identifier in usd_writer.hpp: [A-Za-z0-9_] kept, others '_', a leading digit prefixed."""
    ident = re.sub(r"[^A-Za-z0-9_]", "_", name)
    return "_" + ident if not ident or ident[0].isdigit() else ident


def read_obj(path):
    """Vertices, faces (0-based) and each `g` panel's faces, in file order."""
    vertices, faces, panels, panel = [], [], {}, None
    for line in open(path):
        word = line.split()
        if not word:
            continue
        if word[0] == "v":
            vertices.append([float(c) for c in word[1:4]])
        elif word[0] == "g":
            panel = line[2:].strip()
        elif word[0] == "f":
            if panel is not None:
                panels.setdefault(panel, []).append(len(faces))
            faces.append([int(c.split("/")[0]) - 1 for c in word[1:4]])
    return vertices, faces, panels


def usda_velocities(path, frame):
    """The velocities sample of `frame` in a layer usd_writer wrote (one line a sample)."""
    text = open(path).read()
    block = text[text.index("vector3f[] velocities.timeSamples = {"):]
    line = re.search(r"^\s*%d: \[(.*)\],$" % frame, block, re.M).group(1)
    return [[float(c) for c in t.split(",")] for t in re.findall(r"\(([^)]*)\)", line)]


def check_panels(out, name):
    _, faces, panels = read_obj(os.path.join(out, "frames", name, "0000.obj"))
    check(len(panels) > 1, f"{name}'s OBJ frame has {len(panels)} panels")
    text = open(os.path.join(out, "frames", name + ".usda")).read()
    subsets = re.findall(r'def GeomSubset "([^"]*)"\s*\{([^}]*)\}', text)
    check(len(subsets) == len(panels),
          f"{name}.usda has {len(subsets)} GeomSubsets for {len(panels)} panels")
    covered = 0
    for sub, body in subsets:
        check('uniform token elementType = "face"' in body, f"{name}.usda: subset {sub} is not of faces")
        check('uniform token familyName = "panels"' in body, f"{name}.usda: subset {sub} is not in the panels family")
        indices = [int(i) for i in re.search(r"int\[\] indices = \[([^\]]*)\]", body).group(1).split(",")]
        match = [p for p in panels if usd_identifier(p) == sub]
        check(len(match) == 1, f"{name}.usda: subset {sub} names no OBJ panel ({sorted(panels)})")
        check(indices == panels[match[0]], f"{name}.usda: subset {sub} has other faces than the OBJ's g {match[0]}")
        covered += len(indices)
    kind = "partition" if covered == len(faces) else "nonOverlapping"
    check(f'uniform token subsetFamily:panels:familyType = "{kind}"' in text, f"{name}.usda: family type is not {kind}")
    # The subsets are children of the mesh prim: after its attributes, inside its braces.
    mesh = text.index('def Mesh "mesh"')
    check(mesh < text.index("def GeomSubset") and text.rstrip().endswith("}\n    }\n}"),
          f"{name}.usda: subsets outside the mesh")
    print(f"{name}.usda: {len(subsets)} panels as GeomSubsets ({kind}), faces as the OBJ's g groups")


def close(a, b, rel):
    return abs(a - b) <= rel * max(1.0, abs(a), abs(b))


def printed(p):
    """A row of exact values as the OBJ and USD writers print them (9 significant digits)."""
    return [float("%.9g" % c) for c in p]


def check_vtk(outs):
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy

    for out in outs:
        energies = list(csv.DictReader(open(os.path.join(out, "energies.csv"))))
        for pvd in sorted(glob.glob(os.path.join(out, "*.pvd"))):
            name = os.path.basename(pvd)[:-4]
            layer = os.path.join(out, "frames", name + ".usda")
            for k, entry in enumerate(re.findall(r'file="([^"]*)"', open(pvd).read())):
                where = f"{os.path.basename(out)}/{entry}"
                data = open(os.path.join(out, entry), "rb").read(4096)
                check(b'format="appended"' in data and b'compressor="vtkZLibDataCompressor"' in data,
                      f"{where} is not binary and compressed")
                r = vtk.vtkXMLUnstructuredGridReader()
                r.SetFileName(os.path.join(out, entry))
                r.Update()
                check(r.GetErrorCode() == 0, f"VTK cannot read {where}")
                g = r.GetOutput()
                x = vtk_to_numpy(g.GetPoints().GetData()).tolist()
                cells = vtk_to_numpy(g.GetCells().GetConnectivityArray()).tolist()
                offsets = vtk_to_numpy(g.GetCells().GetOffsetsArray()).tolist()
                corners = offsets[1] - offsets[0] if len(offsets) > 1 else 0
                check(offsets == list(range(0, len(cells) + 1, corners)), f"{where}: cells of mixed sizes")
                vertices, faces, _ = read_obj(os.path.join(out, "frames", name, "%04d.obj" % k))
                velocity = g.GetPointData().GetArray("velocity")
                velocity = vtk_to_numpy(velocity).tolist() if velocity is not None else None
                if corners == 3:  # a surface: its VTU points and triangles are its OBJ frame's
                    check(len(x) == len(vertices) and len(cells) == 3 * len(faces),
                          f"{where}: counts differ from the OBJ frame")
                    check([printed(p) for p in x] == vertices, f"{where}: points differ from the OBJ frame")
                    check(cells == [i for f in faces for i in f], f"{where}: triangles differ from the OBJ frame")
                    if velocity is not None:
                        check([printed(v) for v in velocity] == usda_velocities(layer, k),
                              f"{where}: velocities differ from the USD layer's")
                else:  # a solid: det F and inverted flags as energies.csv counts them
                    check(corners == 4 and g.GetCellType(0) == 10, f"{where}: not tets")
                    det = vtk_to_numpy(g.GetCellData().GetArray("det_F")).tolist()
                    inverted = vtk_to_numpy(g.GetCellData().GetArray("inverted")).tolist()
                    check(len(det) == len(inverted) == g.GetNumberOfCells(), f"{where}: cell data lengths")
                    check(all((d < 0) == (i == 1) for d, i in zip(det, inverted)), f"{where}: inverted flags")
                    row = energies[k]
                    check(int(row["inverted"]) == sum(inverted) and int(row["elements"]) == len(det),
                          f"{where}: {sum(inverted)} of {len(det)} inverted, energies.csv: {row['inverted']}")
                    check(close(min(det), float(row["min_det_F"]), 1e-8),
                          f"{where}: min det F {min(det)}, energies.csv: {row['min_det_F']}")
                    # Its boundary's vertices are nodes of the tet mesh, moving as the USD layer says.
                    node = {tuple(printed(p)): i for i, p in enumerate(x)}
                    surface_v = usda_velocities(layer, k)
                    check(len(surface_v) == len(vertices),
                          f"{where}: the USD layer has {len(surface_v)} velocities for {len(vertices)} vertices")
                    for s, v in enumerate(vertices):
                        i = node.get(tuple(v))
                        check(i is not None, f"{where}: OBJ vertex {s} is no node")
                        check(printed(velocity[i]) == surface_v[s],
                              f"{where}: node {i}'s velocity differs from the USD layer's")
            print(f"VTK read {os.path.basename(out)}/{name}.pvd")


def check_pxr(out, name):
    from pxr import Usd, UsdGeom

    _, faces, panels = read_obj(os.path.join(out, "frames", name, "0000.obj"))
    stage = Usd.Stage.Open(os.path.join(out, "frames", name + ".usda"))
    mesh = UsdGeom.Mesh(stage.GetDefaultPrim().GetChild("mesh"))
    subsets = UsdGeom.Subset.GetGeomSubsets(mesh, "face", "panels")
    check(len(subsets) == len(panels), f"USD finds {len(subsets)} panels, the OBJ has {len(panels)}")
    valid, why = UsdGeom.Subset.ValidateFamily(mesh, "face", "panels")
    check(valid, f"USD: the panels family is not valid: {why}")
    for s in subsets:
        match = [p for p in panels if usd_identifier(p) == s.GetPrim().GetName()]
        check(len(match) == 1 and list(s.GetIndicesAttr().Get()) == panels[match[0]],
              f"USD: subset {s.GetPrim().GetName()} has other faces than the OBJ's panel")
    print(f"USD read {name}'s {len(subsets)} panels")


if __name__ == "__main__":
    mode, args = sys.argv[1], sys.argv[2:]
    {"panels": lambda: check_panels(*args), "vtk": lambda: check_vtk(args), "pxr": lambda: check_pxr(*args)}[mode]()
