#!/usr/bin/python3
"""Write the Gmsh meshes of the scene tests (tests/test_deck_run.cpp, "[scene]"): the meshes of three example
decks, so that a deck and its scene describe the same model node for node.

    /usr/bin/python3 tests/data/make_scenes.py build/release/examples/gapfe     # rewrites tests/data/scenes/*.msh

Each deck is meshed by `gapfe mesh` (the I-J generator places interior points by a Laplace solve, which only
the generator reproduces to the last bit); its nodes and cells are written in the deck's numbering with
meshio's MSH 2.2 writer (python3-meshio, a writer independent of gapfe's reader), with physical surfaces by
material and I range and physical curves picked by coordinates:

  thick_tube.msh    examples/decks/thick_tube.deck: surface "steel"; curves "bore" (r = 100), "outer" (200),
                    "bottom" (z = 0), "top" (z = 10)
  two_tubes.msh     examples/decks/two_tubes.deck: surfaces "inner" (I < 21), "gap" (material 2), "outer"
                    (I > 21); curves "bore" (r = 50), "inner_face" (r = 75), "outer_face" (r = 75.02)
  plastic_tube.msh  examples/decks/plastic_tube.deck: surface "steel"; curves "bore" (r = 100), "outer" (200)
"""
import csv
import pathlib
import subprocess
import sys
import tempfile

import meshio
import numpy as np

here = pathlib.Path(__file__).resolve().parent
root = here.parent.parent
gapfe = pathlib.Path(sys.argv[1]).resolve()


def deck_mesh(deck):
    with tempfile.TemporaryDirectory() as out:
        subprocess.run([gapfe, "mesh", root / "examples/decks" / deck, "--out", out, "--quiet"], check=True)
        with open(pathlib.Path(out) / "mesh_nodes.csv") as f:
            nodes = [(float(r["r"]), float(r["z"])) for r in csv.DictReader(f)]
        with open(pathlib.Path(out) / "mesh_elements.csv") as f:
            cells = [(int(r["i"]), int(r["material"]), [int(r[f"n{k}"]) - 1 for k in range(1, 5)])
                     for r in csv.DictReader(f)]
    return nodes, cells


def write(name, nodes, cells, surface_of, curves):
    """surface_of(i, material) -> surface name; curves: name -> predicate on (r, z) of both ends."""
    surfaces = sorted({surface_of(i, m) for i, m, _ in cells})
    tag = {s: k + 1 for k, s in enumerate(surfaces)}
    tag.update({c: 100 + k for k, c in enumerate(curves)})
    quads = np.array([c for _, _, c in cells])
    quad_tags = np.array([tag[surface_of(i, m)] for i, m, _ in cells])
    lines, line_tags = [], []
    for cname, on in curves.items():
        seen = set()
        for _, _, c in cells:
            for k in range(4):
                a, b = c[k], c[(k + 1) % 4]
                key = (min(a, b), max(a, b))
                if key not in seen and on(*nodes[a]) and on(*nodes[b]):
                    seen.add(key)
                    lines.append(sorted(key, key=lambda n: (nodes[n][1], nodes[n][0])))
                    line_tags.append(tag[cname])
        assert seen, cname
    mesh = meshio.Mesh(np.array([[r, z, 0.0] for r, z in nodes]),
                       [("quad", quads), ("line", np.array(lines))])
    mesh.cell_data["gmsh:physical"] = [quad_tags, np.array(line_tags)]
    mesh.cell_data["gmsh:geometrical"] = [quad_tags, np.array(line_tags)]
    mesh.field_data = {s: np.array([tag[s], 2]) for s in surfaces}
    mesh.field_data.update({c: np.array([tag[c], 1]) for c in curves})
    (here / "scenes").mkdir(exist_ok=True)
    meshio.write(here / "scenes" / name, mesh, file_format="gmsh22", binary=False)
    back = meshio.read(here / "scenes" / name)  # a real reader: the same points and cells
    assert np.array_equal(back.points[:, :2], np.array(nodes)) and (back.cells_dict["quad"] == quads).all()
    print(f"wrote scenes/{name}: {len(nodes)} nodes, {len(quads)} quads, {len(lines)} lines")


nodes, cells = deck_mesh("thick_tube.deck")
write("thick_tube.msh", nodes, cells, lambda i, m: "steel",
      {"bore": lambda r, z: r == 100, "outer": lambda r, z: r == 200, "bottom": lambda r, z: z == 0,
       "top": lambda r, z: z == 10})
nodes, cells = deck_mesh("two_tubes.deck")
write("two_tubes.msh", nodes, cells, lambda i, m: "gap" if m == 2 else "inner" if i < 21 else "outer",
      {"bore": lambda r, z: r == 50, "inner_face": lambda r, z: r == 75, "outer_face": lambda r, z: r == 75.02})
nodes, cells = deck_mesh("plastic_tube.deck")
write("plastic_tube.msh", nodes, cells, lambda i, m: "steel",
      {"bore": lambda r, z: r == 100, "outer": lambda r, z: r == 200})
