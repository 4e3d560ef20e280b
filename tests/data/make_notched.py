#!/usr/bin/python3
"""Write the notched-tube meshes of the scene test "[scene] A notched tube" (tests/test_deck_run.cpp) with
Gmsh's Python API (Debian's python3-gmsh; CI reads the committed files and never needs Gmsh):

    /usr/bin/python3 tests/data/make_notched.py      # rewrites tests/data/scenes/notched_tube_h*.msh

The meridian section of a tube 100 <= r <= 200, 0 <= z <= 100 with a semicircular groove of radius 20 cut
into its outer surface at z = 50 (a section no I-J grid describes): the half below z = 50 meshed with
triangles, the half above with quadrangles (recombined), at mesh sizes 8, 4 and 2 (MSH 4.1, Gmsh's default
writer). The line z = 50 from the bore to the groove's root splits the halves, so every mesh has a node at
(100, 50). Physical groups: surface "steel"; curves "bore" (r = 100), "bottom" (z = 0), "top" (z = 100),
"outer" (r = 200 and the groove).
"""
import pathlib

import gmsh

here = pathlib.Path(__file__).resolve().parent

for h in (8, 4, 2):
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("notched_tube")
    geo = gmsh.model.geo
    p = {name: geo.addPoint(r, z, 0, h) for name, (r, z) in {
        "b0": (100, 0), "o0": (200, 0), "g0": (200, 30), "gc": (200, 50), "root": (180, 50), "g1": (200, 70),
        "o1": (200, 100), "b1": (100, 100), "bm": (100, 50)}.items()}
    bottom = geo.addLine(p["b0"], p["o0"])
    outer_low = geo.addLine(p["o0"], p["g0"])
    groove_low = geo.addCircleArc(p["g0"], p["gc"], p["root"])
    split = geo.addLine(p["root"], p["bm"])
    bore_low = geo.addLine(p["bm"], p["b0"])
    groove_high = geo.addCircleArc(p["root"], p["gc"], p["g1"])
    outer_high = geo.addLine(p["g1"], p["o1"])
    top = geo.addLine(p["o1"], p["b1"])
    bore_high = geo.addLine(p["b1"], p["bm"])
    low = geo.addPlaneSurface([geo.addCurveLoop([bottom, outer_low, groove_low, split, bore_low])])
    high = geo.addPlaneSurface([geo.addCurveLoop([-split, groove_high, outer_high, top, bore_high])])
    geo.synchronize()
    gmsh.model.mesh.setRecombine(2, high)
    for dim, tags, name in [(2, [low, high], "steel"), (1, [bore_low, bore_high], "bore"), (1, [bottom], "bottom"),
                            (1, [top], "top"), (1, [outer_low, groove_low, groove_high, outer_high], "outer")]:
        gmsh.model.setPhysicalName(dim, gmsh.model.addPhysicalGroup(dim, tags), name)
    gmsh.model.mesh.generate(2)
    name = f"notched_tube_h{h}.msh"
    gmsh.write(str(here / "scenes" / name))
    types, elements, _ = gmsh.model.mesh.getElements(2)
    print(name, {gmsh.model.mesh.getElementProperties(t)[0]: len(e) for t, e in zip(types, elements)})
    gmsh.finalize()
