#!/usr/bin/python3
"""Write the unstructured Lame-tube meshes of tests/check_estimate.py and tests/check_quadratic.py with Gmsh's
Python API (Debian's python3-gmsh; CI reads the committed files and never needs Gmsh):

    /usr/bin/python3 tests/data/make_estimate_meshes.py   # rewrites tests/data/scenes/lame_*_h*.msh

The meridian section 100 <= r <= 200, 0 <= z <= 50 of a thick tube, meshed by Gmsh's default 2-D algorithm
(MSH 4.1):
  * order 1, at mesh sizes H = 20, 10 and 5, each half the last: triangles (lame_tri_hH.msh) and
    quadrangles recombined from them (lame_quad_hH.msh);
  * order 2 (Mesh.ElementOrder = 2), at H = 25, 12.5 and 6.25: 6-node triangles (lame_tri6_hH.msh) and
    8-node quadrangles (Mesh.SecondOrderIncomplete = 1: lame_quad8_hH.msh); at H = 25 also Gmsh's default
    9-node quadrangles (lame_quad9_h25.msh, the same mesh with a centre node in each quadrangle).
Physical groups: surface "steel"; curves "bore" (r = 100), "bottom" (z = 0), "top" (z = 50), "outer" (r = 200).
"""
import pathlib

import gmsh

here = pathlib.Path(__file__).resolve().parent


def lame_mesh(name, h, quadrangles, order=1, incomplete=True):
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add(name)
    geo = gmsh.model.geo
    corners = [geo.addPoint(r, z, 0, h) for r, z in ((100, 0), (200, 0), (200, 50), (100, 50))]
    bottom, outer, top, bore = (geo.addLine(corners[k], corners[(k + 1) % 4]) for k in range(4))
    surface = geo.addPlaneSurface([geo.addCurveLoop([bottom, outer, top, bore])])
    geo.synchronize()
    if quadrangles:
        gmsh.model.mesh.setRecombine(2, surface)
    for dim, tags, group in [(2, [surface], "steel"), (1, [bore], "bore"), (1, [bottom], "bottom"),
                             (1, [top], "top"), (1, [outer], "outer")]:
        gmsh.model.setPhysicalName(dim, gmsh.model.addPhysicalGroup(dim, tags), group)
    gmsh.model.mesh.generate(2)
    if order == 2:
        gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 1 if incomplete else 0)
        gmsh.model.mesh.setOrder(2)
    gmsh.write(str(here / "scenes" / f"{name}.msh"))
    types, elements, _ = gmsh.model.mesh.getElements(2)
    print(name, {gmsh.model.mesh.getElementProperties(t)[0]: len(e) for t, e in zip(types, elements)})
    gmsh.finalize()


for kind in ("tri", "quad"):
    for h in (20, 10, 5):
        lame_mesh(f"lame_{kind}_h{h}", h, kind == "quad")
for kind in ("tri6", "quad8"):
    for h in (25, 12.5, 6.25):
        lame_mesh(f"lame_{kind}_h{h:g}", h, kind == "quad8", order=2)
lame_mesh("lame_quad9_h25", 25, True, order=2, incomplete=False)
