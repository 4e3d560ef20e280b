#!/usr/bin/python3
"""Write the Gmsh mesh of the friction family test (tests/check_friction_family.py) with Gmsh's Python API
(Debian's python3-gmsh; CI reads the committed file and never needs Gmsh):

    /usr/bin/python3 tests/data/make_press_fit.py      # rewrites tests/data/scenes/press_fit.msh

examples/decks/press_fit.deck's fit (mm): a hollow shaft 12.5 <= r <= 25, a hub 25.001 <= r <= 50, both 50
long, and the 0.001 gap between them as one column of soft quadrangles. The shaft and the gap are structured
(transfinite, recombined), the hub is Gmsh's unstructured triangles (size 3 at the bore, 5 outside), so the
test meets cells no I-J grid makes; the two faces of the gap carry the same 11 nodes, which is what pairs
them. Physical groups: surfaces "shaft", "gap", "hub"; curves "shaft_face" (r = 25), "hub_face"
(r = 25.001), "shaft_bottom" (the shaft at z = 0), "hub_top" (the hub at z = 50), "hub_outside" (r = 50).
"""
import pathlib

import gmsh

here = pathlib.Path(__file__).resolve().parent
a, b, w, c, length, rows = 12.5, 25.0, 0.001, 50.0, 50.0, 10

gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.add("press_fit")
geo = gmsh.model.geo
point = lambda r, z, size=3.0: geo.addPoint(r, z, 0, size)
s0, s1, s2, s3 = point(a, 0), point(b, 0), point(b, length), point(a, length)
g1, g2 = point(b + w, 0), point(b + w, length)
h1, h2 = point(c, 0, 5.0), point(c, length, 5.0)
shaft_bottom, shaft_face = geo.addLine(s0, s1), geo.addLine(s1, s2)
shaft_top, bore = geo.addLine(s2, s3), geo.addLine(s3, s0)
gap_bottom, hub_face, gap_top = geo.addLine(s1, g1), geo.addLine(g1, g2), geo.addLine(g2, s2)
hub_bottom, outside, hub_top = geo.addLine(g1, h1), geo.addLine(h1, h2), geo.addLine(h2, g2)
shaft = geo.addPlaneSurface([geo.addCurveLoop([shaft_bottom, shaft_face, shaft_top, bore])])
gap = geo.addPlaneSurface([geo.addCurveLoop([gap_bottom, hub_face, gap_top, -shaft_face])])
hub = geo.addPlaneSurface([geo.addCurveLoop([hub_bottom, outside, hub_top, -hub_face])])
geo.synchronize()
mesh = gmsh.model.mesh
for line in (shaft_face, hub_face, bore):
    mesh.setTransfiniteCurve(line, rows + 1)
for line in (gap_bottom, gap_top):
    mesh.setTransfiniteCurve(line, 2)
for line in (shaft_bottom, shaft_top):
    mesh.setTransfiniteCurve(line, 7)
for surface in (shaft, gap):
    mesh.setTransfiniteSurface(surface)
    mesh.setRecombine(2, surface)
for dim, tags, name in [(2, [shaft], "shaft"), (2, [gap], "gap"), (2, [hub], "hub"),
                        (1, [shaft_bottom], "shaft_bottom"), (1, [hub_top], "hub_top"),
                        (1, [shaft_face], "shaft_face"), (1, [hub_face], "hub_face"), (1, [outside], "hub_outside")]:
    gmsh.model.setPhysicalName(dim, gmsh.model.addPhysicalGroup(dim, tags), name)
mesh.generate(2)
gmsh.write(str(here / "scenes" / "press_fit.msh"))
types, elements, _ = mesh.getElements(2)
print("press_fit.msh", {mesh.getElementProperties(t)[0]: len(e) for t, e in zip(types, elements)})
gmsh.finalize()
