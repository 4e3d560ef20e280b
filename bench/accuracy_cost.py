#!/usr/bin/python3
"""What `gapfe run --accuracy TOL` costs on the Lame tube (BENCHMARKS.md "`--accuracy` with the recovered peak
stress and the order choice"): the deck of tests/check_error_bars.py (bench/deckgen.py tube_deck, 8 cells
through the wall, 2 up; a = 100, b = 200, bore pressure 100, plane strain) with its element named (quad4,
quad8: the ladder keeps it) or left to gapfe (auto: the legacy cell, and the order choice), against one
`gapfe run` of the deck on the mesh the quad4 ladder ends on, and on the atlas' cheapest setting for 1e-3
(bench/ATLAS.md "lame": quad4, 16 cells through the wall). Whole processes, median of `--repeat` runs (7),
`--plot none`; each ladder's last mesh, and its true relative errors against the closed forms (the bore's von
Mises stress and u_r).

    /usr/bin/python3 bench/accuracy_cost.py build/release/examples/gapfe WORKDIR [--repeat 7]
"""
import csv
import math
import pathlib
import statistics
import subprocess
import sys
import time

root = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(root / "bench"))
import deckgen  # noqa: E402  (bench/deckgen.py)

gapfe, work = pathlib.Path(sys.argv[1]).resolve(), pathlib.Path(sys.argv[2]).resolve()
repeat = int(sys.argv[sys.argv.index("--repeat") + 1]) if "--repeat" in sys.argv else 7
work.mkdir(parents=True, exist_ok=True)
E, NU, A, B, P = 200000.0, 0.3, 100.0, 200.0, 100.0
s = P * A * A / (B * B - A * A)
sigma = (-P, 2 * NU * s, s * (B * B + A * A) / (A * A))
TRUTH = {"largest von Mises": math.sqrt(0.5 * sum((sigma[k] - sigma[(k + 1) % 3]) ** 2 for k in range(3))),
         "largest |u|": (1 + NU) / E * s * ((1 - 2 * NU) * A + B * B / A)}


def deck(name, ni, nj, element):
    path = work / f"{name}.deck"
    extension = ("format = elastic",) + ((f"element = {element}",) if element != "auto" else ())
    path.write_text(deckgen.tube_deck(ni, nj, extension=extension))
    return path


def timed(args):
    times, log = [], ""
    for _ in range(repeat):
        start = time.perf_counter()
        done = subprocess.run([str(gapfe), "run", *map(str, args), "--overwrite", "--plot", "none"],
                              capture_output=True, text=True)
        times.append(time.perf_counter() - start)
        log = done.stdout + done.stderr
    return statistics.median(times), log


print("| tolerance | run | last mesh | true error: von Mises, |u| | `gapfe run` [s] |")
print("|---|---|---|---|---|")
for tolerance in (1e-3, 1e-4):
    for element in ("quad4", "auto", "quad8"):
        out = work / f"{element}_{tolerance:g}"
        seconds, log = timed([deck(f"lame_{element}", 9, 3, element), "--out", out, "--accuracy", tolerance])
        reached = [line for line in log.splitlines() if line.startswith("accuracy: reached on ")]
        if not reached:
            print(f"| {tolerance:g} | `--accuracy`, element {element} | not reached: {log.strip()[-200:]} | | |")
            continue
        rows = {r["quantity"]: r for r in csv.DictReader(open(out / "estimates.csv"))}
        errors = [abs(abs(float(rows[q]["value"])) - v) / v for q, v in TRUTH.items()]
        nodes = sum(1 for _ in open(out / "nodes.csv")) - 1
        where = reached[0].split("reached on ")[1].split(";")[0]
        print(f"| {tolerance:g} | `--accuracy`, element {element} | {where}, {nodes} nodes | "
              f"{errors[0]:.2g}, {errors[1]:.2g} | {seconds:.4f} |")
    if tolerance == 1e-3:
        for name, ni, nj in (("the quad4 ladder's last mesh alone", 65, 17), ("the atlas' cheapest for 1e-3", 17, 3)):
            out = work / f"single_{ni}"
            seconds, _ = timed([deck(f"single_{ni}", ni, nj, "quad4"), "--out", out])
            print(f"| {tolerance:g} | one run: {name} | {ni} x {nj} grid | | {seconds:.4f} |")
