#!/usr/bin/env python3
"""Two builds of `gapfe run` on bench/run_vs_ccx.py's decks, alternating: for refactors that must not cost
time. Each round runs every case's variants with build A, then with build B (whole processes, one thread,
as run_vs_ccx.py runs them); the table gives each build's median wall time and the ratio B / A of the
medians.

    python3 bench/build_ab.py --a OLD/gapfe --b NEW/gapfe [--cases tube-1e5,plastic-1e4,contact]
                              [--rounds 5] [--work DIR]"""
import argparse
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import run_vs_ccx  # noqa: E402  (its cases, decks and measured runs)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--a", required=True)
    ap.add_argument("--b", required=True)
    ap.add_argument("--cases", default="tube-1e5,plastic-1e4,contact")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--work", default="build_ab-out")
    o = ap.parse_args()
    rows = {}
    for name in o.cases.split(","):
        case = run_vs_ccx.CASES[name]
        work = os.path.join(o.work, name)
        os.makedirs(work, exist_ok=True)
        deck, _ = run_vs_ccx.write_inputs(case, work)
        for _ in range(o.rounds):
            for label, gapfe in (("a", o.a), ("b", o.b)):
                for variant, options in case.variants:
                    out = os.path.join(work, f"{label}_{variant}")
                    argv = [os.path.abspath(gapfe), "run", os.path.abspath(deck), "--out", out, "--quiet",
                            "--overwrite", *options]
                    code, wall, _ = run_vs_ccx.run_measured(argv, work, out + ".log")
                    if code != 0:
                        sys.exit(f"build_ab: {label} failed on {name} {variant} (see {out}.log)")
                    rows.setdefault((name, variant), {"a": [], "b": []})[label].append(wall)
    print("| case | variant | A median [s] | B median [s] | B / A |")
    print("|---|---|---|---|---|")
    for (name, variant), t in rows.items():
        a, b = statistics.median(t["a"]), statistics.median(t["b"])
        print(f"| {name} | {variant} | {a:.3f} | {b:.3f} | {b / a:.3f} |")


if __name__ == "__main__":
    main()
