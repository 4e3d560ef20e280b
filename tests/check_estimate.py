#!/usr/bin/python3
"""The error estimate every run reports (post/error_estimate.hpp, docs/accuracy.md), through `gapfe run`
(ctest `gapfe_estimate`), against the true energy-norm error of problems with closed forms:

  * the Lame tube (a = 100, b = 200, bore pressure 100, plane strain; E = 200000, nu = 0.3) as card decks on
    I-J grids of 8, 16 and 32 cells through the wall, with element = quad4 and quad4bbar, and as Gmsh meshes
    (tests/data/make_estimate_meshes.py) of unstructured quadrangles (quad4) and triangles (the constant-strain
    triangle), each at three sizes;
  * a spinning solid cylinder (b = 100, omega = 1000 rad/s, plane strain) as grid scenes on 8, 16 and 32
    cells across the radius, quad4.

The true error needs no integration of the closed form where the element's form is exact: Galerkin
orthogonality gives |u - u_h|^2 = l(u) - l(u_h), the work of the loads on the exact and on the discrete
displacements (l(u_h) from nodes.csv: u_r along the bore, or the spin's load rho omega^2 r over the section
by 3 x 3 Gauss on each cell), |u|^2 = l(u) in closed form. The identity needs the element's form to be the
exact one. The constant-strain triangle takes its hoop strain at the centroid, so it does not hold for it: its
error is integrated, the closed form's stress against each triangle's (the VTU's cell stress) on a degree-5
rule. Nor for B-bar where the dilatation varies (the spinning cylinder; on the Lame tube it is constant and
B-bar is exact), nor for the legacy quadrilateral, whose sub-triangles' stresses no file holds: their
effectivities are measured in tests/test_estimate.cpp, by integration with the element's own strains (here the
legacy decks' estimates are checked against the library's figures). Quad4's own 2 x 2 Gauss rule integrates
the hoop term N_a N_b / r only to O((h/r)^4), far below these errors. The estimate's effectivity, estimate /
true error, must lie within [0.7, 1.5] on meshes in the asymptotic range, and within 5% of 1 on the finest
structured meshes (the recovery is superconvergent there).

The log's figure and the VTU's per-cell array agree: their squares sum to the whole's square, and on the Lame
decks the largest share lies in the two columns at the bore, where the stress varies fastest (the map from mesh
cells to deck elements; B-bar's largest is in the second). The notched tube (Gmsh: triangles below, quadrangles above) has its largest share at the
groove's root. Runs with gaps, plasticity and friction report an estimate per load step too, with the gap
elements' shares 0; a tube expanding freely under a uniform temperature rise has no stress, and its log says
there is nothing to estimate. With `error_estimate = none` a run writes the same tables, byte for byte, and the
same VTU arrays but the estimate's.

    /usr/bin/python3 tests/check_estimate.py build/release/examples/gapfe WORKDIR
"""
import csv
import math
import pathlib
import re
import shutil
import subprocess
import sys

import meshio
import numpy as np

root = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(root / "bench"))
import deckgen  # noqa: E402  (the decks' one writer)
from checks import check, finish  # noqa: E402  (tests/checks.py: the shared tally)

gapfe = pathlib.Path(sys.argv[1]).resolve()
work = pathlib.Path(sys.argv[2]).resolve()
scenes = root / "tests" / "data" / "scenes"
E, NU, RHO = 200000.0, 0.3, 7.85e-9
A, B, P = 100.0, 200.0, 100.0
LAM, G = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
BAND = (0.7, 1.5)


def run(model, name, *options):
    out = work / name
    shutil.rmtree(out, ignore_errors=True)
    done = subprocess.run([str(gapfe), "run", str(model), "--out", str(out), "--plot", "none", *options],
                          capture_output=True, text=True)
    check(done.returncode == 0, f"{name}: exit {done.returncode}: {done.stderr.strip()}")
    return out, done.stdout


def logged_estimate(log, name):
    found = re.search(r"error estimate at the end: ([0-9.eE+-]+)% in the energy norm", log)
    check(found is not None, f"{name}: the log reports the error estimate")
    return float(found.group(1)) / 100 if found else float("nan")


def last_rows(path):
    rows = list(csv.DictReader(open(path)))
    last = max(int(r["step"]) for r in rows)
    return [r for r in rows if int(r["step"]) == last]


def lame_stress(r):
    """(rr, zz, hoop) of the Lame tube in plane strain."""
    a2, b2 = A * A, B * B
    c = P * a2 / (b2 - a2)
    return np.array([c * (1 - b2 / r ** 2), 2 * NU * c, c * (1 + b2 / r ** 2)])


def lame_u(r):
    s = lame_stress(r)
    return r / E * (s[2] - NU * (s[0] + s[1]))


def complementary(d):
    """sigma^T C^-1 sigma of the isotropic material, d = (rr, zz, hoop, rz)."""
    return (d[0] ** 2 + d[1] ** 2 + d[2] ** 2 - 2 * NU * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]) +
            2 * (1 + NU) * d[3] ** 2) / E


def bore_work(out, height, quadratic=False):
    """The true relative error of a Lame run whose form is exact: sqrt((l(u) - l(u_h)) / l(u)). Along the bore
    u_h is linear between nodes, or (quadratic cells: corner, middle, corner) quadratic, where Simpson's rule
    gives its work exactly."""
    bore = sorted((float(r["z"]), float(r["u_r"])) for r in last_rows(out / "nodes.csv")
                  if abs(float(r["r"]) - A) < 1e-9)
    if quadratic:
        work_h = sum((z2 - z0) * (u0 + 4 * u1 + u2) / 6 for (z0, u0), (_, u1), (z2, u2) in
                     zip(bore[0:-1:2], bore[1::2], bore[2::2]))
    else:
        work_h = sum(0.5 * (u0 + u1) * (z1 - z0) for (z0, u0), (z1, u1) in zip(bore, bore[1:]))
    work = lame_u(A) * height
    return math.sqrt((work - work_h) / work)


# Degree-5 rule on the reference triangle (Dunavant, 7 points; area coordinates, weights summing to 1).
_a, _b = 0.059715871789770, 0.797426985353087
_c, _d = 0.470142064105115, 0.101286507323456
TRI7 = [((1 / 3, 1 / 3), 0.225)] + [((p, q), 0.132394152788506) for p, q in ((_a, _c), (_c, _a), (_c, _c))] + \
       [((p, q), 0.125939180544827) for p, q in ((_b, _d), (_d, _b), (_d, _d))]


def triangle_error(out, height):
    """The true relative error of a Lame run on constant-strain triangles, by integration."""
    mesh = meshio.read(out / "step_0001.vtu")
    stress = mesh.cell_data["stress"]
    error2 = 0.0
    for block, values in zip(mesh.cells, stress):
        if block.type != "triangle":
            continue
        for cell, s in zip(block.data, values):
            x = mesh.points[cell][:, :2]
            area = 0.5 * abs(np.cross(x[1] - x[0], x[2] - x[0]))
            for (l2, l3), w in TRI7:
                r, _ = (1 - l2 - l3) * x[0] + l2 * x[1] + l3 * x[2]
                exact = lame_stress(r)
                d = (exact[0] - s[0], exact[1] - s[1], exact[2] - s[2], -s[3])
                error2 += w * area * 2 * math.pi * r * complementary(d)
    norm2 = P * lame_u(A) * 2 * math.pi * A * height
    return math.sqrt(error2 / norm2)


def effectivities(name, runs, finest_band=None):
    """Check each (estimate, truth) of a sequence of meshes; the finest within `finest_band` of 1."""
    for k, (label, estimate, truth) in enumerate(runs):
        ratio = estimate / truth
        print(f"  {name} {label}: estimate {estimate:.4g}, true {truth:.4g}, effectivity {ratio:.3f}")
        check(BAND[0] <= ratio <= BAND[1], f"{name} {label}: effectivity {ratio:.3f} outside {BAND}")
        if finest_band is not None and k == len(runs) - 1:
            check(abs(ratio - 1) <= finest_band, f"{name} {label}: effectivity {ratio:.3f} not within "
                                                 f"{finest_band} of 1 on the finest mesh")


def cells_agree(out, log_estimate, name):
    """The VTU's error_estimate squares sum to the log's figure squared (to its three printed digits)."""
    files = sorted(out.glob("step_*.vtu"))
    mesh = meshio.read(files[-1])
    values = np.concatenate(mesh.cell_data["error_estimate"])
    whole = math.sqrt(float(np.sum(values ** 2)))
    check(abs(whole - log_estimate) <= 0.005 * log_estimate,
          f"{name}: the cells' error_estimate give {whole:.6g}, the log {log_estimate:.6g}")
    return values


def lame_decks():
    for element in ("quad4", "quad4bbar", "legacy", "quad8"):
        runs = []
        for cells in (8, 16, 32):
            deck = work / f"lame_{element}_{cells}.deck"
            height = (B - A) * 2 / cells
            deck.write_text(deckgen.tube_deck(cells + 1, 3, extension=("format = elastic", f"element = {element}")))
            out, log = run(deck, deck.stem)
            estimate = logged_estimate(log, deck.stem)
            values = cells_agree(out, estimate, deck.stem)
            worst = int(np.argmax(values))  # deck elements row by row: column element % cells, the bore's 0
            check(worst % cells <= 1, f"{deck.stem}: the largest share in element {worst + 1}, not at the bore")
            if element == "legacy":  # its true error needs the sub-triangles' stresses: tests/test_estimate.cpp
                check(0.25 / cells < estimate < 0.4 / cells, f"{deck.stem}: estimate {estimate} far from the "
                                                             "library's (0.0392 at 8 cells, halving with the size)")
                continue
            runs.append((f"{cells} cells", estimate, bore_work(out, height)))
        if runs:
            effectivities(f"Lame deck, {element}", runs, finest_band=0.05)


def lame_gmsh():
    quadratic = lambda out, height: bore_work(out, height, quadratic=True)  # noqa: E731
    for kind, truth, sizes, element in (("quad", bore_work, (20, 10, 5), "quad4"),
                                        ("tri", triangle_error, (20, 10, 5), "quad4"),
                                        ("quad8", quadratic, (25, 12.5, 6.25), "auto"),
                                        ("tri6", quadratic, (25, 12.5, 6.25), "auto")):
        runs = []
        for h in sizes:
            scene = work / f"lame_{kind}_h{h:g}.toml"
            scene.write_text(f"""title = "Lame tube on Gmsh's {kind} mesh of size {h:g}"
[mesh]
file = "{scenes / f'lame_{kind}_h{h:g}.msh'}"
[options]
element = "{element}"
[materials.steel]
E = {E}
nu = {NU}
[[boundary]]
groups = ["bottom", "top"]
fix = ["z"]
[[load]]
curves = ["bore"]
pressure = {P}
""")
            out, log = run(scene, scene.stem)
            estimate = logged_estimate(log, scene.stem)
            runs.append((f"size {h:g}", estimate, truth(out, 50.0)))
        effectivities(f"Lame on Gmsh {kind}s", runs)


def spinning_cylinder():
    omega, radius, height = 1000.0, 100.0, 10.0
    kappa = RHO * omega ** 2 / (LAM + 2 * G)
    # u = c r - kappa r^3 / 8 with sigma_r(b) = 0: (2 lam + 2 G) c - (4 lam + 6 G) kappa b^2 / 8 = 0
    c = (4 * LAM + 6 * G) * kappa * radius ** 2 / 8 / (2 * LAM + 2 * G)
    # l(u) = int rho omega^2 r u 2 pi r dr dz
    exact_work = RHO * omega ** 2 * 2 * math.pi * height * (c * radius ** 4 / 4 - kappa * radius ** 6 / 48)
    for element in ("quad4",):
        runs = []
        for cells in (8, 16, 32):
            scene = work / f"spin_{element}_{cells}.toml"
            scene.write_text(f"""title = "spinning solid cylinder, {cells} cells"
[mesh]
grid = [{cells + 1}, 3]
[[mesh.segments]]
points = [[1, 1, 0.0, 0.0], [{cells + 1}, 1, {radius}, 0.0]]
[[mesh.segments]]
points = [[{cells + 1}, 1, {radius}, 0.0], [{cells + 1}, 3, {radius}, {height}]]
[[mesh.segments]]
points = [[{cells + 1}, 3, {radius}, {height}], [1, 3, 0.0, {height}]]
[[mesh.segments]]
points = [[1, 3, 0.0, {height}], [1, 1, 0.0, 0.0]]
[mesh.groups]
steel = {{ i = [1, {cells + 1}], j = [1, 3] }}
bottom = {{ i = [1, {cells + 1}], j = 1 }}
top = {{ i = [1, {cells + 1}], j = 3 }}
[options]
element = "{element}"
[materials.steel]
E = {E}
nu = {NU}
density = {RHO}
[[boundary]]
groups = ["bottom", "top"]
fix = ["z"]
[inertia]
angular_velocity = {omega}
""")
            out, log = run(scene, scene.stem)
            estimate = logged_estimate(log, scene.stem)
            nodes = {(round(float(r["r"]), 9), round(float(r["z"]), 9)): float(r["u_r"])
                     for r in last_rows(out / "nodes.csv")}
            rs = sorted({k[0] for k in nodes})
            zs = sorted({k[1] for k in nodes})
            gauss = [(-math.sqrt(0.6), 5 / 9), (0.0, 8 / 9), (math.sqrt(0.6), 5 / 9)]
            work_h = 0.0
            for r0, r1 in zip(rs, rs[1:]):
                for z0, z1 in zip(zs, zs[1:]):
                    for xi, wx in gauss:
                        for eta, wy in gauss:
                            s, t = (1 + xi) / 2, (1 + eta) / 2
                            u = ((1 - s) * (1 - t) * nodes[(r0, z0)] + s * (1 - t) * nodes[(r1, z0)] +
                                 s * t * nodes[(r1, z1)] + (1 - s) * t * nodes[(r0, z1)])
                            r = r0 + s * (r1 - r0)
                            work_h += wx * wy / 4 * (r1 - r0) * (z1 - z0) * RHO * omega ** 2 * r * u * 2 * math.pi * r
            runs.append((f"{cells} cells", estimate, math.sqrt((exact_work - work_h) / exact_work)))
        effectivities(f"spinning cylinder, {element}", runs, finest_band=0.05)


def other_runs():
    """Gaps, plasticity and friction: an estimate per load step, the cells agreeing, gap elements at 0; the
    notched tube's largest share at the groove's root; a free expansion with nothing to estimate."""
    for deck, options in (("two_tubes.deck", ()), ("plastic_tube.deck", ()), ("press_fit.deck", ())):
        out, log = run(root / "examples" / "decks" / deck, deck.replace(".deck", ""), *options)
        estimate = logged_estimate(log, deck)
        check(re.search(r"error estimate per load step", log) is not None, f"{deck}: the estimate per load step")
        check(0 < estimate < 1, f"{deck}: an estimate in (0, 1): {estimate}")
        values = cells_agree(out, estimate, deck)
        check(np.all(np.isfinite(values)) and np.all(values >= 0), f"{deck}: finite, non-negative cell values")
        mesh = meshio.read(sorted(out.glob("step_*.vtu"))[-1])
        if "gap_state" in mesh.cell_data:  # gap elements: no share
            gaps = np.concatenate(mesh.cell_data["gap_state"]) != 0
            check(gaps.any() and np.all(values[gaps] == 0), f"{deck}: gap elements carry no share")
    out, log = run(root / "examples" / "scenes" / "notched_tube.toml", "notched")
    estimate = logged_estimate(log, "notched")
    values = cells_agree(out, estimate, "notched")
    mesh = meshio.read(sorted(out.glob("step_*.vtu"))[-1])
    centres = np.concatenate([mesh.points[block.data][:, :, :2].mean(axis=1) for block in mesh.cells])
    r, z = centres[int(np.argmax(values))]
    check(math.hypot(r - 200, z - 50) < 30, f"notched: the largest share at ({r:.3g}, {z:.3g}), not at the groove")
    scene = work / "free_expansion.toml"
    scene.write_text(f"""title = "a tube expanding freely"
[mesh]
grid = [9, 3]
[[mesh.segments]]
points = [[1, 1, {A}, 0.0], [9, 1, {B}, 0.0]]
[[mesh.segments]]
points = [[9, 1, {B}, 0.0], [9, 3, {B}, 25.0]]
[[mesh.segments]]
points = [[9, 3, {B}, 25.0], [1, 3, {A}, 25.0]]
[[mesh.segments]]
points = [[1, 3, {A}, 25.0], [1, 1, {A}, 0.0]]
[mesh.groups]
steel = {{ i = [1, 9], j = [1, 3] }}
bottom = {{ i = [1, 9], j = 1 }}
[materials.steel]
E = {E}
nu = {NU}
alpha = 1.2e-5
[[boundary]]
groups = ["bottom"]
fix = ["z"]
[temperature]
value = 100.0
""")
    _, log = run(scene, "free_expansion")
    check("error estimate at the end: none, the stresses are round-off" in log,
          "free expansion: the log says there is nothing to estimate")


def without_estimate():
    """error_estimate = none: the log says so, and every result but the estimate's array is the same, bit for
    bit (a run takes its centroid stresses from the estimate's pass; without it, from their own): the tables
    byte for byte, the VTU's arrays exactly. On the legacy quadrilateral (its condensed centre), a plastic run
    (stored stresses) and a gap run (skipped gap elements)."""
    for deck in ("thick_tube.deck", "plastic_tube.deck", "two_tubes.deck"):
        name = deck.replace(".deck", "")
        with_it, _ = run(root / "examples" / "decks" / deck, name + "_estimated")
        without, log = run(root / "examples" / "decks" / deck, name + "_none", "--set", "error_estimate=none")
        check("error estimate: none (error_estimate = none)" in log and "error estimate at the end" not in log,
              f"{deck}: the log says the run made no estimate")
        for table in ("nodes.csv", "elements.csv", "reactions.csv"):
            check((with_it / table).read_bytes() == (without / table).read_bytes(),
                  f"{deck}: {table} is the same with and without the estimate")
        a = meshio.read(sorted(with_it.glob("step_*.vtu"))[-1])
        b = meshio.read(sorted(without.glob("step_*.vtu"))[-1])
        check("error_estimate" in a.cell_data and "error_estimate" not in b.cell_data,
              f"{deck}: error_estimate only in the run that estimates")
        same = all(np.array_equal(np.concatenate(a.cell_data[k]), np.concatenate(b.cell_data[k]))
                   for k in b.cell_data) and all(np.array_equal(a.point_data[k], b.point_data[k])
                                                 for k in b.point_data)
        check(same and set(b.cell_data) | {"error_estimate"} == set(a.cell_data),
              f"{deck}: the VTU's other arrays are the same")


work.mkdir(parents=True, exist_ok=True)
lame_decks()
lame_gmsh()
spinning_cylinder()
other_runs()
without_estimate()
finish("check_estimate: ")
