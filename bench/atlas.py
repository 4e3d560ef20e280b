#!/usr/bin/env python3
"""The speed/accuracy atlas: every approximation knob's error against its cost, one command.

    OPENBLAS_NUM_THREADS=1 /usr/bin/python3 bench/atlas.py --gapfe build/bench/examples/gapfe \\
        --bench-dir build/bench/bench [--repeat 3] [--only lame,two-tubes]

Runs the reference problems across the knobs that apply to each, one process per setting, and for every
run records the error against the closed form, the median wall time, the linear solves and the peak
memory (the process's max RSS from wait4). Writes bench/atlas/atlas.csv, one PNG per problem
(bench/atlas/<problem>.png: error against time, one line per knob family through its swept setting, the
Pareto front drawn) and bench/ATLAS.md (per problem, the cheapest setting that reaches each error target).

Errors are relative to the largest exact value: for the element study the larger of the nodal displacement
error and the centroid stress error (what elements.csv holds).
Problems and their paths (the library call a user makes, or the `gapfe run` command on a deck):
  lame, lame-0.4999, spin, shaft   library (bench_atlas): element x refinement; docs/theory.md V1, rotating
                                   solid cylinder, V4 shaft under angular acceleration (SAGA)
  tube-solver                      command: thick tube decks 1e3-1e5 equations, element x solver, Lame
  two-tubes                        command: contact policy x load steps x gap penalty, and refinement;
                                   closure load and final contact pressure against docs/theory.md V5
  press-fit                        command: friction model x contact policy x load steps, the push-out
                                   force against mu p 2 pi b L (nu = 0)
  plastic-limit                    library (bench_plastic): integration x load steps, limit pressure
  rate-bar, saac3x                 library (bench_rate): integration x dt, stress path against the 1-D ODE
"""
import argparse
import csv
import datetime
import json
import math
import os
import pathlib
import platform
import re
import statistics
import subprocess
import sys
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.dont_write_bytecode = True
import contact_tradeoff  # noqa: E402
import deckgen  # noqa: E402

TARGETS = (1e-2, 1e-3, 1e-4)
FIELDS = ["problem", "path", "family", "setting", "swept", "error", "wall_s", "solves", "peak_mb", "note"]


def measured(cmd, repeat, env=None):
    """Run `cmd` `repeat` times: (median wall seconds, largest max RSS in MB, last stdout, last stderr, code).
    The peak comes from GNU time (/usr/bin/time -f %M): a child forked from Python itself would count the
    interpreter's pages touched before exec (18 MB) in its own maximum."""
    walls, peak, out, err, code = [], 0.0, "", "", 0
    for _ in range(repeat):
        with tempfile.TemporaryFile("w+") as o, tempfile.TemporaryFile("w+") as e, \
                tempfile.NamedTemporaryFile("r") as rss:
            t0 = time.perf_counter()
            code = subprocess.run(["/usr/bin/time", "-f", "%M", "-o", rss.name, *cmd], stdout=o, stderr=e,
                                  env=env).returncode
            walls.append(time.perf_counter() - t0)
            text = rss.read().strip().splitlines()
            if text and text[-1].isdigit():
                peak = max(peak, int(text[-1]) / 1024.0)
            o.seek(0), e.seek(0)
            out, err = o.read(), e.read()
            if code != 0:
                break
    return statistics.median(walls), peak, out, err, code


def linear_solves(log):
    m = re.search(r"(\d+) linear solves", log)
    return int(m.group(1)) if m else 1


# ------------------------------------------------------------------------------------------ library paths

def gbench(binary, name, repeat):
    """One Google Benchmark in its own process: (median row, peak MB)."""
    pattern = name.replace(".", "[.]")  # the benchmark library takes POSIX extended regexes: no "\\-"
    cmd = [binary, f"--benchmark_filter=^{pattern}$", "--benchmark_format=json",
           f"--benchmark_repetitions={repeat}", "--benchmark_report_aggregates_only=true",
           "--benchmark_min_time=0.05"]
    _, peak, out, err, code = measured(cmd, 1)
    if code != 0:
        raise RuntimeError(f"{binary} {name}: {err.strip()[-300:]}")
    rows = [b for b in json.loads(out)["benchmarks"] if b.get("aggregate_name", "median") == "median"]
    if not rows:
        raise RuntimeError(f"{binary}: no benchmark named {name}")
    row = rows[0]
    scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}[row.get("time_unit", "ns")]
    return row, row["real_time"] * scale, peak


def elements(args, rows):
    binary = str(pathlib.Path(args.bench_dir) / "bench_atlas")
    for problem, sizes in (("lame", (2, 4, 8, 16, 32, 64, 128)), ("lame-0.4999", (2, 4, 8, 16, 32, 64, 128)),
                           ("spin", (2, 4, 8, 16, 32, 64, 128)), ("shaft", (2, 4, 8, 16, 32))):
        if not wanted(args, problem):
            continue
        for element in ("legacy", "quad4", "quad4bbar", "quad8", "tri3"):
            for n in sizes:
                row, wall, peak = gbench(binary, f"{problem}/{element}/{n}", args.repeat)
                add(rows, problem, "library", element, f"{element}, {n} cells across ({row['dofs']:.0f} DOFs)", n,
                    row["error"], wall, 1, peak,
                    f"nodal u error {row['u_error']:.2e}, centroid stress error {row['stress_error']:.2e}")


def plastic(args, rows):
    if not wanted(args, "plastic-limit"):
        return
    binary = str(pathlib.Path(args.bench_dir) / "bench_plastic")
    for integration, label in (("Tangent", "tangent"), ("ReturnMapping", "return-mapping")):
        for steps in (5, 10, 20, 50, 100, 200):
            row, wall, peak = gbench(binary, f"BM_Limit<gapfe::{integration}>/{steps}", args.repeat)
            add(rows, "plastic-limit", "library", label, f"{label}, {steps} steps", steps, row["limit_error"], wall,
                row.get("solves", steps), peak)


def rate(args, rows):
    binary = str(pathlib.Path(args.bench_dir) / "bench_rate")
    for case, problem in (("BM_ConstantRate", "rate-bar"), ("BM_Saac3x", "saac3x")):
        if not wanted(args, problem):
            continue
        for integration, label in (("Tangent", "tangent"), ("ReturnMapping", "return-mapping")):
            for k in range(6):
                row, wall, peak = gbench(binary, f"{case}<gapfe::{integration}>/{k}", args.repeat)
                add(rows, problem, "library", label,
                    f"{label}, dt = {row['lambda_dt']:g} relaxation times ({row['steps']:.0f} steps)",
                    row["lambda_dt"], row["stress_error"], wall, row["steps"], peak)


# ------------------------------------------------------------------------------------------ command paths

def short(message):
    """The command's error without its path prefix and the residual lists: one readable line."""
    message = re.sub(r"^gapfe: cannot solve [^:]*: ", "", message)
    message = re.sub(r" \((relative [^()]*)\)", " (...)", message)
    return message[:240]


def gapfe_run(args, work, name, text, extra=()):
    work.mkdir(parents=True, exist_ok=True)
    deck = work / f"{name}.deck"
    deck.write_text(text)
    out = work / name
    wall, peak, log, err, code = measured([args.gapfe, "run", str(deck), "--out", str(out), *extra], args.repeat)
    if code != 0:
        return None, short(err.strip().splitlines()[-1]) if err.strip() else f"exit {code}"
    return (out, wall, peak, linear_solves(log)), ""


def last_rows(path):
    rows = list(csv.DictReader(open(path)))
    last = max(float(r["inc"]) for r in rows)
    return [r for r in rows if float(r["inc"]) == last]


def tube_solver(args, rows, work):
    if not wanted(args, "tube-solver"):
        return
    a, b, p, E, nu = 100.0, 200.0, 100.0, 200000.0, 0.3
    A = p * a * a / (b * b - a * a)
    B = A * b * b
    exact = lambda r: r / E * ((A + B / r**2) - nu * ((A - B / r**2) + 2 * nu * A))  # noqa: E731
    for ni, nj in ((23, 12), (71, 36), (224, 112)):
        for element in ("legacy", "quad4bbar"):
            for solver in ("eigen", "cholmod"):
                name = f"tube_{ni}_{element}_{solver}"
                res, why = gapfe_run(args, work, name, deckgen.tube_deck(ni, nj),
                                     ["--element", element, "--solver", solver, "--output", "last", "--quiet"])
                dofs = 2 * ni * nj
                if res is None:
                    add(rows, "tube-solver", "command", f"{element}, {solver}", f"{element}, {solver}, {dofs} DOFs",
                        dofs, math.nan, math.nan, 0, math.nan, why)
                    continue
                out, wall, peak, solves = res
                err = max(abs(float(r["u_r"]) - exact(float(r["r"]))) for r in last_rows(out / "nodes.csv")) / exact(a)
                add(rows, "tube-solver", "command", f"{element}, {solver}", f"{element}, {solver}, {dofs} DOFs", dofs,
                    err, wall, solves, peak)


def two_tubes(args, rows, work):
    if not wanted(args, "two-tubes"):
        return
    a, b, c, gap, E, nu, p, h = 1.0, 1.5, 2.0, 5e-4, 200000.0, 0.3, 100.0, 1.0
    # Exact for the gapped geometry (docs/theory.md V5 puts both tubes' faces at b, which is off by gap / b =
    # 3e-4 here): plane-strain Lame u(r) = (1 + nu) / E ((1 - 2 nu) A r + B / r), A = (p_i r1^2 - p_o r2^2) /
    # (r2^2 - r1^2), B = (p_i - p_o) r1^2 r2^2 / (r2^2 - r1^2). Closure at u_inner(b) = gap; after it, the
    # ring force q b per radian passes the gap elements (q_o (b + gap) = q b) and u_inner(b) - u_outer(b +
    # gap) = gap, linear in q.
    def u(r, r1, r2, p_in, p_out):
        A = (p_in * r1 * r1 - p_out * r2 * r2) / (r2 * r2 - r1 * r1)
        B = (p_in - p_out) * r1 * r1 * r2 * r2 / (r2 * r2 - r1 * r1)
        return (1 + nu) / E * ((1 - 2 * nu) * A * r + B / r)

    p_close = gap / u(b, a, b, 1.0, 0.0)
    gap_change = lambda q: u(b, a, b, p, q) - u(b + gap, b + gap, c, q * b / (b + gap), 0.0) - gap  # noqa: E731
    q_exact = -gap_change(0.0) / (gap_change(1.0) - gap_change(0.0))  # gap_change is linear in q

    def one(family, setting, swept, n, steps, policy, penalty=None):
        ext = (f"gap_penalty = {penalty:g}",) if penalty else ()
        text = deckgen.two_tubes_deck(n=n, nz=2, h=h, steps=steps, contact=policy, extension=ext)
        res, why = gapfe_run(args, work, f"tt_{policy}_{n}_{steps}_{penalty}", text)
        if res is None:
            add(rows, "two-tubes", "command", family, setting, swept, math.nan, math.nan, 0, math.nan, why)
            return
        out, wall, peak, solves = res
        closure, q = contact_tradeoff.closure_and_pressure(out, steps)  # same b = 1.5, h = 1 (and p = 100)
        errs = [abs(q - q_exact) / q_exact]
        errs.append(abs(closure - p_close) / p_close if closure is not None else math.inf)
        add(rows, "two-tubes", "command", family, setting, swept, max(errs), wall, solves, peak,
            f"closure error {errs[1]:.2e}, contact pressure error {errs[0]:.2e}")

    for policy in ("saac", "active-set", "augmented-lagrangian"):
        for steps in (5, 10, 20, 50):
            one(policy, f"{policy}, {steps} steps, 40 cells", steps, 40, steps, policy)
    for penalty in (1e2, 1e6, 1e8):
        for steps in (5, 10, 20):
            one(f"active-set, gap_penalty {penalty:g}", f"active-set, gap_penalty {penalty:g}, {steps} steps", steps,
                40, steps, "active-set", penalty)
    for n in (5, 10, 20, 80, 160):
        one("augmented-lagrangian, 10 steps, refined", f"augmented-lagrangian, 10 steps, {n} cells", n, n, 10,
            "augmented-lagrangian")


def press_fit(args, rows, work):
    if not wanted(args, "press-fit"):
        return
    import friction_tradeoff as ft
    force = ft.closed_form()
    for slip, contact, events in ft.MODELS:
        family = ft.label(slip, contact, events)
        for n in (5, 10, 20, 50, 100):
            text = deckgen.press_fit_deck(slip=slip, contact=contact, steps=n, push=ft.PUSH / n, nu=0.0,
                                          events=events)
            res, why = gapfe_run(args, work, f"pf_{slip}_{contact}_{events}_{n}", text)
            if res is None:
                add(rows, "press-fit", "command", family, f"{family}, {n} steps", n, math.nan, math.nan, 0, math.nan,
                    why)
                continue
            out, wall, peak, solves = res
            got = ft.curve(out)[-1][1]
            add(rows, "press-fit", "command", family, f"{family}, {n} steps", n, abs(got - force) / force, wall,
                solves, peak)


# ----------------------------------------------------------------------------------------------- output

def wanted(args, problem):
    return not args.only or problem in args.only.split(",")


def add(rows, problem, path, family, setting, swept, error, wall, solves, peak, note=""):
    rows.append(dict(problem=problem, path=path, family=family, setting=setting, swept=swept, error=error,
                     wall_s=wall, solves=solves, peak_mb=peak, note=note))
    print(f"{problem:14s} {setting:60s} error {error:9.2e}  {wall:10.3e} s  {solves:6.0f} solves  "
          f"{peak:7.1f} MB {note}", flush=True)


def pareto(points):
    """The points no other point beats in both time and error, by increasing time."""
    front, best = [], math.inf
    for r in sorted(points, key=lambda r: (r["wall_s"], r["error"])):
        if r["error"] < best:
            front.append(r)
            best = r["error"]
    return front


def plots(rows, outdir):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not found (apt-get install python3-matplotlib): no PNG", file=sys.stderr)
        return
    for problem in dict.fromkeys(r["problem"] for r in rows):
        pts = [r for r in rows if r["problem"] == problem and finite(r)]
        if not pts:
            continue
        fig, ax = plt.subplots(figsize=(8, 5))
        markers = "os^vDP*Xh<>p"
        for k, family in enumerate(dict.fromkeys(r["family"] for r in pts)):
            fam = sorted((r for r in pts if r["family"] == family), key=lambda r: float(r["swept"]))
            ax.loglog([r["wall_s"] for r in fam], [max(r["error"], 1e-16) for r in fam], marker=markers[k % 12],
                      ls="-", lw=0.8, ms=5, label=family)
        front = pareto(pts)
        ax.loglog([r["wall_s"] for r in front], [max(r["error"], 1e-16) for r in front], color="k", lw=2, alpha=0.35,
                  drawstyle="steps-post", label="Pareto front")
        for t in TARGETS:
            ax.axhline(t, color="grey", lw=0.5, ls=":")
        ax.set_xlabel(f"wall time [s] ({pts[0]['path']}: {'the gapfe run command' if pts[0]['path'] == 'command' else 'the library call'}, median)")
        ax.set_ylabel("error against the closed form [-]")
        ax.set_title(f"{problem}: error against cost (one marker per setting; lines sweep refinement, steps or dt)")
        ax.title.set_fontsize(9)
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(outdir / f"{problem}.png", dpi=100)
        plt.close(fig)


def finite(r):
    return isinstance(r["error"], float) and math.isfinite(r["error"]) and math.isfinite(r["wall_s"])


def atlas_md(rows, outdir, md, seconds, command, keep_run_lines=False):
    """keep_run_lines: a redraw keeps the machine and date lines of the run that made the table."""
    old = {}
    if keep_run_lines and md.exists():
        old = {ln.split(":")[0]: ln for ln in md.read_text().splitlines() if ln.startswith(("- machine:", "- date:"))}
    lines = ["# The speed/accuracy atlas", "",
             "Generated by `bench/atlas.py`; do not edit by hand. Each problem's error is measured",
             "against its closed form (or the 1-D ODE for the rate-dependent cases), its time is the median wall",
             "time of the whole library call or `gapfe run` process, its memory the process's peak RSS.",
             "Plasticity integrations: `return-mapping` is the command's default; `tangent` is the seed's one-solve",
             "scheme (SAGAEP, SAAC3), kept for reproducing legacy results (docs/plasticity.md).",
             "",
             f"- command: `{command}`",
             old.get("- machine", f"- machine: {platform.machine()}, {os.cpu_count()} cores, {platform.platform()}; "
                     f"one thread (OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS', 'unset')})"),
             old.get("- date", f"- date: {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC; the whole "
                     f"run took {seconds / 60:.1f} min"),
             f"- data: [`{outdir.name}/atlas.csv`]({outdir.name}/atlas.csv); pictures: `{outdir.name}/<problem>.png`",
             ""]
    for problem in dict.fromkeys(r["problem"] for r in rows):
        pts = [r for r in rows if r["problem"] == problem]
        ok = [r for r in pts if finite(r)]
        lines += [f"## {problem}", "", f"![{problem}]({outdir.name}/{problem}.png)", "",
                  "| error target | cheapest setting that reaches it | error | time [s] | solves | peak [MB] |",
                  "|---|---|---:|---:|---:|---:|"]
        for t in TARGETS:
            hits = [r for r in ok if r["error"] <= t]
            if hits:
                r = min(hits, key=lambda r: r["wall_s"])
                lines.append(f"| {t:g} | {r['setting']} | {r['error']:.2e} | {r['wall_s']:.4g} | {r['solves']:.0f} | "
                             f"{r['peak_mb']:.0f} |")
            else:
                best = min(ok, key=lambda r: r["error"]) if ok else None
                lines.append(f"| {t:g} | none of these settings (best: {best['setting']}, {best['error']:.2e})" if best
                             else f"| {t:g} | no run succeeded")
                lines[-1] += " | | | | |"
        failed = [r for r in pts if not finite(r)]
        if failed:
            lines += ["", "Runs that ended in an error (the atlas keeps them: the error is the answer):"]
            lines += [f"- {r['setting']}: {short(r['note'])}" for r in failed]
        lines.append("")
    md.write_text("\n".join(lines))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--gapfe", default="build/bench/examples/gapfe")
    ap.add_argument("--bench-dir", default="build/bench/bench")
    ap.add_argument("--repeat", type=int, default=3, help="runs per setting (median wall time)")
    ap.add_argument("--only", help="comma-separated problems")
    ap.add_argument("--out", default=str(HERE / "atlas"))
    ap.add_argument("--from-csv", help="redraw the pictures and ATLAS.md from an earlier atlas.csv")
    ap.add_argument("--took", type=float, help="with --from-csv: the minutes that run took, for ATLAS.md")
    args = ap.parse_args()
    outdir = pathlib.Path(args.out)
    outdir.mkdir(parents=True, exist_ok=True)
    command = "OPENBLAS_NUM_THREADS=1 /usr/bin/python3 bench/atlas.py " + " ".join(sys.argv[1:])
    if args.from_csv:  # the run that made the table
        command = ("OPENBLAS_NUM_THREADS=1 /usr/bin/python3 bench/atlas.py --gapfe build/bench/examples/gapfe "
                   "--bench-dir build/bench/bench --repeat 3`; tables and pictures redrawn with `--from-csv")
    t0 = time.perf_counter()
    if args.from_csv:
        rows = []
        for r in csv.DictReader(open(args.from_csv)):
            for k in ("error", "wall_s", "solves", "peak_mb"):
                r[k] = float(r[k])
            rows.append(r)
    else:
        rows = []
        work = pathlib.Path(tempfile.mkdtemp(prefix="gapfe_atlas_"))
        elements(args, rows)
        tube_solver(args, rows, work)
        two_tubes(args, rows, work)
        press_fit(args, rows, work)
        plastic(args, rows)
        rate(args, rows)
        with open(outdir / "atlas.csv", "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=FIELDS)
            w.writeheader()
            w.writerows(rows)
    seconds = args.took * 60 if args.from_csv and args.took else time.perf_counter() - t0
    plots(rows, outdir)
    md = outdir.parent / "ATLAS.md"  # next to the folder, which its links name
    atlas_md(rows, outdir, md, seconds, command, keep_run_lines=bool(args.from_csv))
    print(f"wrote {outdir}/atlas.csv, {outdir}/<problem>.png, {md} in {seconds / 60:.1f} min")
    return 0


if __name__ == "__main__":
    sys.exit(main())
