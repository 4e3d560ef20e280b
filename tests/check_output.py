#!/usr/bin/python3
"""The command's output read back by real readers (ctest `output`):

  * every VTU file through meshio (Debian's python3-meshio, a reader independent of gapfe's writer and of its
    input/vtu_reader.hpp): points, cells and every array equal to the CSV tables of the same run, bit for bit;
    result.pvd through Python's XML parser: every file it names exists, the time steps are the tables' t;
  * every SVG picture through Python's XML parser: the colour bar's range equals the field's least and
    greatest value (computed here from the VTU file read by meshio), every cell is drawn once, every title line
    fits the page.
Cases: a 2-DOF quadrilateral tube, a 3-DOF helical sleeve (SAGA), a Gmsh scene of triangles and quadrangles,
and a contact run whose steps are split (step_NNNN_split_K.vtu).

    /usr/bin/python3 tests/check_output.py build/release/examples/gapfe WORKDIR
"""
import csv
import math
import pathlib
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

import meshio
import numpy as np
from checks import check, finish  # noqa: E402  (tests/checks.py: the shared tally)

gapfe = pathlib.Path(sys.argv[1]).resolve()
work = pathlib.Path(sys.argv[2]).resolve()
root = pathlib.Path(__file__).resolve().parent.parent
SVG = "{http://www.w3.org/2000/svg}"


def run(source, name, *extra):
    out = work / name
    shutil.rmtree(out, ignore_errors=True)
    subprocess.run([gapfe, "run", source, "--out", out, "--quiet", *extra], check=True)
    return out


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def by_increment(table):
    """Rows grouped by their t (the increment), in order."""
    groups = {}
    for r in table:
        groups.setdefault(float(r["t"]), []).append(r)
    return groups


def cells_in_order(mesh):
    """meshio's cell blocks (consecutive runs of one type, in the file's order) back as one list."""
    out = []
    for block in mesh.cells:
        out.extend(list(c) for c in block.data)
    return out


def cell_array(mesh, name):
    a = np.concatenate([np.asarray(block) for block in mesh.cell_data[name]])
    return a.ravel() if a.ndim == 2 and a.shape[1] == 1 else a


def check_run(out, dofs, gaps=False):
    label = out.name
    nodes, elements = by_increment(rows(out / "nodes.csv")), by_increment(rows(out / "elements.csv"))
    reactions = by_increment(rows(out / "reactions.csv"))
    gap_rows = by_increment(rows(out / "gaps.csv")) if gaps else {}
    collection = ET.parse(out / "result.pvd").getroot()
    datasets = [(float(d.get("timestep")), d.get("file")) for d in collection.iter("DataSet")]
    check(len(datasets) > 0, f"{label}: result.pvd lists files")
    check([t for t, _ in datasets] == sorted(t for t, _ in datasets), f"{label}: result.pvd's times increase")
    check(sorted(t for t, _ in datasets) == sorted(nodes), f"{label}: one VTU file per increment of nodes.csv")
    splits = 0
    for t, file in datasets:
        check((out / file).exists(), f"{label}: {file} exists")
        splits += "_split_" in file
        mesh = meshio.read(out / file)
        where = f"{label}/{file}"
        table = nodes[t]
        check(len(mesh.points) == len(table), f"{where}: one point per node")
        r = np.array([[float(x["r"]), float(x["z"])] for x in table])
        check(np.array_equal(mesh.points[:, :2], r), f"{where}: points are the nodes' (r, z)")
        u = np.array([[float(x["u_r"]), float(x["u_z"]), float(x["u_t"])] for x in table])
        check(np.array_equal(mesh.point_data["displacement"], u), f"{where}: displacement = nodes.csv")
        if dofs == 2:
            check(not mesh.point_data["displacement"][:, 2].any(), f"{where}: u_t = 0 in 2 DOF")
        # reactions.csv lists the prescribed nodes, their free components written as 0 (output/step_files.hpp)
        reaction = mesh.point_data["reaction"]
        for x in reactions.get(t, []):
            n = int(x["node"]) - 1
            for c, name in enumerate(("R_r", "R_z", "R_t")):
                value = float(x[name])
                check(value == 0 or value == reaction[n, c], f"{where}: reaction of node {n + 1} {name}")
        # cells: element numbers map meshio's order back to elements.csv's
        cells = cells_in_order(mesh)
        ids = cell_array(mesh, "element").astype(int)
        check(sorted(ids) == list(range(1, len(cells) + 1)), f"{where}: every element once")
        check(len(cells) == len(elements[t]), f"{where}: one cell per element row")
        stress, eqps = cell_array(mesh, "stress"), cell_array(mesh, "eqps")
        material = cell_array(mesh, "material").astype(int)
        order = ("s_rr", "s_zz", "s_tt", "s_rz", "s_zt", "s_rt")  # the VTU's Voigt order: rr zz tt rz z-t t-r
        for k, e in enumerate(ids):
            x = elements[t][e - 1]
            check(int(x["element"]) == e, f"{where}: elements.csv row of element {e}")
            check(all(float(x[n]) == stress[k, j] for j, n in enumerate(order)), f"{where}: stress of element {e}")
            check(float(x["eqps"]) == eqps[k], f"{where}: eqps of element {e}")
            check(int(x["material"]) == material[k], f"{where}: material of element {e}")
        if gaps:
            force = cell_array(mesh, "contact_force")
            expected = {}
            for g in gap_rows[t]:
                expected[int(g["element"])] = expected.get(int(g["element"]), 0.0) + float(g["f_n"])
            for k, e in enumerate(ids):
                check(math.isclose(force[k], expected.get(e, 0.0), rel_tol=1e-12, abs_tol=1e-300),
                      f"{where}: contact_force of element {e} = sum of gaps.csv's f_n")
    return splits


def field_values(mesh, field):
    """A field as plot_FIELD.svg colours it, computed here from meshio's arrays (output/field_plot.hpp's list)."""
    u = mesh.point_data["displacement"]
    if field in ("u", "u_r", "u_z", "u_t"):
        return np.linalg.norm(u, axis=1) if field == "u" else u[:, ("u_r", "u_z", "u_t").index(field)]
    s = cell_array(mesh, "stress")
    slots = {"s_rr": 0, "s_zz": 1, "s_tt": 2, "s_rz": 3, "s_zt": 4, "s_rt": 5}
    if field in slots:
        return s[:, slots[field]]
    if field == "mises":
        normal = (s[:, 0] - s[:, 1]) ** 2 + (s[:, 1] - s[:, 2]) ** 2 + (s[:, 2] - s[:, 0]) ** 2
        return np.sqrt(0.5 * normal + 3 * (s[:, 3] ** 2 + s[:, 4] ** 2 + s[:, 5] ** 2))
    return cell_array(mesh, field)


def check_titles(svg, where):
    width = float(svg.get("width"))
    for t in svg.iter(SVG + "text"):
        if t.get("class") == "title":
            # output/svg_canvas.hpp wraps at 0.6 x the font size per character, a generous sans-serif width
            check(float(t.get("x")) + 0.6 * float(t.get("font-size")) * len(t.text) <= width,
                  f"{where}: title line '{t.text[:30]}...' fits")


def check_picture(out, field, vtu):
    where = f"{out.name}/plot_{field}.svg"
    svg = ET.parse(out / f"plot_{field}.svg").getroot()
    mesh = meshio.read(out / vtu)
    values = field_values(mesh, field)
    bar = [g for g in svg.iter(SVG + "g") if g.get("class") == "colorbar"]
    check(len(bar) == 1, f"{where}: one colour bar")
    check(float(bar[0].get("data-min")) == values.min(), f"{where}: colour bar from the field's least value")
    check(float(bar[0].get("data-max")) == values.max(), f"{where}: colour bar to the field's greatest value")
    ticks = [float(t.text) for t in bar[0].iter(SVG + "text")]
    check(math.isclose(ticks[0], values.min(), rel_tol=1e-3, abs_tol=1e-12) and
          math.isclose(ticks[-1], values.max(), rel_tol=1e-3, abs_tol=1e-12), f"{where}: the bar's end labels")
    drawn = [int(p.get("data-cell")) for p in svg.iter(SVG + "polygon") if p.get("class") == "cell"]
    check(sorted(drawn) == list(range(1, len(cells_in_order(mesh)) + 1)), f"{where}: every cell drawn once")
    check_titles(svg, where)


work.mkdir(parents=True, exist_ok=True)
decks = root / "examples" / "decks"
tube = run(decks / "thick_tube.deck", "tube", "--plot", "mises", "--plot", "u_r", "--plot", "s_tt")
check_run(tube, 2)
for field in ("mises", "u_r", "s_tt"):
    check_picture(tube, field, "step_0001.vtu")
sleeve = run(decks / "helical_sleeve.deck", "sleeve", "--plot", "u_t", "--plot", "s_rt")
check_run(sleeve, 3)
last = ET.parse(sleeve / "result.pvd").getroot().findall(".//DataSet")[-1].get("file")
check(np.abs(meshio.read(sleeve / last).point_data["displacement"][:, 2]).max() > 0, "sleeve: u_t is not 0")
for field in ("u_t", "s_rt"):
    check_picture(sleeve, field, last)
notched = run(root / "examples" / "scenes" / "notched_tube.toml", "notched", "--plot", "s_tt")
check_run(notched, 2)
types = {block.type for block in meshio.read(notched / "step_0001.vtu").cells}
check(types == {"triangle", "quad"}, f"notched: triangles and quadrangles ({types})")
check_picture(notched, "s_tt", "step_0001.vtu")
tubes = run(decks / "two_tubes.deck", "two_tubes", "--plot", "contact_force", "--plot", "gap_state")
check(check_run(tubes, 2, gaps=True) > 0, "two_tubes: split steps written")
last = ET.parse(tubes / "result.pvd").getroot().findall(".//DataSet")[-1].get("file")
for field in ("contact_force", "gap_state"):
    check_picture(tubes, field, last)
# gapfe plot on a finished run: another step, another field
subprocess.run([gapfe, "plot", tubes, "--field", "u", "--step", "3", "--quiet", "--no-png"], check=True)
svg = ET.parse(tubes / "plot_u_step_0003.svg").getroot()
values = field_values(meshio.read(tubes / "step_0003.vtu"), "u")
bar = [g for g in svg.iter(SVG + "g") if g.get("class") == "colorbar"][0]
check(float(bar.get("data-max")) == values.max(), "gapfe plot --step 3: the bar ends at step 3's largest |u|")
for picture in ("deformed.svg", "curve_load_factor_u_max.svg"):
    check_titles(ET.parse(tubes / picture).getroot(), f"two_tubes/{picture}")
mesh_dir = work / "mesh"
subprocess.run([gapfe, "mesh", decks / "projectile.deck", "--out", mesh_dir, "--quiet"], check=True)
check_titles(ET.parse(mesh_dir / "mesh.svg").getroot(), "projectile/mesh.svg")

finish()
