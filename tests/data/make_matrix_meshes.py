#!/usr/bin/python3
"""Mesh the two bodies of tests/check_matrix.py with Gmsh (python3-gmsh), so that its Gmsh scenes run on
meshes Gmsh made: structured (transfinite) quadrangles whose nodes lie where the I-J generator puts the
deck's and the grid scene's, so the three inputs can be compared node by node.

    /usr/bin/python3 tests/data/make_matrix_meshes.py    # rewrites tests/data/matrix/{tube,fit}.msh

  tube.msh  10 <= r <= 20, 0 <= z <= 10, 4 x 4 cells: surface "tube"; curves "bottom", "top", "bore",
            "outside"
  fit.msh   a shaft 10..15 and a hub 15.001..20 (2 x 4 cells each) with one column of soft cells "gap"
            between them: surfaces "shaft", "gap", "hub"; curves "bottom", "top" (every z = 10 side),
            "top_shaft", "top_hub", "bore", "outside", "shaft_face" (r = 15), "hub_face" (r = 15.001)
"""
import pathlib

import gmsh

here = pathlib.Path(__file__).resolve().parent / "matrix"
H, NZ = 10.0, 4


def strip(rs, cells):
    """Transfinite rectangles rs[k]..rs[k + 1] x 0..H with cells[k] cells across, side by side and sharing
    their vertical sides (so the soft column's corners are the faces' nodes, as in a deck); returns the
    surfaces and, per rectangle, its sides (bottom, right, top, left)."""
    geo = gmsh.model.geo
    low = [geo.addPoint(r, 0, 0) for r in rs]
    high = [geo.addPoint(r, H, 0) for r in rs]
    verticals = [geo.addLine(low[k], high[k]) for k in range(len(rs))]
    surfaces, sides = [], []
    for k in range(len(rs) - 1):
        bottom, top = geo.addLine(low[k], low[k + 1]), geo.addLine(high[k + 1], high[k])
        loop = geo.addCurveLoop([bottom, verticals[k + 1], top, -verticals[k]])
        surfaces.append(geo.addPlaneSurface([loop]))
        for line in (bottom, top):
            geo.mesh.setTransfiniteCurve(line, cells[k] + 1)
        geo.mesh.setTransfiniteSurface(surfaces[-1])
        geo.mesh.setRecombine(2, surfaces[-1])
        sides.append((bottom, verticals[k + 1], top, verticals[k]))
    for line in verticals:
        geo.mesh.setTransfiniteCurve(line, NZ + 1)
    return surfaces, sides


def write(name, groups_2d, groups_1d):
    gmsh.model.geo.synchronize()
    for dim, groups in ((2, groups_2d), (1, groups_1d)):
        for group, tags in groups.items():
            gmsh.model.setPhysicalName(dim, gmsh.model.addPhysicalGroup(dim, tags), group)
    gmsh.model.mesh.generate(2)
    gmsh.write(str(here / name))
    gmsh.clear()


gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
here.mkdir(exist_ok=True)
(tube,), ((bottom, outside, top, bore),) = strip([10.0, 20.0], [4])
write("tube.msh", {"tube": [tube]}, {"bottom": [bottom], "top": [top], "bore": [bore], "outside": [outside]})
(shaft, gap, hub), (s, g, h) = strip([10.0, 15.0, 15.001, 20.0], [2, 1, 2])
write("fit.msh", {"shaft": [shaft], "gap": [gap], "hub": [hub]},
      {"bottom": [s[0], g[0], h[0]], "top": [s[2], g[2], h[2]], "top_shaft": [s[2]], "top_hub": [h[2]],
       "bore": [s[3]], "outside": [h[1]], "shaft_face": [s[1]], "hub_face": [h[3]]})
gmsh.finalize()
