#!/usr/bin/env python3
"""Loads tocdlab's .vtu and .pvd files with VTK's own XML reader (Debian python3-vtk9).

  check_vtu.py pair ASCII.vtu BINARY.vtu MAX_RATIO
      both load; same points, cells, array names, sizes and values (to the 9 significant
      digits ASCII keeps); BINARY's size below MAX_RATIO x ASCII's
  check_vtu.py pvd SERIES.pvd TIMESTEP,TIMESTEP,...
      the collection lists these timesteps in order and every file it names loads
  check_vtu.py fe FE.vtu THICKNESS_MM DISPLACEMENT_MM
      points are the reference (undeformed) coordinates; points + displacement put the top
      node on the axis at the pin's depth
Exits 1 with a message on stderr at the first failed check.
"""
import os
import sys
import xml.etree.ElementTree as ET

from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader


def fail(message):
    print(f"check_vtu: {message}", file=sys.stderr)
    sys.exit(1)


def load(path):
    reader = vtkXMLUnstructuredGridReader()
    errors = []
    reader.AddObserver(vtkCommand.ErrorEvent, lambda *_: errors.append("error"))
    reader.GetExecutive().AddObserver(vtkCommand.ErrorEvent, lambda *_: errors.append("error"))
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    if errors or grid is None or grid.GetNumberOfCells() == 0:
        fail(f"{path}: VTK could not read it")
    return grid


def values(array):
    n, c = array.GetNumberOfTuples(), array.GetNumberOfComponents()
    return [array.GetComponent(i, k) for i in range(n) for k in range(c)]


def same(a, b, what):
    if len(a) != len(b):
        fail(f"{what}: {len(a)} values in ASCII, {len(b)} in binary")
    for i, (x, y) in enumerate(zip(a, b)):
        if abs(x - y) > 5e-9 * abs(y):
            fail(f"{what}[{i}]: ASCII {x!r}, binary {y!r}")


def arrays(data):
    return {data.GetArrayName(i): data.GetArray(i) for i in range(data.GetNumberOfArrays())}


def check_pair(ascii_path, binary_path, max_ratio):
    a, b = load(ascii_path), load(binary_path)
    if (a.GetNumberOfPoints(), a.GetNumberOfCells()) != (b.GetNumberOfPoints(), b.GetNumberOfCells()):
        fail("point or cell counts differ")
    same(values(a.GetPoints().GetData()), values(b.GetPoints().GetData()), "points")
    same(values(a.GetCells().GetConnectivityArray()), values(b.GetCells().GetConnectivityArray()),
         "connectivity")
    same(values(a.GetCellTypesArray()), values(b.GetCellTypesArray()), "types")
    for kind, da, db in (("point", a.GetPointData(), b.GetPointData()),
                         ("cell", a.GetCellData(), b.GetCellData())):
        xa, xb = arrays(da), arrays(db)
        if sorted(xa) != sorted(xb):
            fail(f"{kind} arrays: ASCII {sorted(xa)}, binary {sorted(xb)}")
        for name in xa:
            if xa[name].GetNumberOfComponents() != xb[name].GetNumberOfComponents():
                fail(f"{kind} array {name}: components differ")
            same(values(xa[name]), values(xb[name]), f"{kind} array {name}")
    sa, sb = os.path.getsize(ascii_path), os.path.getsize(binary_path)
    print(f"{os.path.basename(binary_path)}: ASCII {sa} bytes, binary {sb} bytes, ratio {sb / sa:.3f}, "
          f"{b.GetNumberOfCells()} cells")
    if not sb < max_ratio * sa:
        fail(f"binary is {sb / sa:.3f} of the ASCII size, not under {max_ratio}")


def check_pvd(pvd_path, timesteps):
    root = ET.parse(pvd_path).getroot()
    if root.get("type") != "Collection":
        fail(f"{pvd_path}: not a VTK collection")
    sets = root.findall("./Collection/DataSet")
    got = [float(s.get("timestep")) for s in sets]
    if got != timesteps:
        fail(f"{pvd_path}: timesteps {got}, expected {timesteps}")
    for s in sets:
        path = os.path.join(os.path.dirname(pvd_path), s.get("file"))
        print(f"{pvd_path}: timestep {s.get('timestep')} -> {s.get('file')}, "
              f"{load(path).GetNumberOfCells()} cells")


def check_fe(path, thickness, displacement):
    grid = load(path)
    u = grid.GetPointData().GetArray("displacement")
    if u is None or u.GetNumberOfComponents() != 3:
        fail("no 3-component point array 'displacement'")
    if grid.GetPointData().GetVectors() is None or grid.GetPointData().GetVectors().GetName() != "displacement":
        fail("'displacement' is not the active vectors (Warp By Vector picks the active vectors)")
    points = grid.GetPoints()
    top = [i for i in range(grid.GetNumberOfPoints()) if abs(points.GetPoint(i)[1] - thickness) < 1e-9]
    bottom = [i for i in range(grid.GetNumberOfPoints()) if abs(points.GetPoint(i)[1]) < 1e-12]
    if not top or not bottom:
        fail("no nodes at the reference top (z = thickness) or bottom (z = 0)")
    zs = [points.GetPoint(i)[1] for i in range(grid.GetNumberOfPoints())]
    if min(zs) < -1e-12 or max(zs) > thickness + 1e-9:
        fail(f"points span z {min(zs)}..{max(zs)}, outside the undeformed slab 0..{thickness}")
    for i in bottom:  # bonded to the slide: no motion
        if max(abs(u.GetComponent(i, k)) for k in range(3)) > 1e-12:
            fail(f"bottom node {i} moves by {u.GetTuple3(i)}")
    axis = min(top, key=lambda i: abs(points.GetPoint(i)[0]))
    depth = thickness - (points.GetPoint(axis)[1] + u.GetComponent(axis, 1))
    print(f"{path}: {len(top)} top nodes at z = {thickness}, warped axis node depth {depth:.6f} mm")
    if abs(depth - displacement) > 0.01:
        fail(f"warped top node on the axis is {depth} mm deep, the pin is {displacement} mm in")


def main(argv):
    if len(argv) == 5 and argv[1] == "pair":
        check_pair(argv[2], argv[3], float(argv[4]))
    elif len(argv) == 4 and argv[1] == "pvd":
        check_pvd(argv[2], [float(t) for t in argv[3].split(",")])
    elif len(argv) == 5 and argv[1] == "fe":
        check_fe(argv[2], float(argv[3]), float(argv[4]))
    else:
        fail(__doc__)


if __name__ == "__main__":
    main(sys.argv)
