#!/usr/bin/python3
"""Write the Gmsh meshes of a surface and a curve each in two physical groups (tests/check_files.py), with
Gmsh's Python API (Debian's python3-gmsh; CI reads the committed files and never needs Gmsh):

    /usr/bin/python3 tests/data/make_two_groups.py   # rewrites tests/data/scenes/two_groups_v22.msh, _v41.msh

The thick tube 100 <= r <= 200, 0 <= z <= 25 (mm) as 8 x 2 recombined quadrangles. Physical groups: the
surface in "steel" and in "all"; the bore r = 100 in "bore" and in "inner"; the ends "bottom" (z = 0) and
"top" (z = 25); the outside r = 200 in "outside". Gmsh's MSH 2.2 writer gives every cell and edge once per
group it is in (so the cells come twice); its MSH 4.1 writer gives the groups of each entity once.
"""
import pathlib

import gmsh

here = pathlib.Path(__file__).resolve().parent

gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.add("two_groups")
geo = gmsh.model.geo
p = [geo.addPoint(r, z, 0, 10.0) for r, z in [(100, 0), (200, 0), (200, 25), (100, 25)]]
bottom, outside, top, bore = (geo.addLine(p[k], p[(k + 1) % 4]) for k in range(4))
surface = geo.addPlaneSurface([geo.addCurveLoop([bottom, outside, top, bore])])
geo.synchronize()
mesh = gmsh.model.mesh
for line in (bottom, top):
    mesh.setTransfiniteCurve(line, 9)
for line in (outside, bore):
    mesh.setTransfiniteCurve(line, 3)
mesh.setTransfiniteSurface(surface)
mesh.setRecombine(2, surface)
for dim, tags, name in [(2, [surface], "steel"), (2, [surface], "all"), (1, [bore], "bore"), (1, [bore], "inner"),
                        (1, [bottom], "bottom"), (1, [top], "top"), (1, [outside], "outside")]:
    gmsh.model.setPhysicalName(dim, gmsh.model.addPhysicalGroup(dim, tags), name)
mesh.generate(2)
for version, name in [(2.2, "two_groups_v22.msh"), (4.1, "two_groups_v41.msh")]:
    gmsh.option.setNumber("Mesh.MshFileVersion", version)
    gmsh.write(str(here / "scenes" / name))
    print("wrote", name)
# Mesh.SaveAll = 1: MSH 2.2 then writes every element once with physical tag 0 (the names stay).
gmsh.option.setNumber("Mesh.MshFileVersion", 2.2)
gmsh.option.setNumber("Mesh.SaveAll", 1)
gmsh.write(str(here / "scenes" / "two_groups_v22_saveall.msh"))
print("wrote two_groups_v22_saveall.msh")
gmsh.finalize()
