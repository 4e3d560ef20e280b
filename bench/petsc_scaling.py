#!/usr/bin/env python3
"""`mpirun -np N gapfe run DECK --solver petsc` on 1e6 and 4e6 equations: time and peak memory per rank.

    python3 bench/petsc_scaling.py [--gapfe build/bench/examples/gapfe] [--sizes 1e6,4e6] [--ranks 1,2]
                                   [--repeats 3] [--work DIR] [--write BENCHMARKS.md]

What a user runs is timed: the whole `gapfe run` command, each rank under GNU time (wall seconds and peak
resident memory, %M), reading the deck, meshing, partitioning, assembling, factorizing or iterating,
solving and writing every file (each rank its own part, docs/cluster.md "Output"). Problems: bench/deckgen.py's Lame tube (a = 100,
b = 200 mm, plane strain, bore pressure 100 MPa as BC-card ring forces), legacy element, `$ fields = wide`:
  1e6   708 x 707 grid    999,696 equations
  4e6  1415 x 1414 grid  4,001,620 equations
With --gathered, every run of several ranks also with `--set output_parts=gathered` (rank 0 gathers every
result and writes the whole mesh's files, as before the ranks wrote their own parts).
Solvers (PETSc's options on the command line):
  direct     the default: -ksp_type preonly -pc_type cholesky -pc_factor_mat_solver_type mumps
  iterative  -ksp_type cg -pc_type gamg (with the axisymmetric near-null space; rtol 1e-10 on the true
             residual)
and, for reference in the same session, the serial CHOLMOD run of the same deck (one process, no MPI).
The runs are interleaved (each round runs every configuration once) and the table gives medians over the
rounds, with rank 0's phases from the command's log (setup includes partitioning and PETSc's analysis).
Accuracy: every run's bore u_r against Lame's (node 1's row of nodes.csv, or of the part's nodes_pK.csv).

--write FILE replaces the text between `<!-- petsc_scaling: begin -->` and `<!-- petsc_scaling: end -->`.
Exit status 0, or 2 when a run fails (its log is named)."""
import argparse
import datetime
import glob
import os
import platform
import re
import shlex
import statistics
import subprocess
import sys
import tempfile

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import deckgen  # noqa: E402

SIZES = {"1e6": (708, 707), "4e6": (1415, 1414)}
SOLVERS = {"direct": [], "iterative": ["-ksp_type", "cg", "-pc_type", "gamg"]}
A, B, P, E, NU = 100.0, 200.0, 100.0, 200000.0, 0.3
MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
           "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}


def lame_bore():
    """Bore u_r of the plane-strain Lame tube (docs/theory.md V1)."""
    ca = P * A * A / (B * B - A * A)
    cb = ca * B * B
    sr, st, sz = ca - cb / (A * A), ca + cb / (A * A), 2 * NU * ca
    return A / E * (st - NU * (sr + sz))


def run(cmd, log, times, env):
    """Runs cmd (a list); returns (per-rank [(wall s, peak MB)], log text). GNU time appends one line per
    rank, 'TIME wall maxrss_kb', to the file `times` (appends of a line are atomic)."""
    if os.path.exists(times):
        os.remove(times)
    with open(log, "w") as out:
        code = subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT, env=env).returncode
    text = open(log).read()
    if code != 0:
        print(f"petsc_scaling: run failed ({code}): {' '.join(cmd)}; see {log}", file=sys.stderr)
        sys.exit(2)
    ranks = [(float(w), int(k) / 1024) for w, k in re.findall(r"^TIME (\S+) (\d+)$", open(times).read(), re.M)]
    return ranks, text


def phases(text):
    m = re.search(r"time \[s\]: read (\S+), mesh (\S+), setup (\S+), assemble (\S+), factorize (\S+), "
                  r"solve (\S+), (?:(?:estimate|recovery) \S+, )?write (\S+)", text)
    return dict(zip(["read", "mesh", "setup", "assemble", "factorize", "solve", "write"],
                    map(float, m.groups()))) if m else {}


def bore_displacement(out_dir):
    """Node 1's u_r, from nodes.csv or from the part's nodes_pK.csv that holds it (a run of several ranks)."""
    for path in [os.path.join(out_dir, "nodes.csv")] + sorted(glob.glob(os.path.join(out_dir, "nodes_p*.csv"))):
        if not os.path.exists(path):
            continue
        with open(path) as f:
            header = f.readline().strip().split(",")
            node, u_r = header.index("node"), header.index("u_r")
            for line in f:
                row = line.split(",")
                if row[node] == "1":
                    return float(row[u_r])
    raise SystemExit(f"petsc_scaling: no table in {out_dir} holds node 1")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--gapfe", default="build/bench/examples/gapfe")
    ap.add_argument("--sizes", default="1e6,4e6")
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--solvers", default="direct,iterative")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--serial", action="store_true", help="also the serial CHOLMOD run, for reference")
    ap.add_argument("--gathered", action="store_true",
                    help="also every run of several ranks with output_parts = gathered (rank 0 gathers and "
                         "writes the whole mesh's files), against the default pieces")
    ap.add_argument("--work", default=None)
    ap.add_argument("--write", default=None)
    args = ap.parse_args()
    work = args.work or tempfile.mkdtemp(prefix="petsc_scaling_")
    os.makedirs(work, exist_ok=True)
    env = dict(os.environ, **MPI_ENV)
    gapfe = os.path.abspath(args.gapfe)
    configs = []  # (size, label, ranks, command prefix, command suffix)
    for size in args.sizes.split(","):
        ni, nj = SIZES[size]
        deck = os.path.join(work, f"tube_{size}.deck")
        if not os.path.exists(deck):
            with open(deck, "w") as f:
                f.write(deckgen.tube_deck(ni, nj, nodal=True, wide=True))
        if args.serial:
            configs.append((size, "cholmod", 1, [], ["--solver", "cholmod"], deck))
        for solver in args.solvers.split(","):
            for n in map(int, args.ranks.split(",")):
                prefix = ["mpirun", "--oversubscribe", "-np", str(n)]
                configs.append((size, solver, n, prefix, ["--solver", "petsc"] + SOLVERS[solver], deck))
                if args.gathered and n > 1:
                    configs.append((size, solver + ", gathered", n, prefix,
                                    ["--solver", "petsc", "--set", "output_parts=gathered"] + SOLVERS[solver], deck))
    results = {}
    for rnd in range(args.repeats):
        for size, solver, n, prefix, suffix, deck in configs:
            label = solver.replace(", ", "_")
            out = os.path.join(work, f"out_{size}_{label}_{n}")
            log = os.path.join(work, f"log_{size}_{label}_{n}_{rnd}.txt")
            times = log + ".time"
            cmd = prefix + ["/usr/bin/time", "-a", "-o", times, "-f", "TIME %e %M", gapfe, "run", deck, "--out",
                            out, "--plot", "none"] + suffix
            ranks, text = run(cmd, log, times, env)
            error = bore_displacement(out) / lame_bore() - 1
            results.setdefault((size, solver, n), []).append((ranks, phases(text), error))
            print(f"{size} {solver} np={n}: wall {[r[0] for r in ranks]} s, peak {[round(r[1]) for r in ranks]} MB, "
                  f"phases {phases(text)}, bore u_r error {error:.2e}", flush=True)
    lines = ["| equations | solver | ranks | wall s (median) | peak MB per rank (smallest first) | rank 0: setup / assemble / "
             "factorize / solve / write s | bore u_r vs Lame |", "|---|---|---|---|---|---|---|"]
    for (size, solver, n), runs in results.items():
        wall = statistics.median(max(r[0] for r in ranks) for ranks, _, _ in runs)
        # Ranks in the order of their peaks (GNU time's lines come in the order the ranks end).
        peak = [statistics.median(sorted(r[1] for r in ranks)[k] for ranks, _, _ in runs) for k in range(n)]
        ph = {k: statistics.median(p[k] for _, p, _ in runs) for k in runs[0][1]}
        lines.append(f"| {size} | {solver} | {n} | {wall:.1f} | {' / '.join(f'{m:.0f}' for m in peak)} | "
                     f"{ph['setup']:.1f} / {ph['assemble']:.2f} / {ph['factorize']:.1f} / {ph['solve']:.2f} / "
                     f"{ph['write']:.1f} | {runs[0][2]:+.1e} |")
    cpu = platform.processor() or "x86_64"
    try:
        cpu = [l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")][0]
    except (OSError, IndexError):
        pass
    text = "\n".join(lines) + (
        f"\n\nCommand: `python3 bench/petsc_scaling.py {' '.join(shlex.quote(a) for a in sys.argv[1:])}`; "
        f"{args.repeats} rounds; {cpu}, {os.cpu_count()} cores; "
        f"{datetime.date.today().isoformat()}.\n")
    print(text)
    if args.write:
        doc = open(args.write).read()
        begin, end = "<!-- petsc_scaling: begin -->", "<!-- petsc_scaling: end -->"
        i, j = doc.index(begin) + len(begin), doc.index(end)
        open(args.write, "w").write(doc[:i] + "\n" + text + doc[j:])


if __name__ == "__main__":
    main()
