#!/usr/bin/env python3
"""What the error estimate every run makes (post/error_estimate.hpp) costs, on bench/run_vs_ccx.py's cases:

    python3 bench/estimate_cost.py [--cases tube-1e5,plastic-1e4,...] [--runs 3] [--gapfe build/bench/examples/gapfe]

Each case's deck (run_vs_ccx.write_inputs, its first gapfe variant's options) runs --runs times as a whole
process, one thread; the table gives the medians of the whole wall time and of the log's `estimate` phase (the
`time [s]` line: every accepted increment's estimate), and the estimate's share of the run.
"""
import argparse
import os
import re
import statistics
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import run_vs_ccx  # noqa: E402  (the cases and their decks)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", default="tube-1e5,plastic-1e4,plastic-1e5,tube-1e6,contact")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--gapfe", default="build/bench/examples/gapfe")
    ap.add_argument("--work", default=None)
    args = ap.parse_args()
    gapfe = os.path.abspath(args.gapfe)
    work = args.work or tempfile.mkdtemp(prefix="estimate_cost_")
    os.makedirs(work, exist_ok=True)
    print("| case | equations | increments | run [s] | estimate [s] | share |")
    print("|---|---|---|---|---|---|")
    for name in args.cases.split(","):
        case = run_vs_ccx.CASES[name]
        deck, _ = run_vs_ccx.write_inputs(case, work)
        _, options = case.variants[0]
        walls, estimates = [], []
        for k in range(args.runs):
            out = os.path.join(work, f"{name}_{k}")
            log = out + ".log"
            code, wall, _ = run_vs_ccx.run_measured([gapfe, "run", deck, "--out", out, "--overwrite"] + options,
                                                   work, log)
            if code != 0:
                run_vs_ccx.die(f"{name}: exit {code} (log {log})")
            text = open(log).read()
            estimate = re.search(r"time \[s\]:.* estimate ([0-9.eE+-]+),", text)
            if not estimate:
                run_vs_ccx.die(f"{name}: no estimate phase in {log}")
            walls.append(wall), estimates.append(float(estimate.group(1)))
        wall, estimate = statistics.median(walls), statistics.median(estimates)
        print(f"| {name} | {case.equations:,} | {case.steps} | {wall:.3g} | {estimate:.3g} | "
              f"{100 * estimate / wall:.1f}% |", flush=True)


if __name__ == "__main__":
    main()
