#!/usr/bin/python3
"""Write the order-2 Lame-tube meshes of tests/check_quadratic.py with Gmsh's Python API (Debian's python3-gmsh;
CI reads the committed files and never needs Gmsh):

    /usr/bin/python3 tests/data/make_order2_meshes.py   # rewrites tests/data/scenes/lame_{quad8,tri6}_h*.msh

The meridian section 100 <= r <= 200, 0 <= z <= 50 of tests/data/make_estimate_meshes.py, meshed by Gmsh's
default 2-D algorithm at mesh sizes H = 25, 12.5 and 6.25 and raised to order 2 (Mesh.ElementOrder = 2):
6-node triangles (lame_tri6_hH.msh), and quadrangles recombined from them, of 8 nodes
(Mesh.SecondOrderIncomplete = 1: lame_quad8_hH.msh) and, at H = 25, of 9 nodes (Gmsh's default:
lame_quad9_h25.msh, the same mesh with a centre node in each quadrangle). MSH 4.1. Physical groups: surface
"steel"; curves "bore" (r = 100), "bottom" (z = 0), "top" (z = 50), "outer" (r = 200).

Also the thick sphere of tests/data/make_sphere.py (100 <= R <= 200, z >= 0, size 25) at order 2: 6-node
triangles (sphere_tri6.msh) and recombined 8-node quadrangles (sphere_quad8.msh), whose middle nodes on the
bore and the outside Gmsh puts on the circles.
"""
import pathlib

import gmsh

here = pathlib.Path(__file__).resolve().parent

for kind, sizes in (("tri6", (25, 12.5, 6.25)), ("quad8", (25, 12.5, 6.25)), ("quad9", (25,))):
    for h in sizes:
        gmsh.initialize()
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add(f"lame_{kind}")
        geo = gmsh.model.geo
        corners = [geo.addPoint(r, z, 0, h) for r, z in ((100, 0), (200, 0), (200, 50), (100, 50))]
        bottom, outer, top, bore = (geo.addLine(corners[k], corners[(k + 1) % 4]) for k in range(4))
        surface = geo.addPlaneSurface([geo.addCurveLoop([bottom, outer, top, bore])])
        geo.synchronize()
        if kind != "tri6":
            gmsh.model.mesh.setRecombine(2, surface)
        gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 1 if kind == "quad8" else 0)
        for dim, tags, name in [(2, [surface], "steel"), (1, [bore], "bore"), (1, [bottom], "bottom"),
                                (1, [top], "top"), (1, [outer], "outer")]:
            gmsh.model.setPhysicalName(dim, gmsh.model.addPhysicalGroup(dim, tags), name)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(2)
        name = f"lame_{kind}_h{h:g}.msh"
        gmsh.write(str(here / "scenes" / name))
        types, elements, _ = gmsh.model.mesh.getElements(2)
        print(name, {gmsh.model.mesh.getElementProperties(t)[0]: len(e) for t, e in zip(types, elements)})
        gmsh.finalize()

a, b, h = 100.0, 200.0, 25.0
for kind in ("tri6", "quad8"):
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add(f"sphere_{kind}")
    geo = gmsh.model.geo
    centre = geo.addPoint(0, 0, 0, h)
    p = {name: geo.addPoint(r, z, 0, h) for name, r, z in (("a0", a, 0), ("b0", b, 0), ("b1", 0, b), ("a1", 0, a))}
    bottom = geo.addLine(p["a0"], p["b0"])
    outer = geo.addCircleArc(p["b0"], centre, p["b1"])
    axis = geo.addLine(p["b1"], p["a1"])
    bore = geo.addCircleArc(p["a1"], centre, p["a0"])
    surface = geo.addPlaneSurface([geo.addCurveLoop([bottom, outer, axis, bore])])
    geo.synchronize()
    if kind == "quad8":
        gmsh.model.mesh.setRecombine(2, surface)
    gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 1)
    for dim, tags, name in [(2, [surface], "steel"), (1, [bore], "bore"), (1, [outer], "outer"),
                            (1, [bottom], "bottom"), (1, [axis], "axis")]:
        gmsh.model.setPhysicalName(dim, gmsh.model.addPhysicalGroup(dim, tags), name)
    gmsh.model.mesh.generate(2)
    gmsh.model.mesh.setOrder(2)
    name = f"sphere_{kind}.msh"
    gmsh.write(str(here / "scenes" / name))
    types, elements, _ = gmsh.model.mesh.getElements(2)
    print(name, {gmsh.model.mesh.getElementProperties(t)[0]: len(e) for t, e in zip(types, elements)})
    gmsh.finalize()
