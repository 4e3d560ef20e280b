#!/usr/bin/env python3
"""Side-by-side benchmark: CalculiX (ccx) vs. gapfe on a Lame thick tube.

Both codes solve the same problem on the same structured mesh:

  * axisymmetric thick tube, inner radius a = 0.1 m, outer radius b = 0.2 m,
    axial length L = nz * (b - a) / nr (square cells);
  * E = 200e9 Pa, nu = 0.3, internal pressure p = 100e6 Pa on the bore r = a;
  * plane strain: u_z = 0 on every node of z = 0 and z = L, nothing else fixed;
  * nr x nz bilinear quads (ccx: CAX4) on the regular grid
    r_i = a + i (b - a) / nr,  z_j = j L / nz.

Closed form (plane strain) bore displacement:

    u(a) = (1 + nu) a / E * [ (1 - 2 nu) A + B / a^2 ],
    A = p a^2 / (b^2 - a^2),  B = p a^2 b^2 / (b^2 - a^2)   (= 9.5333e-5 m here)

For every size the script writes a ccx deck into the work directory, runs
`ccx -i <job>` there, then (if --gapfe is given) runs
`<gapfe> --nr NR --nz NZ --solver S` for every requested solver.  Each child
is timed (wall clock) and its peak resident set size is taken from
os.wait4()'s rusage (ru_maxrss, KiB on Linux; it covers the child and any
descendants it waited for).  With --repeat N every run is repeated N times
and the median time / RSS is reported.

The gapfe executable must print (somewhere on stdout) a line like

    gapfe nr=316 nz=158 dofs=100806 solver=eigen assemble_s=0.01 \
          factor_s=0.4 solve_s=0.02 total_s=0.5 u_bore=9.5333e-05

Only key=value tokens are used (the last line starting with "gapfe" wins);
other lines are ignored.

All children run single-threaded by default (OMP_NUM_THREADS,
CCX_NPROC_EQUATION_SOLVER, OPENBLAS_NUM_THREADS, MKL_NUM_THREADS all set to
--threads, default 1), so the comparison is one core against one core.

Notes on ccx:
  * ccx expands every CAX4 internally into a thin 3D wedge element (C3D8,
    2x2x2 integration) and ties the expanded nodes back to the 2D nodes with
    MPCs, so it ends up solving the same number of equations as a 2D code
    (2 * nodes minus the constrained u_z dofs -- that is the "dofs" it is
    reported with), but pays for the 3D element work and MPC handling, and
    its axisymmetric results carry a relative bias of roughly 2.5e-4 with
    respect to the exact 2D solution.
  * *DLOAD pressure is positive *into* the element face; with the
    counter-clockwise node order used here (n1=(i,j), n2=(i+1,j),
    n3=(i+1,j+1), n4=(i,j+1)) the bore face r = a is face 4 (nodes 4-1), so
    "P4, +p" pushes the bore outward.
  * Pressure is a genuine traction (no 2*pi or per-radian factor); only
    *CLOAD forces on axisymmetric models are special in ccx (they are taken
    for the 360-degree ring).
  * No *NODE FILE is requested, so the .frd file is essentially empty and
    ccx does no result-file I/O beyond one *NODE PRINT line in the .dat.

Usage:
    bench/ccx_compare.py [--sizes 316x158,1000x500] [--gapfe build/bench/gapfe_bench]
                         [--solvers eigen,cholmod] [--workdir DIR] [--repeat N]
                         [--threads N] [--ccx ccx]

Exit status: 0 on success, 2 if ccx is missing or fails (or bad arguments),
3 if every ccx run succeeded but a gapfe run failed.
"""

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

A_IN = 0.1
B_OUT = 0.2
E_MOD = 200e9
NU = 0.3
P_IN = 100e6


def closed_form_bore():
    a, b, p, E, nu = A_IN, B_OUT, P_IN, E_MOD, NU
    A = p * a * a / (b * b - a * a)
    B = p * a * a * b * b / (b * b - a * a)
    return (1.0 + nu) * a / E * ((1.0 - 2.0 * nu) * A + B / (a * a))


U_EXACT = closed_form_bore()


def die(msg, code=2):
    sys.stderr.write("ccx_compare: error: %s\n" % msg)
    sys.exit(code)


def parse_sizes(text):
    sizes = []
    for tok in text.split(","):
        tok = tok.strip().lower()
        if not tok:
            continue
        try:
            nr_s, nz_s = tok.split("x")
            nr, nz = int(nr_s), int(nz_s)
        except ValueError:
            die("bad size %r (expected NRxNZ, e.g. 316x158)" % tok)
        if nr < 1 or nz < 1:
            die("bad size %r (nr, nz must be >= 1)" % tok)
        sizes.append((nr, nz))
    if not sizes:
        die("--sizes is empty")
    return sizes


def child_env(threads):
    env = dict(os.environ)
    t = str(threads)
    env["OMP_NUM_THREADS"] = t
    env["CCX_NPROC_EQUATION_SOLVER"] = t
    env["OPENBLAS_NUM_THREADS"] = t
    env["MKL_NUM_THREADS"] = t
    return env


def run_measured(argv, cwd, env, stdout_path, stderr_path=None):
    """Run argv with stdout (and stderr, merged unless stderr_path is given)
    sent to files; return (exit_code, wall_seconds, peak_rss_kib, stdout_text,
    stderr_text)."""
    with open(stdout_path, "wb") as out, \
            open(stderr_path or os.devnull, "wb") as err:
        t0 = time.perf_counter()
        proc = subprocess.Popen(argv, cwd=cwd, env=env, stdin=subprocess.DEVNULL,
                                stdout=out,
                                stderr=err if stderr_path else subprocess.STDOUT)
        _, status, ru = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - t0
    code = os.waitstatus_to_exitcode(status)
    proc.returncode = code  # already reaped; keep Popen from waiting again
    with open(stdout_path, "r", errors="replace") as f:
        text = f.read()
    etext = ""
    if stderr_path:
        with open(stderr_path, "r", errors="replace") as f:
            etext = f.read()
    return code, wall, ru.ru_maxrss, text, etext


# ---------------------------------------------------------------- ccx ------

def node_id(i, j, nr):
    return j * (nr + 1) + i + 1


def write_id_list(lines, ids, per_line=8):
    for k in range(0, len(ids), per_line):
        lines.append(", ".join(str(x) for x in ids[k:k + per_line]) + ",")


def write_ccx_deck(path, nr, nz):
    h = (B_OUT - A_IN) / nr
    L = nz * h
    jmid = nz // 2
    out = ["*HEADING", "gapfe ccx_compare Lame tube nr=%d nz=%d" % (nr, nz),
           "*NODE, NSET=NALL"]
    for j in range(nz + 1):
        z = j * L / nz
        for i in range(nr + 1):
            r = A_IN + i * (B_OUT - A_IN) / nr
            out.append("%d, %.17g, %.17g" % (node_id(i, j, nr), r, z))
    out.append("*ELEMENT, TYPE=CAX4, ELSET=EALL")
    for j in range(nz):
        for i in range(nr):
            out.append("%d, %d, %d, %d, %d" % (
                j * nr + i + 1,
                node_id(i, j, nr), node_id(i + 1, j, nr),
                node_id(i + 1, j + 1, nr), node_id(i, j + 1, nr)))
    out.append("*NSET, NSET=NZFIX")
    write_id_list(out, [node_id(i, 0, nr) for i in range(nr + 1)]
                  + [node_id(i, nz, nr) for i in range(nr + 1)])
    out.append("*NSET, NSET=NBOREMID")
    out.append("%d," % node_id(0, jmid, nr))
    out.append("*ELSET, ELSET=EBORE")
    # elements of column i = 0; their face 4 (nodes 4-1) lies on r = a
    write_id_list(out, [j * nr + 1 for j in range(nz)])
    out += [
        "*MATERIAL, NAME=STEEL",
        "*ELASTIC",
        "%.17g, %.17g" % (E_MOD, NU),
        "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL",
        "*BOUNDARY",
        "NZFIX, 2, 2, 0.",
        "*STEP",
        "*STATIC",
        "*DLOAD",
        "EBORE, P4, %.17g" % P_IN,
        "*NODE PRINT, NSET=NBOREMID",
        "U",
        "*END STEP",
    ]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
    return node_id(0, jmid, nr)


def parse_ccx_dat(path, nid):
    """Return u_r of node nid from the first displacement block of a .dat."""
    try:
        with open(path, "r", errors="replace") as f:
            lines = f.readlines()
    except OSError:
        return None
    in_block = False
    for line in lines:
        s = line.strip()
        if s.startswith("displacements"):
            in_block = True
            continue
        if in_block and s:
            parts = s.split()
            try:
                if int(parts[0]) == nid:
                    return float(parts[1].replace("D", "E"))
            except (ValueError, IndexError):
                in_block = s.startswith("displacements")
    return None


def parse_ccx_neq(log_text):
    """Number of equations ccx solved (printed on the line after the label)."""
    lines = log_text.splitlines()
    for k, line in enumerate(lines[:-1]):
        if line.strip() == "number of equations":
            try:
                return int(lines[k + 1].split()[0])
            except (ValueError, IndexError):
                return None
    return None


def parse_ccx_total_time(log_text):
    """ccx's own 'Total CalculiX Time: X' (seconds), or None."""
    for line in log_text.splitlines():
        if "Total CalculiX Time" in line:
            try:
                return float(line.split(":")[1])
            except (ValueError, IndexError):
                return None
    return None


def median_or_none(vals):
    vals = [v for v in vals if v is not None]
    return statistics.median(vals) if vals else None


def run_ccx(ccx, workdir, nr, nz, repeat, env):
    job = "tube_%dx%d" % (nr, nz)
    nid = write_ccx_deck(os.path.join(workdir, job + ".inp"), nr, nz)
    times, rsss, inner, u, neq = [], [], [], None, None
    for k in range(repeat):
        for ext in (".dat", ".frd", ".sta", ".cvg"):
            try:
                os.remove(os.path.join(workdir, job + ext))
            except OSError:
                pass
        log_path = os.path.join(workdir, job + ".log")
        code, wall, rss, text, _ = run_measured([ccx, "-i", job], workdir, env,
                                                log_path)
        if code != 0 or "*ERROR" in text:
            tail = "\n".join(text.splitlines()[-15:])
            die("ccx failed for %dx%d (exit code %d); see %s\n%s"
                % (nr, nz, code, log_path, tail))
        u = parse_ccx_dat(os.path.join(workdir, job + ".dat"), nid)
        if u is None:
            die("could not find displacement of node %d in %s"
                % (nid, os.path.join(workdir, job + ".dat")))
        neq = parse_ccx_neq(text)
        times.append(wall)
        rsss.append(rss)
        inner.append(parse_ccx_total_time(text))
    return {"wall": statistics.median(times), "rss_kib": statistics.median(rsss),
            "u": u, "dofs": neq, "inner": median_or_none(inner)}


# -------------------------------------------------------------- gapfe ------

def parse_gapfe_line(text):
    kv = None
    for line in text.splitlines():
        s = line.strip()
        if s.startswith("gapfe") and "=" in s:
            d = {}
            for tok in s.split():
                if "=" in tok:
                    key, _, val = tok.partition("=")
                    d[key] = val
            kv = d
    return kv


def run_gapfe(exe, workdir, nr, nz, solver, repeat, env):
    times, rsss, inner, kv = [], [], [], None
    base = os.path.join(workdir, "gapfe_%dx%d_%s" % (nr, nz, solver))
    log_path, err_path = base + ".out", base + ".err"
    for k in range(repeat):
        argv = [exe, "--nr", str(nr), "--nz", str(nz), "--solver", solver]
        code, wall, rss, text, etext = run_measured(argv, workdir, env, log_path,
                                                    err_path)
        if code != 0:
            tail = "\n".join((text + etext).splitlines()[-10:])
            return {"error": "exit code %d (stdout %s, stderr %s)\n%s"
                    % (code, log_path, err_path, tail)}
        kv = parse_gapfe_line(text)
        if kv is None:
            return {"error": "no 'gapfe key=value' line on stdout (%s)" % log_path}
        times.append(wall)
        rsss.append(rss)
        try:
            inner.append(float(kv["total_s"]))
        except (KeyError, ValueError):
            inner.append(None)
    res = {"wall": statistics.median(times), "rss_kib": statistics.median(rsss),
           "kv": kv, "inner": median_or_none(inner)}
    try:
        res["u"] = float(kv["u_bore"])
    except (KeyError, ValueError):
        res["u"] = None
    try:
        res["dofs"] = int(kv["dofs"])
    except (KeyError, ValueError):
        res["dofs"] = None
    for key, want in (("nr", nr), ("nz", nz)):
        if key in kv and kv[key] != str(want):
            sys.stderr.write("ccx_compare: warning: gapfe reported %s=%s, expected %d\n"
                             % (key, kv[key], want))
    if kv.get("solver") not in (None, solver):
        sys.stderr.write("ccx_compare: warning: gapfe reported solver=%s, expected %s\n"
                         % (kv.get("solver"), solver))
    return res


# --------------------------------------------------------------- main ------

def fmt_err(u):
    if u is None:
        return "n/a"
    return "%+.3e" % ((u - U_EXACT) / U_EXACT)


def main():
    ap = argparse.ArgumentParser(
        description="Run CalculiX and gapfe on the same Lame thick-tube mesh "
                    "and compare wall time / peak RSS.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=__doc__.split("Usage:")[0])
    ap.add_argument("--sizes", default="316x158",
                    help="comma-separated NRxNZ list (default 316x158)")
    ap.add_argument("--gapfe", default=None,
                    help="gapfe bench executable (omit to run ccx only)")
    ap.add_argument("--solvers", default="eigen,cholmod",
                    help="comma-separated gapfe solvers (default eigen,cholmod)")
    ap.add_argument("--workdir", default=None,
                    help="directory for ccx decks/results (default: new temp dir, kept)")
    ap.add_argument("--repeat", type=int, default=1,
                    help="repetitions per run; the median is reported (default 1)")
    ap.add_argument("--threads", type=int, default=1,
                    help="thread count exported to all children (default 1)")
    ap.add_argument("--ccx", default="ccx", help="ccx executable (default: ccx on PATH)")
    args = ap.parse_args()

    if args.repeat < 1:
        die("--repeat must be >= 1")
    if args.threads < 1:
        die("--threads must be >= 1")
    sizes = parse_sizes(args.sizes)
    solvers = [s.strip() for s in args.solvers.split(",") if s.strip()]

    ccx = shutil.which(args.ccx)
    if ccx is None:
        die("CalculiX executable %r not found on PATH "
            "(Debian: apt-get install calculix-ccx)" % args.ccx)

    gapfe = None
    if args.gapfe:
        gapfe = os.path.abspath(args.gapfe)
        if not (os.path.isfile(gapfe) and os.access(gapfe, os.X_OK)):
            die("gapfe executable %r does not exist or is not executable" % args.gapfe)
        if not solvers:
            die("--solvers is empty")

    if args.workdir:
        workdir = os.path.abspath(args.workdir)
        os.makedirs(workdir, exist_ok=True)
    else:
        workdir = tempfile.mkdtemp(prefix="ccx_compare_")

    env = child_env(args.threads)
    print("# ccx_compare: a=%g b=%g E=%g nu=%g p=%g, exact u_r(a) = %.6e m"
          % (A_IN, B_OUT, E_MOD, NU, P_IN, U_EXACT))
    print("# ccx=%s  gapfe=%s  threads=%d  repeat=%d (median)  workdir=%s"
          % (ccx, gapfe or "-", args.threads, args.repeat, workdir))
    sys.stdout.flush()

    rows = []      # (size, label, dofs, wall, rss_mib, u)
    ratios = []    # (size, solver, t_ratio, m_ratio)
    gapfe_failed = False
    for nr, nz in sizes:
        size = "%dx%d" % (nr, nz)
        c = run_ccx(ccx, workdir, nr, nz, args.repeat, env)
        rows.append((size, "ccx/spooles", c["dofs"], c["wall"], c["inner"],
                     c["rss_kib"] / 1024.0, c["u"]))
        if c["u"] <= 0:
            sys.stderr.write("ccx_compare: warning: ccx bore displacement %g is not "
                             "outward; pressure sign/face label wrong?\n" % c["u"])
        if gapfe:
            for s in solvers:
                g = run_gapfe(gapfe, workdir, nr, nz, s, args.repeat, env)
                if "error" in g:
                    gapfe_failed = True
                    sys.stderr.write("ccx_compare: gapfe %s solver=%s failed: %s\n"
                                     % (size, s, g["error"]))
                    rows.append((size, "gapfe/" + s, None, None, None, None, None))
                    continue
                rows.append((size, "gapfe/" + s, g["dofs"], g["wall"], g["inner"],
                             g["rss_kib"] / 1024.0, g["u"]))
                ratios.append((size, s, c["wall"] / g["wall"] if g["wall"] > 0 else None,
                               c["rss_kib"] / g["rss_kib"] if g["rss_kib"] > 0 else None))

    hdr = "%-11s %-16s %10s %10s %10s %12s %13s %11s" % (
        "size", "code/solver", "dofs", "wall_s", "self_s", "peakRSS_MiB",
        "u_r(a) [m]", "rel_err")
    print()
    print(hdr)
    print("-" * len(hdr))
    for size, label, dofs, wall, inner, rss, u in rows:
        if wall is None:
            print("%-11s %-16s %10s %10s %10s %12s %13s %11s"
                  % (size, label, "-", "FAILED", "-", "-", "-", "-"))
            continue
        print("%-11s %-16s %10s %10.3f %10s %12.1f %13s %11s" % (
            size, label, dofs if dofs is not None else "?", wall,
            "%.3f" % inner if inner is not None else "-", rss,
            "%.6e" % u if u is not None else "n/a", fmt_err(u)))
    print("(ccx dofs = equations ccx actually solved, i.e. free 2D dofs after its 3D "
          "expansion is folded back by MPCs and the u_z = 0 dofs are removed;\n"
          " gapfe dofs = whatever gapfe reports.  self_s = the code's own total time "
          "(ccx 'Total CalculiX Time', gapfe total_s).\n rel_err is vs. the closed form and "
          "includes discretisation error; ccx adds ~2.5e-4 axisymmetric bias)")

    if ratios:
        print()
        hdr2 = "%-11s %-10s %22s %20s" % ("size", "solver", "ccx_time/gapfe_time",
                                          "ccx_rss/gapfe_rss")
        print(hdr2)
        print("-" * len(hdr2))
        for size, s, tr, mr in ratios:
            print("%-11s %-10s %22s %20s" % (
                size, s, "%.2f" % tr if tr is not None else "n/a",
                "%.2f" % mr if mr is not None else "n/a"))
    print()
    print("# ccx files kept in %s" % workdir)
    return 3 if gapfe_failed else 0


if __name__ == "__main__":
    sys.exit(main())
