#!/usr/bin/env python3
"""How far `gapfe run` is from this machine's limits: the factorization's flop rate against the BLAS's
dgemm, and the files' write rate against a plain write of as many bytes.

    /usr/bin/python3 bench/limits.py [--cases tube-1e5,tube-1e6] [--runs 3] [--gapfe build/bench/examples/gapfe]

For each case (bench/run_vs_ccx.py's deck of it, every default output, one thread) the run's log gives the
factorization's flop count (CHOLMOD's, for the exact factor; the relaxed supernodes' explicit zeros are
not counted) with its time, and the bytes of the files it wrote with their time; the best of --runs runs.
The peaks beside them, measured here in this process:
  dgemm  numpy's matrix product on one thread (OPENBLAS_NUM_THREADS=1), n = 1000, 2000, 4000, best of
         three each: the BLAS-3 kernel a supernodal factorization's time is spent in. numpy and gapfe load
         the same libblas.so.3 (Debian's alternatives); both paths are printed so that a reader can check.
  disk   as many bytes as the run's files, file for file in 8 MiB writes, into the folder that holds the
         run's (the same filesystem), without fsync (what the run does: the page cache) and with an fsync
         per file.
"""
import os
import re
import subprocess
import sys
import time

os.environ["OPENBLAS_NUM_THREADS"] = os.environ["OMP_NUM_THREADS"] = "1"  # before numpy loads OpenBLAS

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import run_vs_ccx  # noqa: E402  (the cases and their decks)


def loaded_blas(pid):
    """The BLAS library mapped into process `pid` (its path: libblas.so.3 or libopenblas*), or None."""
    with open(f"/proc/{pid}/maps") as maps:
        for line in maps:
            name = os.path.basename(line.split()[-1])
            if name.startswith("libblas.so") or name.startswith("libopenblas"):
                return line.split()[-1]
    return None


def dgemm_peak():
    """(best GFLOP/s of numpy's dgemm on one thread over n = 1000, 2000, 4000, the BLAS's path)."""
    import numpy as np
    best = 0.0
    for n in (1000, 2000, 4000):
        a, b = np.random.rand(n, n), np.random.rand(n, n)
        a @ b  # warm: OpenBLAS's buffers, the pages
        for _ in range(3):
            t0 = time.perf_counter()
            a @ b
            best = max(best, 2.0 * n ** 3 / (time.perf_counter() - t0) / 1e9)
    return best, loaded_blas(os.getpid())


def disk_rate(folder, sizes):
    """(MB/s without fsync, MB/s with one fsync per file) writing files of `sizes` bytes into `folder`."""
    chunk = os.urandom(8 << 20)
    rates = []
    for sync in (False, True):
        best = 0.0
        for _ in range(3):
            t0 = time.perf_counter()
            for k, size in enumerate(sizes):
                path = os.path.join(folder, f"limits_{k}.bin")
                with open(path, "wb") as f:
                    left = size
                    while left > 0:
                        left -= f.write(chunk[:min(left, len(chunk))])
                    if sync:
                        f.flush()
                        os.fsync(f.fileno())
            best = max(best, sum(sizes) / (time.perf_counter() - t0) / 1e6)
            for k in range(len(sizes)):
                os.remove(os.path.join(folder, f"limits_{k}.bin"))
        rates.append(best)
    return rates


def run_once(gapfe, deck, out, work, options):
    """(factorization flops, its seconds, files' bytes, their seconds, the BLAS gapfe loaded) of one run."""
    proc = subprocess.Popen([gapfe, "run", deck, "--out", out, "--overwrite"] + options, cwd=work,
                            env=run_vs_ccx.child_env(), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            text=True)
    blas = None
    while blas is None and proc.poll() is None:  # the BLAS is mapped once the program has started
        try:
            blas = loaded_blas(proc.pid)
        except OSError:
            break
        time.sleep(0.01)
    log, _ = proc.communicate()
    if proc.returncode != 0:
        run_vs_ccx.die(f"{deck}: exit {proc.returncode}\n{log}")
    fact = re.search(r"^factorization: ([0-9.eE+]+) flops in ([0-9.eE+-]+) s", log, re.M)
    files = re.search(r"^files: ([0-9]+) bytes in ([0-9.eE+-]+) s", log, re.M)
    if not fact or not files:
        run_vs_ccx.die(f"{deck}: no factorization or files line in the log\n{log}")
    return float(fact.group(1)), float(fact.group(2)), int(files.group(1)), float(files.group(2)), blas


def main():
    args = run_vs_ccx.comparison_options(__doc__, "tube-1e5,tube-1e6", 3).parse_args()
    gapfe, work = run_vs_ccx.gapfe_and_work(args, "limits_")
    peak, numpy_blas = dgemm_peak()
    print(f"dgemm, one thread: {peak:.1f} GFLOP/s (numpy's BLAS: {numpy_blas})")
    print("| case | equations | flops | factorize [s] | GFLOP/s | of dgemm | files [MB] | write [s] | MB/s "
          "| plain write MB/s (no fsync, fsync) | of plain |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name, case, deck, options in run_vs_ccx.case_decks(args.cases, work):
        out = os.path.join(work, name)
        runs = [run_once(gapfe, deck, out, work, options) for _ in range(args.runs)]
        flops, t_fact = min(((r[0], r[1]) for r in runs), key=lambda r: r[1])
        size, t_write = min(((r[2], r[3]) for r in runs), key=lambda r: r[1])
        sizes = [os.path.getsize(os.path.join(out, f)) for f in os.listdir(out)]
        plain, synced = disk_rate(work, sizes)
        rate, write_rate = flops / t_fact / 1e9, size / t_write / 1e6
        print(f"| {name} | {case.equations:,} | {flops:.3g} | {t_fact:.3g} | {rate:.1f} | {100 * rate / peak:.0f}% "
              f"| {size / 1e6:.0f} | {t_write:.3g} | {write_rate:.0f} | {plain:.0f}, {synced:.0f} "
              f"| {100 * write_rate / plain:.0f}% |", flush=True)
        if runs[0][4] and numpy_blas and os.path.realpath(runs[0][4]) != os.path.realpath(numpy_blas):
            print(f"  note: gapfe loaded {runs[0][4]}, numpy {numpy_blas}: not the same BLAS")


if __name__ == "__main__":
    main()
