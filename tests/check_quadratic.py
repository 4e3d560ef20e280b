#!/usr/bin/python3
"""Quadratic cells through `gapfe run` (ctest `gapfe_quadratic`; docs/settings.md "Quadratic cells"), against
the Lame tube's closed form (a = 100, b = 200, bore pressure 100, plane strain; E = 200000, nu = 0.3):

  * Gmsh order-2 meshes (tests/data/make_estimate_meshes.py) of 8-node quadrangles and of 6-node triangles at
    three sizes, each half the last: the L2 error of u_r, integrated over the meridian section with the
    cells' own shape functions on the VTU's quadratic cells (read back by meshio), falls at third order;
  * a 9-node quadrangle mesh (Gmsh's default order 2) runs as the 8-node one with the centres dropped: the
    same displacements at the shared nodes;
  * the thick sphere on order-2 meshes, whose middle nodes on the bore lie on its circle: u_R against its
    closed form at every node, 5 times closer than Quad4 on the order-1 mesh of the same size;
  * card decks with element = quad8 on I-J grids of 4, 8, 16 and 32 cells through the wall: third order too, the
    grid's corners keeping their numbers and the middle nodes numbered after them;
  * SAAC3X's driven faces with a BC card on one: every node of both faces driven, the middle nodes too;
  * a plastic tube as a deck with element = quad8 (pressure 300, below the limit 320) agrees with quad4bbar's
    bore u_r to 1%;
  * nu = 0.4999: the quadrangles' L2 error of u_r as at nu = 0.3 and no warning; the triangles warned of;
  * the refusals: element = quad4 on an order-2 mesh, element = quad8 with gap elements, --estimate on an
    order-2 mesh; each with one line naming the cause and no result files.

    /usr/bin/python3 tests/check_quadratic.py build/release/examples/gapfe WORKDIR
"""
import math
import pathlib
import shutil
import subprocess
import sys

import meshio
import numpy as np

root = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(root / "bench"))
import deckgen  # noqa: E402  (the decks' one writer)
import vtu_l2  # noqa: E402  (tests/vtu_l2.py: the L2 error of a VTU's displacements)
from checks import check, finish  # noqa: E402  (tests/checks.py: the shared tally)

gapfe = pathlib.Path(sys.argv[1]).resolve()
work = pathlib.Path(sys.argv[2]).resolve()
scenes = root / "tests" / "data" / "scenes"
E, NU = 200000.0, 0.3
A, B, P = 100.0, 200.0, 100.0
ORDER = (2.6, 3.4)  # quadratic cells: the L2 error of u falls as h^3
work.mkdir(parents=True, exist_ok=True)


def run(model, name, *options, expect=0):
    out = work / name
    shutil.rmtree(out, ignore_errors=True)
    done = subprocess.run([str(gapfe), "run", str(model), "--out", str(out), "--plot", "none", *options],
                          capture_output=True, text=True)
    check(done.returncode == expect, f"{name}: exit {done.returncode}, expected {expect}: {done.stderr.strip()}")
    return out, done.stdout, done.stderr


def lame_u(r, nu=NU):
    """u_r of the Lame tube in plane strain."""
    c = P * A * A / (B * B - A * A)
    return (1 + nu) / E * ((1 - 2 * nu) * c * r + c * B * B / r)


def l2_error(out, nu=NU):
    """(L2 error of u_r per unit height, cells, their kinds) over a run's last VTU (tests/vtu_l2.py)."""
    vtu = sorted(out.glob("step_*.vtu"))
    check(len(vtu) > 0, f"{out.name}: no step VTU")
    return vtu_l2.radial_error(meshio.read(vtu[-1]), lambda r: lame_u(r, nu))


def orders(name, errors):
    rates = [math.log2(errors[k] / errors[k + 1]) for k in range(len(errors) - 1)]
    print(f"{name}: L2 errors of u_r {', '.join(f'{e:.3e}' for e in errors)}; orders "
          f"{', '.join(f'{q:.2f}' for q in rates)}")
    check(ORDER[0] <= rates[-1] <= ORDER[1], f"{name}: the last order {rates[-1]:.2f} outside {ORDER}")
    return rates


def scene_text(mesh, extra="", nu=NU):
    return f"""title = "Lame tube on {mesh}"
[mesh]
file = "{scenes / mesh}"
{extra}
[materials.steel]
E = {E}
nu = {nu}
[[boundary]]
groups = ["bottom", "top"]
fix = ["z"]
[[load]]
curves = ["bore"]
pressure = {P}
"""


def gmsh_order2():
    for kind, cell in (("quad8", "quad8"), ("tri6", "triangle6")):
        errors = []
        for h in ("25", "12.5", "6.25"):
            scene = work / f"lame_{kind}_h{h}.toml"
            scene.write_text(scene_text(f"lame_{kind}_h{h}.msh"))
            out, log, _ = run(scene, scene.stem)
            check("element quad8" in log, f"{scene.stem}: the log names element quad8")
            error, cells, kinds = l2_error(out)
            check(kinds == {cell}, f"{scene.stem}: VTU cells {kinds}, expected {cell}")
            errors.append(error)
        orders(f"Gmsh order-2 {kind}", errors)
    # The 9-node quadrangles: the same mesh as lame_quad8_h25 but for the centres.
    scene = work / "lame_quad9_h25.toml"
    scene.write_text(scene_text("lame_quad9_h25.msh"))
    out9, _, _ = run(scene, scene.stem)
    a = meshio.read(sorted(out9.glob("step_*.vtu"))[-1])
    b = meshio.read(sorted((work / "lame_quad8_h25").glob("step_*.vtu"))[-1])
    same = a.points.shape == b.points.shape and np.allclose(a.points, b.points, rtol=0, atol=1e-12)
    check(same, "9-node quadrangles: the nodes differ from the 8-node mesh's")
    if same:
        diff = np.abs(a.point_data["displacement"] - b.point_data["displacement"]).max()
        check(diff <= 1e-12 * np.abs(b.point_data["displacement"]).max(),
              f"9-node quadrangles: displacements differ from the 8-node mesh's by {diff:.2e}")


def sphere():
    """The thick sphere 100 <= R <= 200 under bore pressure on Gmsh's order-2 meshes of size 25
    (tests/data/make_sphere.py): the middle nodes on the bore lie on its circle, as the file puts them,
    and u_R at every node is within 0.5% of the closed form P a^3 / (E (b^3 - a^3)) ((1 - 2 nu) R +
    (1 + nu) b^3 / (2 R^2)) (0.18% on the quadrangles, 0.31% on the triangles), 5 times closer than Quad4 on
    the order-1 mesh of the same size (tests/data/make_sphere.py: 4.1%, and 8.8% on its constant-strain
    triangles)."""
    cube = B ** 3 - A ** 3

    def worst(out):
        mesh = meshio.read(sorted(out.glob("step_*.vtu"))[-1])
        x, u = mesh.points[:, :2], mesh.point_data["displacement"][:, :2]
        radius = np.hypot(x[:, 0], x[:, 1])
        exact = P * A ** 3 / (E * cube) * ((1 - 2 * NU) * radius + (1 + NU) * B ** 3 / (2 * radius ** 2))
        bore = np.abs(radius - A) < 0.01 * A
        return (np.abs((u[:, 0] * x[:, 0] + u[:, 1] * x[:, 1]) / radius / exact - 1).max(),
                np.abs(radius[bore] - A).max(), int(bore.sum()), {c.type for c in mesh.cells})

    body = ('[materials.steel]\nE = 200000.0\nnu = 0.3\n[[boundary]]\ngroups = "bottom"\nfix = "z"\n'
            '[[boundary]]\ngroups = "axis"\nfix = "r"\n[[load]]\ncurves = "bore"\npressure = 100.0\n')
    for order2, order1 in (("sphere_quad8", "sphere_quad"), ("sphere_tri6", "sphere_tri")):
        errors = []
        for mesh, extra in ((order2, ""), (order1, '[options]\nelement = "quad4"\n')):
            model = work / f"{mesh}.toml"
            model.write_text(f'title = "{mesh}"\n[mesh]\nfile = "{scenes / (mesh + ".msh")}"\n{extra}{body}')
            out, _, _ = run(model, model.stem)
            errors.append(worst(out))
        (quadratic, off_circle, bore, kinds), (linear, _, _, _) = errors
        print(f"{order2}: largest relative error of u_R {quadratic:.2e} ({order1} with quad4: {linear:.2e}); "
              f"{bore} bore nodes, {off_circle:.1e} off the circle; cells {kinds}")
        check(off_circle < 1e-9 * A and bore > 9, f"{order2}: bore nodes {off_circle:.2e} off the circle")
        check(quadratic < 5e-3, f"{order2}: u_R off the closed form by {quadratic:.2e}")
        check(quadratic < linear / 5, f"{order2}: u_R error {quadratic:.2e} not 5 times below quad4's {linear:.2e}")


def decks():
    errors = []
    for cells in (4, 8, 16, 32):
        deck = work / f"lame_quad8_{cells}.deck"
        deck.write_text(deckgen.tube_deck(cells + 1, 3, extension=("format = elastic", "element = quad8")))
        out, log, _ = run(deck, deck.stem)
        error, _, kinds = l2_error(out)
        check(kinds == {"quad8"}, f"{deck.stem}: VTU cells {kinds}")
        errors.append(error)
        # The grid's corners keep their numbers: node 1 is (I, J) = (1, 1) at the bore, u_r there the closed
        # form's to the discretization error; a middle node's row has I = J = 0.
        rows = [line.split(",") for line in (out / "nodes.csv").read_text().splitlines()[1:]]
        first = rows[0]
        check(first[3] == "1" and first[4] == "1" and first[5] == "1" and abs(float(first[6]) - A) < 1e-9,
              f"{deck.stem}: nodes.csv's first row is not node 1 at (I, J) = (1, 1), r = a: {first[:8]}")
        check(abs(float(first[8]) / lame_u(A) - 1) < 2e-3 / cells,
              f"{deck.stem}: bore u_r {first[8]} against {lame_u(A):.6e}")
        corners = (cells + 1) * 3
        check(len(rows) > corners and all(r[4] == "0" and r[5] == "0" for r in rows[corners:]),
              f"{deck.stem}: the middle nodes are not after the {corners} corners with I = J = 0")
    orders("deck element = quad8", errors)


def plastic():
    """The plastic tube (bench/deckgen.py plastic_tube_deck) with quad8: its last step's bore pressure 300 lies
    below the plane-strain limit; the bore's u_r against the deck run with quad4bbar, to 1%."""
    ref = work / "plastic_bbar.deck"
    ref.write_text(deckgen.plastic_tube_deck(ni=21, steps=6))
    quad8 = work / "plastic_quad8.deck"
    quad8.write_text(deckgen.plastic_tube_deck(ni=21, steps=6, extension=("element = quad8",)))
    out_b, _, _ = run(ref, ref.stem)
    out_q, log, _ = run(quad8, quad8.stem)
    check("element quad8" in log, "plastic quad8: the log names element quad8")

    def bore(out):
        rows = [line.split(",") for line in (out / "nodes.csv").read_text().splitlines()[1:]]
        last = max(int(r[0]) for r in rows)
        return float(next(r for r in rows if int(r[0]) == last and r[3] == "1")[8])

    ub, uq = bore(out_b), bore(out_q)
    check(abs(uq / ub - 1) < 0.01, f"plastic quad8: bore u_r {uq:.6e} against quad4bbar's {ub:.6e}")


def saac3x_faces():
    """SAAC3X's faces (docs/decks.md "SAAC3X") with a BC card on the bottom face (u_r = 0) and element = quad8:
    the command drives every node of both faces, the faces' middle nodes too (their conditions from the card
    hold u_r only, and the drive adds u_z and, at the bottom, u_theta), so at the end every top node has the
    top's u_z and every bottom node u_z = u_theta = u_r = 0."""
    text = deckgen.saac3x_deck(steps=10)
    text = text.replace(deckgen.mesh_control(2, 2, 4, 0, 1), deckgen.mesh_control(2, 2, 4, 1, 1))
    text = text.replace(deckgen.block(1, 1, 2, 1, 2), deckgen.bc(1, 2, 1, 1, 1) + "\n" + deckgen.block(1, 1, 2, 1, 2))
    deck = work / "saac3x_quad8.deck"
    deck.write_text(text.replace("$ format = saac3", "$ format = saac3\n$ element = quad8"))
    out, log, _ = run(deck, deck.stem)
    check("element quad8" in log, "saac3x quad8: the log names element quad8")
    rows = [line.split(",") for line in (out / "nodes.csv").read_text().splitlines()[1:]]
    last = max(int(r[0]) for r in rows)
    rows = [r for r in rows if int(r[0]) == last]
    top = [float(r[9]) for r in rows if abs(float(r[7]) - 1.0) < 1e-12]
    bottom = [(float(r[8]), float(r[9]), float(r[10])) for r in rows if abs(float(r[7])) < 1e-12]
    check(len(top) == 3 and len(bottom) == 3, f"saac3x quad8: {len(top)} top and {len(bottom)} bottom nodes, not 3")
    check(top[0] > 0 and max(top) - min(top) <= 1e-12 * top[0], f"saac3x quad8: the top's u_z differ: {top}")
    check(all(abs(v) <= 1e-15 for node in bottom for v in node), f"saac3x quad8: the bottom moves: {bottom}")


def incompressible():
    """nu = 0.4999 on the Gmsh order-2 Lame tubes of size 12.5: the 8-node quadrangles carry a linear pressure
    (B-bar) and do not lock: no warning, and the L2 error of u_r within twice nu = 0.3's on the same mesh
    (measured 8.0e-4 against 6.6e-4); the 6-node triangles lock (3.9e-2), and the run says so in one warning
    naming them."""
    for kind, warned in (("quad8", False), ("tri6", True)):
        errors = {}
        for nu in (NU, 0.4999):
            scene = work / f"lame_{kind}_nu{nu}.toml"
            scene.write_text(scene_text(f"lame_{kind}_h12.5.msh", nu=nu))
            out, _, err = run(scene, scene.stem)
            warnings = [line for line in err.splitlines() if line.startswith("gapfe: warning:")]
            if nu == NU or not warned:
                check(not warnings, f"{scene.stem}: no warning expected: {warnings}")
            else:
                check(len(warnings) == 1 and "6-node triangles lock" in warnings[0],
                      f"{scene.stem}: one warning of the triangles expected: {warnings}")
            errors[nu] = l2_error(out, nu)[0]
        print(f"nu = 0.4999 on {kind}: L2 error of u_r {errors[0.4999]:.3e} against {errors[NU]:.3e} at nu = 0.3")
        if not warned:
            check(errors[0.4999] < 2 * errors[NU], f"{kind} at nu = 0.4999: L2 error {errors[0.4999]:.3e} "
                  f"against {errors[NU]:.3e} at nu = 0.3")
        else:  # what the warning says: the triangles lock
            check(errors[0.4999] > 10 * errors[NU], f"{kind} at nu = 0.4999: L2 error {errors[0.4999]:.3e}, "
                  f"not locked against {errors[NU]:.3e} at nu = 0.3")


def refusals():
    scene = work / "order2_quad4.toml"
    scene.write_text(scene_text("lame_quad8_h25.msh", '[options]\nelement = "quad4"'))
    out, _, err = run(scene, scene.stem, expect=1)
    check("order 2" in err and len(err.strip().splitlines()) == 1, f"element = quad4 on order 2: {err!r}")
    check(not out.exists() or not any(out.glob("*.csv")), "element = quad4 on order 2: files written")
    deck = work / "gaps_quad8.deck"
    deck.write_text(deckgen.two_tubes_deck(n=8, nz=8, steps=1, extension=("element = quad8",)))
    _, _, err = run(deck, deck.stem, expect=1)
    check("gap elements" in err, f"element = quad8 with gaps: {err!r}")
    scene = work / "order2_estimate.toml"
    scene.write_text(scene_text("lame_quad8_h25.msh"))
    _, _, err = run(scene, scene.stem, "--estimate", expect=1)
    check("order 2" in err, f"--estimate on order 2: {err!r}")


gmsh_order2()
sphere()
decks()
saac3x_faces()
plastic()
incompressible()
refusals()
finish()
