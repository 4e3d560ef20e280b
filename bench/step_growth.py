#!/usr/bin/python3
"""Work linear in the step count: `gapfe run` on a one-cell deck of N load steps, each with its own load
block (INCF = 1: a pressure card per step) and every increment written (CSV tables, a VTU file per step and
result.pvd), for N = 1e3, 1e4 and 99,999 (NLINC is five columns wide). Prints the wall, user and system time, the bytes written, and the user time
and bytes per step; a run whose work grows linearly keeps the per-step figures flat. The system time is the
file system's (creating, renaming and, before each repeat, removing N files in one folder) and swings by 3x
between runs on a shared machine; the user time is the command's own work.

    /usr/bin/python3 bench/step_growth.py build/release/examples/gapfe [WORKDIR] [--steps 1000 10000 99999]

Each N is run `--repeat` times (default 3) and the median time quoted. The deck: a square 100 <= r <= 101,
0 <= z <= 1 (one bilinear cell), u_z = 0 at z = 0, and the pressure on the bore stepping by 1e-3 each step.
"""
import argparse
import pathlib
import resource
import shutil
import statistics
import subprocess
import sys
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import deckgen as g  # noqa: E402


def one_cell_deck(steps):
    lines = ["$ format = elastic", f"ONE CELL, {steps} LOAD STEPS EACH WITH ITS OWN PRESSURE CARD",
             g.control(numpc=1, nlinc=steps, incf=1), g.mesh_control(2, 2, 4, 1, 1),
             g.segment([(1, 1, 100.0, 0.0), (2, 1, 101.0, 0.0)], 1),
             g.segment([(2, 1, 101.0, 0.0), (2, 2, 101.0, 1.0)], 1),
             g.segment([(2, 2, 101.0, 1.0), (1, 2, 100.0, 1.0)], 1),
             g.segment([(1, 2, 100.0, 1.0), (1, 1, 100.0, 0.0)], 1),
             g.bc(1, 2, 1, 1, 2), g.block(1, 1, 2, 1, 2)]
    lines += g.material(1, [g.isotropic(200000.0, 0.3)], elastic_format=True)
    lines += [g.edge(3, 1, 1e-3) for _ in range(steps)]  # node (1, 2) to (1, 1): the bore, cell on the left
    return "\n".join(lines) + "\n"


def folder_bytes(path):
    return sum(f.stat().st_size for f in path.iterdir() if f.is_file())


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("gapfe")
    ap.add_argument("work", nargs="?", default="/tmp/gapfe_step_growth")
    ap.add_argument("--steps", type=int, nargs="+", default=[1000, 10000, 99999])
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    work = pathlib.Path(a.work)
    work.mkdir(parents=True, exist_ok=True)
    print(f"{'steps':>8} {'wall [s]':>9} {'user [s]':>9} {'sys [s]':>8} {'user us/step':>13} {'MB written':>11} "
          f"{'bytes/step':>11}")
    for steps in a.steps:
        deck = work / f"cell_{steps}.deck"
        deck.write_text(one_cell_deck(steps))
        out = work / f"cell_{steps}"
        wall, user, system = [], [], []
        for _ in range(a.repeat):
            shutil.rmtree(out, ignore_errors=True)
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            start = time.perf_counter()
            subprocess.run([a.gapfe, "run", str(deck), "--out", str(out), "--quiet", "--plot", "none"], check=True)
            wall.append(time.perf_counter() - start)
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            user.append(after.ru_utime - before.ru_utime)
            system.append(after.ru_stime - before.ru_stime)
        t, u, k, size = (statistics.median(x) for x in (wall, user, system, [folder_bytes(out)]))
        print(f"{steps:>8} {t:>9.2f} {u:>9.2f} {k:>8.2f} {1e6 * u / steps:>13.1f} {size / 1e6:>11.1f} "
              f"{size / steps:>11.0f}", flush=True)
        shutil.rmtree(out, ignore_errors=True)


if __name__ == "__main__":
    main()
