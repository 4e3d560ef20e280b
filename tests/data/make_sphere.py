#!/usr/bin/python3
"""Write the thick sphere's meshes of tests/check_error_bars.py and tests/check_quadratic.py with Gmsh's Python
API (Debian's python3-gmsh; CI reads the committed files and never needs Gmsh):

    /usr/bin/python3 tests/data/make_sphere.py   # rewrites tests/data/scenes/sphere_{quad,tri,quad8,tri6}.msh

The meridian section of a hollow sphere a = 100 <= R <= b = 200 in z >= 0, r >= 0: a quarter annulus whose
bore and outer boundary are circular arcs (Gmsh circles, so the nodes lie on them to round-off), meshed with
size 25 (the bore's arc in 7 sides, the outer's in 13), triangles (sphere_tri.msh) or recombined into
quadrangles (sphere_quad.msh), and the same at order 2 (Mesh.ElementOrder = 2, 6-node triangles and 8-node
quadrangles: sphere_tri6.msh, sphere_quad8.msh), whose middle nodes on the arcs Gmsh puts on the circles.
MSH 4.1. Physical groups: surface "steel"; curves "bore" (R = a), "outer" (R = b), "bottom" (z = 0), "axis"
(r = 0).
"""
import pathlib

import gmsh

here = pathlib.Path(__file__).resolve().parent
a, b, h = 100.0, 200.0, 25.0

for kind, order in (("quad", 1), ("tri", 1), ("quad8", 2), ("tri6", 2)):
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
    if kind.startswith("quad"):
        gmsh.model.mesh.setRecombine(2, surface)
    for dim, tags, name in [(2, [surface], "steel"), (1, [bore], "bore"), (1, [outer], "outer"),
                            (1, [bottom], "bottom"), (1, [axis], "axis")]:
        gmsh.model.setPhysicalName(dim, gmsh.model.addPhysicalGroup(dim, tags), name)
    gmsh.model.mesh.generate(2)
    if order == 2:
        gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 1)
        gmsh.model.mesh.setOrder(2)
    name = f"sphere_{kind}.msh"
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.write(str(here / "scenes" / name))
    types, elements, _ = gmsh.model.mesh.getElements(2)
    print(name, {gmsh.model.mesh.getElementProperties(t)[0]: len(e) for t, e in zip(types, elements)})
    gmsh.finalize()
