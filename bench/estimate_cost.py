#!/usr/bin/env python3
"""What the error estimate every run makes (post/error_estimate.hpp) costs, on bench/run_vs_ccx.py's cases:

    python3 bench/estimate_cost.py [--cases tube-1e5,plastic-1e4,...] [--runs 5] [--gapfe build/bench/examples/gapfe]

Each case's deck (run_vs_ccx.write_inputs, its first gapfe variant's options) runs --runs times as a whole
process, one thread, with the estimate (the default) and without it (`--set error_estimate=none`), the two
interleaved. Two measures of the cost, as a share of the run with the estimate:
  phase  the log's `recovery` phase with the estimate less the phase without it: the estimate's pass recovers
         the centroid stresses the files carry too, which a run without it recovers alone, timed as the
         same phase. Two in-process timers of the same code, steady to about a percent of the run;
  whole  the difference of the two whole processes' medians, wall and CPU time (user + system): what a user
         waits, but on a shared machine good to 5-15% of the run at best (BENCHMARKS.md).
"""
import os
import re
import statistics
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import run_vs_ccx  # noqa: E402  (the cases and their decks)


def timed_run(gapfe, deck, out, work, options):
    """(wall seconds, CPU seconds: user + system, the log's recovery phase) of one whole run."""
    log = out + ".log"
    with open(log, "wb") as sink:
        t0 = time.perf_counter()
        proc = subprocess.Popen([gapfe, "run", deck, "--out", out, "--overwrite"] + options, cwd=work,
                                env=run_vs_ccx.child_env(), stdin=subprocess.DEVNULL, stdout=sink,
                                stderr=subprocess.STDOUT)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - t0
    if os.waitstatus_to_exitcode(status) != 0:
        run_vs_ccx.die(f"{deck}: exit {os.waitstatus_to_exitcode(status)} (log {log})")
    phase = re.search(r"time \[s\]:.* recovery ([0-9.eE+-]+),", open(log).read())
    if not phase:
        run_vs_ccx.die(f"{deck}: no recovery phase in {log}")
    return wall, usage.ru_utime + usage.ru_stime, float(phase.group(1))


def main():
    cases = "tube-1e5,plastic-1e4,plastic-1e5,tube-1e6,contact"
    args = run_vs_ccx.comparison_options(__doc__, cases, 5).parse_args()
    gapfe, work = run_vs_ccx.gapfe_and_work(args, "estimate_cost_")
    print("| case | equations | increments | run [s] | recovery [s] | without [s] | cost, phase | "
          "run without [s] | cost, whole wall | cost, whole CPU |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name, case, deck, options in run_vs_ccx.case_decks(args.cases, work):
        runs = {"energy": [], "none": []}
        for k in range(args.runs):
            for mode in ("energy", "none"):
                runs[mode].append(timed_run(gapfe, deck, os.path.join(work, f"{name}_{mode}"), work,
                                            options + ["--set", f"error_estimate={mode}"]))
        med = {m: [statistics.median(r[i] for r in runs[m]) for i in range(3)] for m in runs}
        (wall, cpu, phase), (bare, bare_cpu, bare_phase) = med["energy"], med["none"]
        print(f"| {name} | {case.equations:,} | {case.steps} | {wall:.3g} | {phase:.3g} | {bare_phase:.3g} | "
              f"{100 * (phase - bare_phase) / wall:.1f}% | {bare:.3g} | {100 * (wall - bare) / wall:.1f}% | "
              f"{100 * (cpu - bare_cpu) / cpu:.1f}% |", flush=True)


if __name__ == "__main__":
    main()
