#!/usr/bin/env python3
"""Partitioned runs through the command against the serial CHOLMOD answers:

    python3 tests/check_partitioned.py GAPFE MPIEXEC WORK [RANKS...]

For the thick tube, the two tubes with a gap and the plastic tube (examples/decks), and on finer versions
of the first two written here (bench/deckgen.py: 40 x 20 and two 20 x 20 tubes, so that every rank holds
many cells and the cut crosses the gap), `gapfe run DECK --solver cholmod` once and
`MPIEXEC -np N gapfe run DECK --solver petsc` for every N in RANKS (default 1 2). Every numeric column of
every CSV table the runs write (nodes, reactions, elements, gaps, history, plasticity) must agree to 1e-8
relative to its field: max |petsc - cholmod| <= 1e-8 max |cholmod| over the column and the columns of the
same field in any table of the run (u_r, u_z, u_t and u_max are one displacement field, the six stresses
one stress, R_* one reaction, f_n and f_t one pair force; a component that is round-off throughout, such as
u_z of a plane-strain tube or the summed axial reaction in history.csv, is measured against its field). The tables must have the same rows (the same increments, nodes and elements)
and the same contact states. The logged error estimate agrees too (compare_estimates). Exit status 0 when all
agree, 1 otherwise."""
import csv
import math
import os
import re
import subprocess
import sys

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
    if not os.path.exists(b_path):
        return [f"{name}: missing from the partitioned run"]
    head_a, rows_a = read(a_path)
    head_b, rows_b = read(b_path)
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
    for f in failures:
        print("FAIL", f)
    print("all partitioned runs agree with CHOLMOD to 1e-8" if not failures else f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
