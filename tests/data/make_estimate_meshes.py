#!/usr/bin/python3
"""Write the unstructured Lame-tube meshes of tests/check_estimate.py with Gmsh's Python API (Debian's
python3-gmsh; CI reads the committed files and never needs Gmsh):

    /usr/bin/python3 tests/data/make_estimate_meshes.py   # rewrites tests/data/scenes/lame_{tri,quad}_h*.msh

The meridian section 100 <= r <= 200, 0 <= z <= 50 of a thick tube, meshed by Gmsh's default 2-D algorithm
with triangles (lame_tri_hH.msh) and recombined into quadrangles (lame_quad_hH.msh), at mesh sizes H = 20, 10
and 5, each half the last (MSH 4.1). Physical groups: surface "steel"; curves "bore" (r = 100), "bottom"
(z = 0), "top" (z = 50), "outer" (r = 200).
"""
import pathlib

import gmsh

here = pathlib.Path(__file__).resolve().parent

for kind in ("tri", "quad"):
    for h in (20, 10, 5):
        gmsh.initialize()
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add(f"lame_{kind}")
        geo = gmsh.model.geo
        corners = [geo.addPoint(r, z, 0, h) for r, z in ((100, 0), (200, 0), (200, 50), (100, 50))]
        bottom, outer, top, bore = (geo.addLine(corners[k], corners[(k + 1) % 4]) for k in range(4))
        surface = geo.addPlaneSurface([geo.addCurveLoop([bottom, outer, top, bore])])
        geo.synchronize()
        if kind == "quad":
            gmsh.model.mesh.setRecombine(2, surface)
        for dim, tags, name in [(2, [surface], "steel"), (1, [bore], "bore"), (1, [bottom], "bottom"),
                                (1, [top], "top"), (1, [outer], "outer")]:
            gmsh.model.setPhysicalName(dim, gmsh.model.addPhysicalGroup(dim, tags), name)
        gmsh.model.mesh.generate(2)
        name = f"lame_{kind}_h{h}.msh"
        gmsh.write(str(here / "scenes" / name))
        types, elements, _ = gmsh.model.mesh.getElements(2)
        print(name, {gmsh.model.mesh.getElementProperties(t)[0]: len(e) for t, e in zip(types, elements)})
        gmsh.finalize()
