#!/usr/bin/env python3
"""Partitioned runs through the command against the serial CHOLMOD answers:

    python3 tests/check_partitioned.py GAPFE MPIEXEC WORK [RANKS...]

For the thick tube, the two tubes with a gap and the plastic tube (examples/decks), and on finer versions
of the first two written here (bench/deckgen.py: 40 x 20 and two 20 x 20 tubes, so that every rank holds
many cells and the cut crosses the gap), `gapfe run DECK --solver cholmod` once and
`MPIEXEC -np N gapfe run DECK --solver petsc` for every N in RANKS (default 1 2). Each rank writes its own
part (docs/cluster.md "Output"): the tables nodes_pK.csv, elements_pK.csv, reactions_pK.csv, joined here
into whole tables (every node and element in exactly one part), and the VTU pieces step_NNNN_pK.vtu, read
with meshio (a reader independent of gapfe's), listed by step_NNNN.pvtu, read with Python's XML parser (and
with VTK's own parallel reader when python3-vtk9 is installed), which result.pvd lists. Every numeric column
of every CSV table the runs write (nodes, reactions, elements, gaps, history, plasticity) must agree to 1e-8
relative to its field: max |petsc - cholmod| <= 1e-8 max |cholmod| over the column and the columns of the
same field in any table of the run (u_r, u_z, u_t and u_max are one displacement field, the six stresses
one stress, R_* one reaction, f_n and f_t one pair force; a component that is round-off throughout, such as
u_z of a plane-strain tube or the summed axial reaction in history.csv, is measured against its field). The tables must have the same rows (the same increments, nodes and elements)
and the same contact states. The logged error estimate agrees too (compare_estimates). The pieces of a run on
more than one rank must hold every node and element of the serial run's VTU files, with its points, cells and arrays (compare_pieces).
One case also runs with output_parts = gathered, whose rank 0 writes the whole tables as one process does,
and `gapfe plot` draws from the pieces. Exit status 0 when all agree, 1 otherwise."""
import csv
import glob
import math
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

import meshio
import numpy as np

try:
    import vtk
except ImportError:
    vtk = None

sys.dont_write_bytecode = True
HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "bench"))
import deckgen  # noqa: E402
import check_matrix  # noqa: E402  (its fit and deck writer)

TOLERANCE = 1e-8
TABLES = ["nodes.csv", "reactions.csv", "elements.csv", "gaps.csv", "history.csv", "plasticity.csv"]
EXACT = {"step", "node", "element", "pair", "i", "j", "material", "status", "iterations", "plastic_points",
         "closed", "slipping"}


def field(column):
    """The field a column belongs to: its prefix for displacement, stress, reaction and pair-force components."""
    if column in ("applied_z", "reaction_z"):  # the global balance's sums: round-off where they cancel
        return "R_"
    if column in ("applied_torque", "reaction_torque", "gap_torque"):  # its torques, one field
        return "torque"
    prefix = column.split("_")[0] + "_"
    return prefix if prefix in ("u_", "s_", "R_", "f_") else column
SKIPPED = {"residual", "residuals", "drift", "balance"}  # round-off measures, not answers


def read(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


PARTS = {"nodes.csv": "node", "reactions.csv": "node", "elements.csv": "element"}


def read_parts(folder, name):
    """A table a partitioned run writes per rank (nodes_pK.csv, ...), joined: one header, the parts' rows in the
    serial table's order (by increment, then node or element). None when the run wrote no part of it."""
    stem = name[:-4]
    paths = sorted(glob.glob(os.path.join(folder, stem + "_p*.csv")),
                   key=lambda p: int(re.search(r"_p(\d+)\.csv$", p).group(1)))
    if not paths:
        return None
    head, joined = None, []
    for path in paths:
        h, rows = read(path)
        if head is not None and h != head:
            raise ValueError(f"{path}: header {h[:4]}... differs from the first part's")
        head = h
        joined += rows
    step, inc, key = head.index("step"), head.index("inc"), head.index(PARTS[name])
    joined.sort(key=lambda r: (int(r[step]), float(r[inc]), int(r[key])))
    return head, joined


def field_scales(serial_dir):
    """The largest |value| of every field over every table of a run: history.csv's summed reactions (R_z_bc1,
    round-off where they cancel) are measured against the reactions they sum."""
    scales = {}
    for name in TABLES:
        path = os.path.join(serial_dir, name)
        if not os.path.exists(path):
            continue
        head, rows = read(path)
        for k, col in enumerate(head):
            if col in EXACT or col in SKIPPED:
                continue
            try:
                values = [abs(float(r[k])) for r in rows]
            except ValueError:
                continue
            scales[field(col)] = max(scales.get(field(col), 0), max(values, default=0))
    return scales


def compare(name, serial_dir, part_dir, scales):
    """Returns a list of failures (text)."""
    failures = []
    a_path, b_path = os.path.join(serial_dir, name), os.path.join(part_dir, name)
    if not os.path.exists(a_path):
        return []
    parts = read_parts(part_dir, name) if name in PARTS else None
    if parts and os.path.exists(b_path):
        return [f"{name}: both the whole table and the parts' tables"]
    if not parts and not os.path.exists(b_path):
        return [f"{name}: missing from the partitioned run"]
    head_a, rows_a = read(a_path)
    head_b, rows_b = parts or read(b_path)
    if head_a != head_b or len(rows_a) != len(rows_b):
        return [f"{name}: {len(rows_b)} rows / header {head_b[:4]}... against {len(rows_a)} / {head_a[:4]}..."]
    numeric = {}
    for k, col in enumerate(head_a):
        if col in SKIPPED:
            continue
        a = [r[k] for r in rows_a]
        b = [r[k] for r in rows_b]
        if col in EXACT:
            if a != b:
                failures.append(f"{name}: column {col} differs (first at row {next(i for i in range(len(a)) if a[i] != b[i]) + 2})")
            continue
        try:
            numeric[col] = ([float(x) for x in a], [float(x) for x in b])
        except ValueError:
            if a != b:
                failures.append(f"{name}: column {col} differs")
    worst = 0
    for col, (a, b) in numeric.items():
        scale = scales[field(col)]
        diff = max((abs(x - y) for x, y in zip(a, b)), default=0)
        rel = diff / scale if scale > 0 else diff
        worst = max(worst, rel)
        if rel > TOLERANCE:
            failures.append(f"{name}: column {col} differs by {rel:.2e} relative to its field (max |cholmod| {scale:.3e})")
    print(f"    {name}: {len(rows_a)} rows, largest relative difference {worst:.1e}")
    return failures


def datasets(folder):
    """result.pvd's (timestep, file) pairs, read with Python's XML parser."""
    root = ET.parse(os.path.join(folder, "result.pvd")).getroot()
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]


def cell_array(mesh, name):
    """A cell array of a meshio mesh, its blocks joined, one row per cell."""
    return np.concatenate([np.asarray(a).reshape(len(a), -1) for a in mesh.cell_data[name]])


def compare_pieces(serial_dir, part_dir, ranks, last_only=False, estimate=False, tolerance=TOLERANCE):
    """The pieces of every increment against the serial run's VTU file (both read with meshio): each piece's
    points are its nodes' (the point array `node`), with their displacement and reaction; each element is in
    exactly one piece, on the same nodes, with the same cell arrays (error_estimate only on one rank: a part's
    patches are one-sided at its edges); every node is in some piece. The .pvtu lists the pieces in rank order
    and declares the arrays they hold. `last_only`: the part's run wrote its last increment only (output = last);
    `estimate`: compare error_estimate too (against a run on the same partition); `tolerance` relative to each
    array's largest value. Returns a list of failures."""
    failures = []
    serial_sets, part_sets = datasets(serial_dir), datasets(part_dir)
    if last_only:
        serial_sets = serial_sets[-1:]
    if len(serial_sets) != len(part_sets) or \
            any(abs(a - b) > 1e-9 * max(abs(a), 1) for (a, _), (b, _) in zip(serial_sets, part_sets)):
        return [f"result.pvd: times {[t for t, _ in part_sets]} against {[t for t, _ in serial_sets]}"]
    # Each array's scale is its largest |value| over the whole serial run, as field_scales' for the tables: at a
    # split point where every gap closes, the gaps are round-off against the run's.
    serials = {f: meshio.read(os.path.join(serial_dir, f)) for _, f in serial_sets}
    scale = {}
    for mesh in serials.values():
        arrays = [(n, v) for n, v in mesh.point_data.items()] + [(n, cell_array(mesh, n)) for n in mesh.cell_data]
        for name, values in arrays:
            scale[name] = max(scale.get(name, 1e-300), float(np.abs(values).max()))
    worst = 0.0
    for (_, serial_file), (_, part_file) in zip(serial_sets, part_sets):
        stem = serial_file[:-4]
        if part_file != stem + ".pvtu":
            failures.append(f"result.pvd lists {part_file}, expected {stem}.pvtu")
            continue
        grid = ET.parse(os.path.join(part_dir, part_file)).getroot().find("PUnstructuredGrid")
        sources = [p.get("Source") for p in grid.findall("Piece")]
        if sources != [f"{stem}_p{k}.vtu" for k in range(ranks)]:
            failures.append(f"{part_file}: pieces {sources}")
            continue
        declared = {kind: [a.get("Name") for a in grid.find(kind)] for kind in ("PPointData", "PCellData")}
        serial = serials[serial_file]
        s_elements = cell_array(serial, "element")[:, 0].astype(int)
        position = {e: k for k, e in enumerate(s_elements)}
        s_cells = [list(c) for block in serial.cells for c in block.data]
        seen_nodes = np.zeros(len(serial.points), dtype=int)
        seen_elements = np.zeros(len(s_elements), dtype=int)
        for source in sources:
            piece = meshio.read(os.path.join(part_dir, source))
            if sorted(piece.point_data) != sorted(declared["PPointData"]) or \
                    sorted(piece.cell_data) != sorted(declared["PCellData"]):
                failures.append(f"{source}: arrays {sorted(piece.point_data)} {sorted(piece.cell_data)} against "
                                f"the .pvtu's {declared}")
                continue
            node = piece.point_data["node"].reshape(-1).astype(int) - 1
            seen_nodes[node] = 1
            if not np.array_equal(piece.points, serial.points[node]):
                failures.append(f"{source}: a point is not its node's")
            for name in ("displacement", "reaction"):
                rel = np.abs(piece.point_data[name] - serial.point_data[name][node]).max() / scale[name]
                worst = max(worst, rel)
                if rel > tolerance:
                    failures.append(f"{source}: {name} differs by {rel:.2e} relative to its field")
            at = [position[e] for e in cell_array(piece, "element")[:, 0].astype(int)]
            np.add.at(seen_elements, at, 1)
            cells = [list(c) for block in piece.cells for c in block.data]
            if any(sorted(node[c].tolist()) != sorted(s_cells[k]) for c, k in zip(cells, at)):
                failures.append(f"{source}: a cell is not on its element's nodes")
            for name in piece.cell_data:
                if name == "error_estimate" and ranks > 1 and not estimate:
                    continue
                rel = np.abs(cell_array(piece, name) - cell_array(serial, name)[at]).max() / scale[name]
                worst = max(worst, rel)
                if rel > tolerance:
                    failures.append(f"{source}: cell array {name} differs by {rel:.2e} relative to its field")
        if not seen_nodes.all() or not (seen_elements == 1).all():
            failures.append(f"{stem}: the pieces miss {int((seen_nodes == 0).sum())} node(s); "
                            f"{int((seen_elements != 1).sum())} element(s) are not in exactly one piece")
        if vtk:  # VTK's own reader of the parallel file, when installed
            reader = vtk.vtkXMLPUnstructuredGridReader()
            reader.SetFileName(os.path.join(part_dir, part_file))
            reader.Update()
            grid_out = reader.GetOutput()
            if grid_out.GetNumberOfCells() != len(s_elements) or \
                    grid_out.GetPointData().GetArray("displacement") is None:
                failures.append(f"{part_file}: VTK reads {grid_out.GetNumberOfCells()} cells, expected "
                                f"{len(s_elements)}, with a displacement array")
    print(f"    VTU pieces of {len(part_sets)} increment(s): largest relative difference {worst:.1e}"
          f"{'' if vtk else ' (VTK not installed: its .pvtu reader not tried)'}")
    return failures


def compare_estimates(serial_log, part_log, ranks):
    """The logged error estimate (docs/accuracy.md): a part recovers from its own cells, so at the parts' edges
    its patches are one-sided: one rank gives the serial figure (to a unit in its third printed digit), more
    ranks within 10%."""
    def estimate(log):
        found = re.search(r"error estimate at the end: ([0-9.eE+-]+)%", log)
        return float(found.group(1)) if found else None
    serial, part = estimate(serial_log), estimate(part_log)
    if serial is None or part is None:
        return [f"no error estimate in the log (serial {serial}, partitioned {part})"]
    if serial == 0 or part == 0:
        return [] if serial == part else [f"error estimate {part}% against the serial run's {serial}%"]
    printed = 10 ** (math.floor(math.log10(serial)) - 2)  # a unit in the third digit the log prints
    limit = printed if ranks == 1 else 0.1 * serial
    if abs(part - serial) > limit * (1 + 1e-9):
        return [f"error estimate {part}% against the serial run's {serial}% (limit {limit:.3g})"]
    return []


def other_ways(gapfe, mpiexec, ranks, deck, part, serial, env, work):
    """The same run with output_parts = gathered: rank 0 writes the whole tables, as one process does, and no
    part's; its VTU files equal the pieces to 1e-10, error_estimate too (the same partition). With output = last and the
    default pictures: the pieces of the last increment (held to the run's end), deformed.svg and plot_mises.svg
    from the results gathered for them. `gapfe plot` on the pieces' folder draws the last increment from them.
    A mesh of more than 20,000 cells draws no pictures in a partitioned run, and says so."""
    failures = []

    def again(out, *more, plots=("--plot", "none"), model=deck):
        line = [mpiexec, "-np", str(ranks), gapfe, "run", model, "--out", out, "--solver", "petsc", *plots, *more]
        return subprocess.run(line, env=env, capture_output=True, text=True, timeout=600)

    gathered = part + "_gathered"
    done = again(gathered, "--set", "output_parts=gathered")
    if done.returncode != 0:
        return [f"output_parts = gathered: exit {done.returncode}: {done.stderr.strip()}"]
    if glob.glob(os.path.join(gathered, "*_p*.csv")) or glob.glob(os.path.join(gathered, "*.pvtu")):
        failures.append("output_parts = gathered wrote a part's files")
    scales = field_scales(serial)
    for table in TABLES:
        failures += [f"gathered, {f}" for f in compare(table, serial, gathered, scales)]
    failures += [f"pieces against gathered, {f}"
                 for f in compare_pieces(gathered, part, ranks, estimate=True, tolerance=1e-10)]
    last = part + "_last"
    done = again(last, "--set", "output=last", plots=())
    if done.returncode != 0:
        return failures + [f"output = last: exit {done.returncode}: {done.stderr.strip()}"]
    failures += [f"output = last, {f}" for f in compare_pieces(serial, last, ranks, last_only=True)]
    for picture in ("deformed.svg", "plot_mises.svg"):
        if not os.path.exists(os.path.join(last, picture)):
            failures.append(f"output = last: no {picture}")
    plot = subprocess.run([gapfe, "plot", part, "--no-png"], env=env, capture_output=True, text=True)
    if plot.returncode != 0 or not os.path.exists(os.path.join(part, "plot_mises.svg")):
        failures.append(f"gapfe plot on the pieces: exit {plot.returncode}: {plot.stderr.strip()}")
    large = os.path.join(work, "tube_150x140.deck")  # 21,000 cells
    with open(large, "w") as f:
        f.write(deckgen.tube_deck(151, 141, h=50.0))
    done = again(os.path.join(work, "large_pieces"), plots=(), model=large)
    said = "pictures not drawn: deformed.svg and the fields: 21000 cells in a partitioned run"
    if done.returncode != 0 or said not in done.stdout or \
            os.path.exists(os.path.join(work, "large_pieces", "deformed.svg")):
        failures.append(f"21,000 cells on {ranks} ranks: exit {done.returncode}, expected the log to say "
                        f"'{said}' and no deformed.svg")
    return failures


def main():
    gapfe, mpiexec, work = sys.argv[1:4]
    ranks = [int(n) for n in sys.argv[4:]] or [1, 2]
    os.makedirs(work, exist_ok=True)
    decks = {name: os.path.join(HERE, "..", "examples", "decks", name + ".deck")
             for name in ["thick_tube", "two_tubes", "plastic_tube"]}
    # The global balance's terms summed over the parts: body forces along the axis and about it (a 3-DOF fit
    # under an axial and an angular acceleration, tests/check_matrix.py's) and the gap pairs' torque (a press
    # fit pushed and twisted, Coulomb).
    fit = {"element": "legacy", "dofs": 3, "contact": "active-set", "policy": "active-set", "plastic": False,
           "name": "partitioned"}
    for name, text in {"tube_40x20": deckgen.tube_deck(41, 21, h=50.0),
                       "two_tubes_20x20": deckgen.two_tubes_deck(n=20, nz=20, a=50.0, b=75.0, gap=0.02, c=100.0,
                                                                 steps=10, contact="active-set"),
                       "fit_angular_acceleration": check_matrix.deck(dict(fit, load="angular_acceleration"),
                                                                     check_matrix.Body(True)),
                       "fit_axial_acceleration": check_matrix.deck(dict(fit, load="axial_acceleration"),
                                                                   check_matrix.Body(True)),
                       "press_fit_twisted": deckgen.press_fit_deck(ns=4, nh=4, nz=6, steps=4, twist=0.001)}.items():
        decks[name] = os.path.join(work, name + ".deck")
        with open(decks[name], "w") as f:
            f.write(text)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1",
               OMPI_MCA_mpi_yield_when_idle="1")  # a waiting rank gives its core to the others
    failures = []
    for name, deck in decks.items():
        serial = os.path.join(work, name + "_cholmod")
        serial_log = subprocess.run([gapfe, "run", deck, "--out", serial, "--solver", "cholmod", "--plot", "none"],
                                    check=True, env=env, capture_output=True, text=True).stdout
        for n in ranks:
            part = os.path.join(work, f"{name}_petsc_{n}")
            cmd = [mpiexec, "-np", str(n), gapfe, "run", deck, "--out", part, "--solver", "petsc", "--plot", "none"]
            done = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
            print(f"{name}, {n} rank(s):")
            if done.returncode != 0:
                failures.append(f"{name}, {n} rank(s): exit {done.returncode}: {done.stderr.strip()}")
                continue
            scales = field_scales(serial)
            for table in TABLES:
                failures += [f"{name}, {n} rank(s), {f}" for f in compare(table, serial, part, scales)]
            failures += [f"{name}, {n} rank(s), {f}" for f in compare_estimates(serial_log, done.stdout, n)]
            if n > 1:  # one process writes a serial run's files (the tables compared above)
                failures += [f"{name}, {n} rank(s), {f}" for f in compare_pieces(serial, part, n)]
            if name == "two_tubes_20x20" and n == max(ranks) and n > 1:
                failures += [f"{name}, {n} rank(s), {f}" for f in other_ways(gapfe, mpiexec, n, deck, part, serial, env, work)]
    for f in failures:
        print("FAIL", f)
    print("all partitioned runs agree with CHOLMOD to 1e-8" if not failures else f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
