#!/usr/bin/python3
"""Checks `structmesh quality` against VTK's vtkMeshQuality (Verdict), element by element.

Usage: /usr/bin/python3 verdict_oracle.py STRUCTMESH WORKDIR

Builds quad and hex meshes with VTK (regular, jittered, sheared, with non-convex,
inverted and degenerate elements), writes them as uncompressed VTU (ASCII and raw
appended), makes one structured hex mesh with the gmsh command line (.msh 4.1), runs
`STRUCTMESH quality MESH -o OUT.vtu --json OUT.json --quiet` on each, and requires
for every element |ours - Verdict| <= 1e-6, where ours is the cell array
`scaled_jacobian` of OUT.vtu and Verdict's value is computed by vtkMeshQuality on
the original geometry (for .msh input, the coordinates parsed from the file).
Verdict returns VERDICT_DBL_MAX (1e30 in VTK 9.1) for a hex with a zero-length edge
or principal axis, where we write NaN: those match each other. The JSON summary's
element, inverted and invalid counts and min / max / mean must agree as well, and
the hexes' `corner_scaled_jacobian` is checked against the 8-corner minimum computed
here. Exit 0 when everything matches, 1 otherwise (naming the mesh, the element and
both values), 2 when the command cannot be run.

Planar quads follow our convention (+z reference normal), which equals Verdict's
principal-axes normal whenever a quad's vector area points to +z: every planar quad
here is built counter-clockwise (positive shoelace area, checked), including the
non-convex ones. The warped (non-planar) quad mesh uses Verdict's normal on both
sides, so its flipped quads must agree too.
"""

import json
import math
import os
import random
import shutil
import subprocess
import sys

import vtk

TOLERANCE = 1e-6
VERDICT_HUGE = 1e29  # Verdict's VERDICT_DBL_MAX is 1e30 in VTK 9.1 (DBL_MAX in some builds)
MAX_REPORTED = 10  # mismatches printed per mesh


# ---------------------------------------------------------------- mesh builders


def grid_points(nx, ny, nz, dx=1.0, dy=1.0, dz=1.0):
    """Structured points, x fastest; nz = None for a single z = 0 layer."""
    layers = [0] if nz is None else range(nz + 1)
    return [[i * dx, j * dy, k * dz] for k in layers for j in range(ny + 1) for i in range(nx + 1)]


def quad_grid_cells(nx, ny):
    def pid(i, j):
        return j * (nx + 1) + i

    return [(pid(i, j), pid(i + 1, j), pid(i + 1, j + 1), pid(i, j + 1)) for j in range(ny) for i in range(nx)]


def hex_grid_cells(nx, ny, nz):
    def pid(i, j, k):
        return (k * (ny + 1) + j) * (nx + 1) + i

    cells = []
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                cells.append((pid(i, j, k), pid(i + 1, j, k), pid(i + 1, j + 1, k), pid(i, j + 1, k),
                              pid(i, j, k + 1), pid(i + 1, j, k + 1), pid(i + 1, j + 1, k + 1), pid(i, j + 1, k + 1)))
    return cells


def interior_ids(nx, ny, nz=None):
    if nz is None:
        return [j * (nx + 1) + i for j in range(1, ny) for i in range(1, nx)]
    return [(k * (ny + 1) + j) * (nx + 1) + i for k in range(1, nz) for j in range(1, ny) for i in range(1, nx)]


def jitter(points, ids, amount, rng, dims=3):
    for p in ids:
        for d in range(dims):
            points[p][d] += rng.uniform(-amount, amount)


def add_cell(points, cells, corners):
    """Appends a cell with its own points (so it can be distorted alone)."""
    first = len(points)
    points.extend([list(c) for c in corners])
    cells.append(tuple(range(first, first + len(corners))))


def shoelace(points, cell):
    area = 0.0
    for a, b in zip(cell, cell[1:] + cell[:1]):
        area += points[a][0] * points[b][1] - points[b][0] * points[a][1]
    return 0.5 * area


def quad_meshes(rng):
    meshes = []

    points = grid_points(8, 6, None, 0.7, 1.3)
    meshes.append(("quad_regular", points, quad_grid_cells(8, 6)))

    points = grid_points(20, 15, None)
    jitter(points, interior_ids(20, 15), 0.3, rng, dims=2)
    meshes.append(("quad_jittered", points, quad_grid_cells(20, 15)))

    points = grid_points(12, 10, None)
    for p in points:  # a uniform shear and a varying one
        p[0] += 0.8 * p[1] + 0.4 * math.sin(0.7 * p[1])
        p[1] += 0.25 * math.sin(0.5 * p[0])
    meshes.append(("quad_sheared", points, quad_grid_cells(12, 10)))

    # Non-convex quads: interior vertices pushed past the diagonal of one of their
    # quads (an arrow with a reflex corner, Verdict < 0), plus degenerate quads kept
    # counter-clockwise: node 3 on node 2 (Verdict's collapsed quad = triangle) and a
    # zero-length edge 0-1 (Verdict gives 0).
    nx, ny = 10, 8
    points = grid_points(nx, ny, None)
    jitter(points, interior_ids(nx, ny), 0.1, rng, dims=2)
    cells = quad_grid_cells(nx, ny)
    for i, j in [(2, 2), (5, 3), (7, 6), (3, 6)]:
        p = points[j * (nx + 1) + i]
        p[0] += 0.65 * (1 if (i + j) % 2 else -1)
        p[1] += 0.65
    add_cell(points, cells, [(20, 0, 0), (21, 0, 0), (20.5, 0.8, 0), (20.5, 0.8, 0)])
    add_cell(points, cells, [(22, 0, 0), (24, 0, 0), (22, 0.5, 0), (22, 0.5, 0)])
    add_cell(points, cells, [(25, 0, 0), (25, 0, 0), (26, 1, 0), (25, 1, 0)])
    add_cell(points, cells, [(27, 0, 0), (29, 0, 0), (27.4, 0.3, 0), (27, 2, 0)])  # arrow
    meshes.append(("quad_nonconvex", points, cells))

    # A warped surface (not planar): Verdict's own normal on both sides, so twisted
    # and even flipped quads must agree.
    nx, ny = 10, 10
    points = grid_points(nx, ny, None, 0.5, 0.5)
    for p in points:
        p[2] = 0.6 * math.sin(p[0]) * math.cos(0.8 * p[1]) + 0.2 * p[0] * p[1]
    jitter(points, range(len(points)), 0.08, rng)
    cells = quad_grid_cells(nx, ny)
    for c in (5, 37, 71):
        q = cells[c]
        cells[c] = (q[0], q[3], q[2], q[1])
    meshes.append(("quad_warped", points, cells))

    for name, points, cells in meshes:
        if all(p[2] == points[0][2] for p in points):
            for c, cell in enumerate(cells):
                if shoelace(points, list(cell)) <= 0:
                    raise SystemExit(f"oracle bug: planar quad {c} of {name} is not counter-clockwise")
    return meshes


def unit_hex(origin, scale=1.0):
    ox, oy, oz = origin
    return [(ox + scale * x, oy + scale * y, oz + scale * z)
            for (x, y, z) in [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]]


def hex_meshes(rng):
    meshes = []

    points = grid_points(5, 4, 3, 1.0, 0.5, 2.0)
    meshes.append(("hex_regular", points, hex_grid_cells(5, 4, 3)))

    points = grid_points(6, 5, 4)
    jitter(points, range(len(points)), 0.25, rng)
    meshes.append(("hex_jittered", points, hex_grid_cells(6, 5, 4)))

    points = grid_points(5, 5, 5)
    for p in points:  # shear plus a twist about the z axis growing with height
        x, y, z = p
        a = 0.12 * z
        x, y = x - 2.5, y - 2.5
        p[0] = 2.5 + x * math.cos(a) - y * math.sin(a) + 0.6 * z
        p[1] = 2.5 + x * math.sin(a) + y * math.cos(a) + 0.3 * p[0]
    meshes.append(("hex_sheared", points, hex_grid_cells(5, 5, 5)))

    # A grid with interior vertices pushed far (several inverted hexes around each),
    # plus standalone hexes: one corner through the opposite face, a mirrored hex
    # (all corners -1), a repeated point and a flat hex (both invalid in Verdict).
    nx, ny, nz = 5, 4, 4
    points = grid_points(nx, ny, nz)
    jitter(points, range(len(points)), 0.1, rng)
    cells = hex_grid_cells(nx, ny, nz)
    for pid in interior_ids(nx, ny, nz)[1::5]:
        points[pid][0] += 1.3
        points[pid][2] -= 0.9
    through = unit_hex((10, 0, 0))
    through[6] = (10.5, 0.5, -0.5)
    add_cell(points, cells, through)
    add_cell(points, cells, [(x, y, -z) for (x, y, z) in unit_hex((12, 0, 0))])
    repeated = unit_hex((14, 0, 0))
    repeated[1] = repeated[0]
    add_cell(points, cells, repeated)
    flat = unit_hex((16, 0, 0))
    flat[4:] = flat[:4]
    add_cell(points, cells, flat)
    meshes.append(("hex_inverted", points, cells))
    return meshes


# ---------------------------------------------------------------- VTK side


def make_grid(points, cells, cell_type):
    vtk_points = vtk.vtkPoints()
    vtk_points.SetDataTypeToDouble()  # float32 points would change the geometry
    for p in points:
        vtk_points.InsertNextPoint(*p)
    grid = vtk.vtkUnstructuredGrid()
    grid.SetPoints(vtk_points)
    for cell in cells:
        grid.InsertNextCell(cell_type, len(cell), list(cell))
    return grid


def write_vtu(grid, path, mode):
    writer = vtk.vtkXMLUnstructuredGridWriter()
    writer.SetFileName(path)
    writer.SetInputData(grid)
    writer.SetCompressorTypeToNone()
    if mode == "ascii":
        writer.SetDataModeToAscii()
    else:
        writer.SetDataModeToAppended()
        writer.EncodeAppendedDataOff()
    if not writer.Write():
        raise SystemExit(f"VTK could not write {path}")


def read_vtu(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def verdict_scaled_jacobian(grid):
    quality = vtk.vtkMeshQuality()
    quality.SetInputData(grid)
    quality.SetQuadQualityMeasureToScaledJacobian()
    quality.SetHexQualityMeasureToScaledJacobian()
    quality.Update()
    values = quality.GetOutput().GetCellData().GetArray("Quality")
    return [values.GetValue(i) for i in range(values.GetNumberOfTuples())]


def corner_scaled_jacobian(corners):
    """The 8-corner minimum (no centre sample); None where Verdict's is invalid."""
    def sub(a, b):
        return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]

    def dot(a, b):
        return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]

    def cross(a, b):
        return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]

    def normalized_det(a, b, c):
        la, lb, lc = dot(a, a), dot(b, b), dot(c, c)
        if min(la, lb, lc) <= 1e-30:
            return None
        return dot(a, cross(b, c)) / math.sqrt(la * lb * lc)

    p = corners
    axes = [sub([p[1][i] + p[2][i] + p[5][i] + p[6][i] for i in range(3)],
                [p[0][i] + p[3][i] + p[4][i] + p[7][i] for i in range(3)]),
            sub([p[2][i] + p[3][i] + p[6][i] + p[7][i] for i in range(3)],
                [p[0][i] + p[1][i] + p[4][i] + p[5][i] for i in range(3)]),
            sub([p[4][i] + p[5][i] + p[6][i] + p[7][i] for i in range(3)],
                [p[0][i] + p[1][i] + p[2][i] + p[3][i] for i in range(3)])]
    if normalized_det(*axes) is None:
        return None
    corners_table = [(0, 1, 3, 4), (1, 2, 0, 5), (2, 3, 1, 6), (3, 0, 2, 7),
                     (4, 7, 5, 0), (5, 4, 6, 1), (6, 5, 7, 2), (7, 6, 4, 3)]
    values = [normalized_det(sub(p[i], p[c]), sub(p[j], p[c]), sub(p[k], p[c])) for c, i, j, k in corners_table]
    return None if None in values else min(values)


# ---------------------------------------------------------------- gmsh side

GEO = """// A twisted, tapered block with one curved side, meshed as a structured hex block:
// transfinite curves (with progressions), surfaces and volume, recombined.
SetFactory("Built-in");
Point(1) = {0, 0, 0};
Point(2) = {3, 0, 0};
Point(3) = {3.2, 2, 0};
Point(4) = {0, 2, 0};
Point(5) = {0.4, 0.3, 2};
Point(6) = {2.9, -0.2, 2.3};
Point(7) = {3.0, 1.7, 2};
Point(8) = {0.2, 1.7, 2};
Point(9) = {1.6, 6, 0};      // centre of the curved bottom side 3-4 (bulging inward)
Point(10) = {1.6, 6, 2};     // centre of the curved top side 7-8
Line(1) = {1, 2};
Line(2) = {2, 3};
Circle(3) = {3, 9, 4};
Line(4) = {4, 1};
Line(5) = {5, 6};
Line(6) = {6, 7};
Circle(7) = {7, 10, 8};
Line(8) = {8, 5};
Line(9) = {1, 5};
Line(10) = {2, 6};
Line(11) = {3, 7};
Line(12) = {4, 8};
Curve Loop(1) = {1, 2, 3, 4};
Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, 8};
Surface(2) = {2};
Curve Loop(3) = {1, 10, -5, -9};
Surface(3) = {3};
Curve Loop(4) = {2, 11, -6, -10};
Surface(4) = {4};
Curve Loop(5) = {3, 12, -7, -11};
Surface(5) = {5};
Curve Loop(6) = {4, 9, -8, -12};
Surface(6) = {6};
Surface Loop(1) = {1, 2, 3, 4, 5, 6};
Volume(1) = {1};
Transfinite Curve {1, -3, 5, -7} = 9 Using Progression 1.15;
Transfinite Curve {2, -4, 6, -8} = 7 Using Progression 0.85;
Transfinite Curve {9, 10, 11, 12} = 6 Using Progression 1.3;
Transfinite Surface {1, 2, 3, 4, 5, 6};
Recombine Surface {1, 2, 3, 4, 5, 6};
Transfinite Volume {1} = {1, 2, 3, 4, 5, 6, 7, 8};
"""


def parse_msh41_hexes(path):
    """Nodes and 8-node hexes (type 5) of an ASCII .msh 4.1 file, hexes in file order."""
    with open(path) as f:
        lines = [line.strip() for line in f]
    at = lines.index("$Nodes") + 1
    blocks = int(lines[at].split()[0])
    at += 1
    coordinates = {}
    for _ in range(blocks):
        _dim, _entity, parametric, count = (int(v) for v in lines[at].split())
        if parametric:
            raise SystemExit(f"{path}: parametric nodes not expected")
        tags = [int(lines[at + 1 + i]) for i in range(count)]
        for i, tag in enumerate(tags):
            coordinates[tag] = [float(v) for v in lines[at + 1 + count + i].split()[:3]]
        at += 1 + 2 * count
    at = lines.index("$Elements") + 1
    blocks = int(lines[at].split()[0])
    at += 1
    hexes = []
    for _ in range(blocks):
        _dim, _entity, element_type, count = (int(v) for v in lines[at].split())
        for i in range(count):
            fields = [int(v) for v in lines[at + 1 + i].split()]
            if element_type == 5:
                hexes.append(fields[1:9])
        at += 1 + count
    tags = sorted(coordinates)
    index = {tag: i for i, tag in enumerate(tags)}
    points = [coordinates[tag] for tag in tags]
    return points, [tuple(index[t] for t in h) for h in hexes]


def gmsh_mesh(work):
    gmsh = shutil.which("gmsh")
    if gmsh is None:
        return None
    geo = os.path.join(work, "box.geo")
    msh = os.path.join(work, "gmsh_hex.msh")
    with open(geo, "w") as f:
        f.write(GEO)
    run = subprocess.run([gmsh, geo, "-3", "-format", "msh41", "-o", msh], capture_output=True, text=True)
    if run.returncode != 0 or not os.path.exists(msh):
        raise SystemExit(f"gmsh failed ({run.returncode}):\n{run.stdout[-2000:]}\n{run.stderr[-2000:]}")
    points, cells = parse_msh41_hexes(msh)
    if not cells:
        raise SystemExit(f"{msh}: gmsh produced no hexahedra")
    return msh, points, cells


# ---------------------------------------------------------------- comparison


class Tally:
    def __init__(self):
        self.passed = 0
        self.failed = 0

    def check(self, ok, message):
        if ok:
            self.passed += 1
        else:
            self.failed += 1
            print("  MISMATCH " + message)
        return ok


def same_value(ours, verdict):
    if verdict >= VERDICT_HUGE:
        return math.isnan(ours)
    return not math.isnan(ours) and abs(ours - verdict) <= TOLERANCE


def compare(name, mesh_path, kind, points, cells, structmesh, work, tally):
    out_vtu = os.path.join(work, name + ".out.vtu")
    out_json = os.path.join(work, name + ".out.json")
    command = [structmesh, "quality", mesh_path, "-o", out_vtu, "--json", out_json, "--quiet"]
    run = subprocess.run(command, capture_output=True, text=True)
    if not tally.check(run.returncode == 0, f"{name}: exit {run.returncode} from {' '.join(command)}\n"
                       f"{run.stdout[-1500:]}{run.stderr[-1500:]}"):
        return
    cell_type = vtk.VTK_QUAD if kind == "quad" else vtk.VTK_HEXAHEDRON
    verdict = verdict_scaled_jacobian(make_grid(points, cells, cell_type))
    output = read_vtu(out_vtu)
    ours = output.GetCellData().GetArray("scaled_jacobian")
    if not tally.check(ours is not None, f"{name}: {out_vtu} has no cell array 'scaled_jacobian'"):
        return
    if not tally.check(output.GetNumberOfCells() == len(cells) and ours.GetNumberOfTuples() == len(cells),
                       f"{name}: {output.GetNumberOfCells()} cells / {ours.GetNumberOfTuples()} values "
                       f"written, {len(cells)} in the input"):
        return
    corner = output.GetCellData().GetArray("corner_scaled_jacobian") if kind == "hex" else None
    if kind == "hex" and not tally.check(corner is not None, f"{name}: no cell array 'corner_scaled_jacobian'"):
        return

    reported = 0
    element_failures = 0
    for c, cell in enumerate(cells):
        # The written cell must be the input cell: same corner coordinates, same order.
        written = output.GetCell(c)
        geometry_ok = written.GetNumberOfPoints() == len(cell) and all(
            max(abs(a - b) for a, b in zip(written.GetPoints().GetPoint(k), points[cell[k]])) <= 1e-12 *
            (1 + max(abs(v) for v in points[cell[k]])) for k in range(len(cell)))
        value = ours.GetValue(c)
        ok = geometry_ok and same_value(value, verdict[c])
        if kind == "hex":
            expected = corner_scaled_jacobian([points[i] for i in cell])
            corner_value = corner.GetValue(c)
            ok = ok and (math.isnan(corner_value) if expected is None else abs(corner_value - expected) <= TOLERANCE)
        if ok:
            tally.passed += 1
            continue
        tally.failed += 1
        element_failures += 1
        if reported < MAX_REPORTED:
            reported += 1
            detail = f"ours {value!r}, Verdict {verdict[c]!r}"
            if kind == "hex":
                detail += f"; corners ours {corner.GetValue(c)!r}, expected {expected!r}"
            if not geometry_ok:
                detail += "; the written cell's corners differ from the input's"
            print(f"  MISMATCH {name}: element {c}: {detail}")

    with open(out_json) as f:
        report = json.load(f)
    valid = [v for v in verdict if v < VERDICT_HUGE]
    expected_summary = {
        "kind": kind,
        "elements": len(cells),
        "inverted": sum(1 for v in valid if v <= 0),
        "invalid": len(verdict) - len(valid),
    }
    for key, want in expected_summary.items():
        tally.check(report.get(key) == want, f"{name}: JSON {key} = {report.get(key)!r}, expected {want!r}")
    stats = report.get("scaled_jacobian", {})
    mean = sum(valid) / len(valid) if valid else 0.0
    for key, want in (("min", min(valid, default=0.0)), ("max", max(valid, default=0.0)), ("mean", mean)):
        got = stats.get(key)
        tally.check(isinstance(got, (int, float)) and abs(got - want) <= TOLERANCE,
                    f"{name}: JSON scaled_jacobian.{key} = {got!r}, Verdict {want!r}")
    negative = sum(1 for v in valid if v <= 0)
    status = "ok" if element_failures == 0 else f"{element_failures} elements differ"
    print(f"{name}: {len(cells)} {kind}s, Verdict min {min(valid, default=float('nan')):.6f}, "
          f"{negative} inverted, {len(verdict) - len(valid)} invalid: {status}")


def main():
    if len(sys.argv) != 3:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    structmesh, work = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    if not os.access(structmesh, os.X_OK):
        print(f"verdict_oracle: {structmesh} is not an executable", file=sys.stderr)
        return 2
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    rng = random.Random(20150501)
    tally = Tally()

    cases = [("quad", m) for m in quad_meshes(rng)] + [("hex", m) for m in hex_meshes(rng)]
    for kind, (name, points, cells) in cases:
        grid = make_grid(points, cells, vtk.VTK_QUAD if kind == "quad" else vtk.VTK_HEXAHEDRON)
        for mode in ("ascii", "raw"):
            path = os.path.join(work, f"{name}_{mode}.vtu")
            write_vtu(grid, path, mode)
            compare(f"{name}_{mode}", path, kind, points, cells, structmesh, work, tally)

    gmsh = gmsh_mesh(work)
    if gmsh is None:
        # The Gmsh-made mesh is part of the acceptance test: a missing gmsh is a failure.
        print("gmsh_hex: FAILED: no gmsh on PATH (scripts/install-deps.sh installs it)")
        tally.failed += 1
    else:
        path, points, cells = gmsh
        compare("gmsh_hex", path, "hex", points, cells, structmesh, work, tally)

    print(f"{tally.passed} passed, {tally.failed} failed")
    return 0 if tally.failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
