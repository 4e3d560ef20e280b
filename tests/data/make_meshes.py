#!/usr/bin/python3
"""Write the small Gmsh meshes the tests read (tests/test_deck.cpp, "[gmsh]"), with meshio (Debian's
python3-meshio), a writer independent of gapfe's reader:

    /usr/bin/python3 tests/data/make_meshes.py     # rewrites tests/data/*.msh

tube_quad4_v22.msh (meshio's MSH 2.2 writer): the thick tube 100 <= r <= 200, 0 <= z <= 25 on a 4 x 2 grid
of 4-node quadrangles, node (i, j) at r = 100 + 25 i, z = 12.5 j; physical surface "steel" (tag 1) and curves
"bore" (r = 100, tag 11), "bottom" (z = 0, 12), "top" (z = 25, 13); the cells of the second row written
clockwise (the reader turns them). tube_quad8_v41.msh (meshio's MSH 4.1 writer): the same section as one row of
four 8-node quadrangles; meshio 7 puts every line in one curve entity without a physical group, so its lines
carry none. tube_quad4_v41.msh: the quad4 tube written here as MSH 4.1 text with $Entities (curve entities 1-3
with their physical groups, surface 1 in "steel") and node tags 1000 + 10 j + i (gaps), then read back with
meshio to check it is a valid file with the same points and cells.
"""
import pathlib

import meshio
import numpy as np

here = pathlib.Path(__file__).resolve().parent


def tube(order):
    ni, nj = 4, 2
    if order == 1:
        pts = {(i, j): (100 + 25 * i, 12.5 * j) for j in range(nj + 1) for i in range(ni + 1)}
    else:  # serendipity: corners and mid-sides of a 4 x 1 grid, on the half-grid
        pts = {(i, j): (100 + 12.5 * i, 12.5 * j) for j in range(3) for i in range(2 * ni + 1)
               if not (i % 2 == 1 and j == 1)}
    keys = list(pts)
    tag_of = {k: 1000 + 10 * k[1] + k[0] for k in keys}
    # meshio numbers points 0.. in order; gapfe's test reads the coordinates, so the order is free.
    index = {k: n for n, k in enumerate(keys)}
    points = np.array([[*pts[k], 0.0] for k in keys])
    if order == 1:
        quads = []
        for j in range(nj):
            for i in range(ni):
                c = [index[(i, j)], index[(i + 1, j)], index[(i + 1, j + 1)], index[(i, j + 1)]]
                quads.append(c if j == 0 else c[::-1])  # second row clockwise
        cells = [("quad", np.array(quads))]
        bore = [[index[(0, j + 1)], index[(0, j)]] for j in range(nj)]
        bottom = [[index[(i, 0)], index[(i + 1, 0)]] for i in range(ni)]
        top = [[index[(i + 1, nj)], index[(i, nj)]] for i in range(ni)]
        lines = [("line", np.array(bore + bottom + top))]
    else:
        quads = []
        for i in range(0, 2 * ni, 2):
            quads.append([index[(i, 0)], index[(i + 2, 0)], index[(i + 2, 2)], index[(i, 2)],
                          index[(i + 1, 0)], index[(i + 2, 1)], index[(i + 1, 2)], index[(i, 1)]])
        cells = [("quad8", np.array(quads))]
        bore = [[index[(0, 2)], index[(0, 0)], index[(0, 1)]]]
        bottom = [[index[(i, 0)], index[(i + 2, 0)], index[(i + 1, 0)]] for i in range(0, 2 * ni, 2)]
        top = [[index[(i + 2, 2)], index[(i, 2)], index[(i + 1, 2)]] for i in range(0, 2 * ni, 2)]
        lines = [("line3", np.array(bore + bottom + top))]
    nq, nb, nbo, nt = len(quads), len(bore), len(bottom), len(top)
    mesh = meshio.Mesh(points, cells + lines)
    physical = [np.full(nq, 1), np.array([11] * nb + [12] * nbo + [13] * nt)]
    mesh.cell_data["gmsh:physical"] = physical
    mesh.cell_data["gmsh:geometrical"] = [np.full(nq, 1), np.array([1] * nb + [2] * nbo + [3] * nt)]
    mesh.field_data = {"steel": np.array([1, 2]), "bore": np.array([11, 1]), "bottom": np.array([12, 1]),
                       "top": np.array([13, 1])}
    mesh.point_data["gmsh:dim_tags"] = np.array([[2, 1]] * len(points))
    return mesh, np.array([tag_of[k] for k in keys])


for order, version, name in [(1, "gmsh22", "tube_quad4_v22.msh"), (2, "gmsh", "tube_quad8_v41.msh")]:
    mesh, tags = tube(order)
    meshio.write(here / name, mesh, file_format=version, binary=False)
    print(f"wrote {name}: {len(mesh.points)} nodes")


def tube_v41():
    """The quad4 tube as MSH 4.1 text: entities with physical groups, tags with gaps, a clockwise row."""
    tag = lambda i, j: 1000 + 10 * j + i
    nodes = [(tag(i, j), 100 + 25 * i, 12.5 * j) for j in range(3) for i in range(5)]
    quads = []
    for j in range(2):
        for i in range(4):
            c = [tag(i, j), tag(i + 1, j), tag(i + 1, j + 1), tag(i, j + 1)]
            quads.append(c if j == 0 else c[::-1])
    curves = {1: [(tag(0, j + 1), tag(0, j)) for j in range(2)],        # bore, physical 11
              2: [(tag(i, 0), tag(i + 1, 0)) for i in range(4)],        # bottom, 12
              3: [(tag(i + 1, 2), tag(i, 2)) for i in range(4)]}        # top, 13
    out = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat",
           "$PhysicalNames", "4", '1 11 "bore"', '1 12 "bottom"', '1 13 "top"', '2 1 "steel"', "$EndPhysicalNames",
           "$Entities", "0 3 1 0",
           "1 100 0 0 100 25 0 1 11 0", "2 100 0 0 200 0 0 1 12 0", "3 100 25 0 200 25 0 1 13 0",
           "1 100 0 0 200 25 0 1 1 3 1 2 3", "$EndEntities",
           "$Nodes", f"1 {len(nodes)} {min(n[0] for n in nodes)} {max(n[0] for n in nodes)}",
           f"2 1 0 {len(nodes)}"]
    out += [str(n[0]) for n in nodes] + [f"{n[1]:g} {n[2]:g} 0" for n in nodes] + ["$EndNodes"]
    count = len(quads) + sum(len(v) for v in curves.values())
    out += ["$Elements", f"{1 + len(curves)} {count} 1 {count}", f"2 1 3 {len(quads)}"]
    e = 1
    for q in quads:
        out.append(" ".join(map(str, [e] + q)))
        e += 1
    for c, lines in curves.items():
        out.append(f"1 {c} 1 {len(lines)}")
        for a, b in lines:
            out.append(f"{e} {a} {b}")
            e += 1
    out.append("$EndElements")
    return "\n".join(out) + "\n", nodes, quads


text, nodes, quads = tube_v41()
(here / "tube_quad4_v41.msh").write_text(text)
check = meshio.read(here / "tube_quad4_v41.msh")  # a real reader: the same points and cells
assert np.allclose(check.points[:, :2], [[r, z] for _, r, z in nodes])
order = {n[0]: k for k, n in enumerate(nodes)}
assert (check.cells_dict["quad"] == np.array([[order[t] for t in q] for q in quads])).all()
assert len(check.cells_dict["line"]) == 10
print("wrote tube_quad4_v41.msh (checked with meshio.read)")
