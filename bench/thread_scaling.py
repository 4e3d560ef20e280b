#!/usr/bin/env python3
"""`gapfe run --threads N` against --threads 1: the whole process and its phases.

    /usr/bin/python3 bench/thread_scaling.py [--cases tube-1e6,plastic-1e5] [--threads 1,2] [--runs 3]
                                              [--gapfe build/bench/examples/gapfe]

For each case (bench/run_vs_ccx.py's deck of it, every default output) the thread counts run in turn,
--runs rounds of them, so that a slow minute of a shared machine hits each alike. Printed per case and
thread count: the median wall time of the whole process (GNU time's peak memory beside it), its speed-up
over the first count, and the median of each phase the log's `time [s]:` line gives. What runs on N
threads (docs/process.md "Threads"): the cells' passes (assembly, recovery, the error estimate), the
encoding of the tables and VTU files, the scatter offsets and the first touch of the factor's pages on
gapfe's pool; the factorization's dense kernels on OpenBLAS's.
"""
import os
import re
import statistics
import sys

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import run_vs_ccx  # noqa: E402  (the cases and their decks)

PHASES = ("setup", "assemble", "factorize", "solve", "recovery", "write")


def run_once(gapfe, deck, out, work, options, threads):
    """(wall seconds, peak MiB, {phase: seconds}) of one whole `gapfe run`."""
    log_path = os.path.join(work, f"run_{threads}.log")
    argv = [gapfe, "run", deck, "--out", out, "--overwrite", "--threads", str(threads)] + options
    code, wall, rss = run_vs_ccx.run_measured(argv, work, log_path)
    with open(log_path) as f:
        log = f.read()
    if code != 0:
        run_vs_ccx.die(f"{deck} --threads {threads}: exit {code}\n{log}")
    line = re.search(r"^time \[s\]: (.*)$", log, re.M)
    if not line:
        run_vs_ccx.die(f"{deck}: no `time [s]:` line in the log\n{log}")
    phases = {k: float(v) for k, v in re.findall(r"(\w+) ([0-9.eE+-]+)", line.group(1))}
    return wall, rss, phases


def main():
    ap = run_vs_ccx.comparison_options(__doc__, "tube-1e6,plastic-1e5", 3)
    ap.add_argument("--threads", default="1,2", help="the thread counts, the first the reference")
    args = ap.parse_args()
    counts = [int(t) for t in args.threads.split(",")]
    gapfe, work = run_vs_ccx.gapfe_and_work(args, "threads_")
    print(f"| case | threads | wall [s] | speed-up | peak MiB | " + " | ".join(PHASES) + " |")
    print("|---|---|---|---|---|" + "---|" * len(PHASES))
    for name, case, deck, options in run_vs_ccx.case_decks(args.cases, work):
        runs = {t: [] for t in counts}
        for _ in range(args.runs):
            for t in counts:
                runs[t].append(run_once(gapfe, deck, os.path.join(work, f"{name}_{t}"), work, options, t))
        reference = statistics.median(r[0] for r in runs[counts[0]])
        for t in counts:
            wall = statistics.median(r[0] for r in runs[t])
            rss = max(r[1] for r in runs[t])
            phases = [statistics.median(r[2].get(p, 0.0) for r in runs[t]) for p in PHASES]
            print(f"| {name} | {t} | {wall:.2f} | {reference / wall:.2f}x | {rss:,.0f} | "
                  + " | ".join(f"{p:.3g}" for p in phases) + " |", flush=True)


if __name__ == "__main__":
    main()
