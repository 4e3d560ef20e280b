#!/usr/bin/env python3
"""Side-by-side benchmark: CalculiX (ccx) vs. gapfe on two concentric tubes closing a radial gap.

    python3 bench/ccx_contact.py --gapfe build/bench/examples/gapfe

The problem (docs/theory.md V5), the same for both codes:

  * axisymmetric, plane strain: u_z = 0 on every node;
  * inner tube a = 1 <= r <= b = 1.5, outer tube b + delta = 1.5005 <= r <= c = 2 (radial gap
    delta = 5e-4), both of height h = (b - a) * 80 / 40 = 1, each meshed 40 (radial) x 80 (axial)
    bilinear quads (ccx: CAX4) on a regular grid; E = 200000, nu = 0.3 for both;
  * bore pressure on r = a ramped linearly from 0 to p = 100 in 10 equal increments;
  * frictionless contact between the inner tube's outer face r = b and the outer tube's bore.

Closed form (standard small-gap compound-cylinder result, the outer tube's bore taken at r = b):

    p_c = delta E (b^2 - a^2) / (2 a^2 b (1 - nu^2))             closure bore pressure (45.79)
    q   = (p - p_c) a^2 (c^2 - b^2) / (b^2 (c^2 - a^2))          contact pressure      (14.055)

and the bore displacement u_r(a) of the inner tube under p inside and q outside (Lame, plane
strain; 1.14778e-3). Both meshes put the outer tube's bore at b + delta, though, and the Lame
solution of that geometry (u_in(b; p, q) - u_out(b + delta; q) = delta) gives q = 14.043, 8.5e-4
lower -- as large as the discretisation errors compared here -- so the table shows the errors
against both (q_err: standard closed form, q_err_geo: exact geometry).

gapfe: the deck comes from bench/deckgen.py, two_tubes_deck(n=40, nz=80, steps=10, contact=POLICY)
(POLICY = --contact, default augmented-lagrangian; a column of gap elements between the tubes), and
is run as `GAPFE run DECK --out DIR --quiet --element quad4` (--element: quad4 = bilinear, like
CAX4, is the default here; `--element deck` keeps gapfe's own default, the seed's four-CST quad),
--repeat times, median wall time; then once more, untimed and without --quiet, for its contact
summary line (increments, linear solves, factorizations). From gaps.csv
(step,inc,t,element,pair,status,gap,f_n,f_t) the rows of the last (step, inc) are summed: a row is
one gap element's full-ring normal force at one of its two node pairs (compressive positive), and
a node pair shared by two gap elements gets one row from each, each with that element's share,
so the sum over all rows is the total contact force and q = sum f_n / (2 pi b h). (Checked
against the closed form: halving the sum would be off by a factor of 2.) nodes.csv gives u_r of
node (I = 1, J = 41), the bore at mid-height, at the last (step, inc).

ccx: the script writes ccx_tubes.inp -- two node and element sets, CAX4; *BOUNDARY u_z (DOF 2) = 0
on all nodes; *CONTACT PAIR, TYPE=NODE TO SURFACE, slave = faces S2 (nodes 2-3) of the inner
tube's outer column (r = b), master = faces S4 (nodes 4-1) of the outer tube's inner column;
*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR with slope K (--slope, default 1.6e9 = 100 E /
element size: the penetration q / K = 9e-9 lowers q by ~1.5e-5 relative; K = 1e8 lowers it by
2e-4, K = 1e7 by 2.4e-3; all three converge in 21 iterations), a small tension sigma_inf = 1e-3
for open springs and the default c0; *STEP (geometrically linear, ccx iterates on contact
anyway), *STATIC 0.1, 1.0, 1e-5, 0.1 (so 10 increments unless ccx cuts back; no *CONTROLS
needed); *DLOAD EBORE, P4, 100 on the bore faces (ccx ramps loads linearly over a *STATIC step);
*NODE PRINT U (bore, mid-height), *CONTACT PRINT CSTR, *NODE FILE U, *EL FILE S, *CONTACT FILE
CSTR, CDIS -- and runs `ccx -i ccx_tubes` --ccx-repeat times (median wall time). Parsed:
increments and Newton iterations from the .sta (and the .cvg, which also counts cut-back
attempts), the bore u_r and the contact pressure of the last increment from the .dat: the normal
contact stresses of all contact elements, averaged (ccx reports them at the slave nodes of its
internal 3-D expansion, two per 2-D node, so they are not mapped back to z; they are uniform
along z here since u_z = 0 everywhere, and a spread above 1% is reported as a warning).

All children run with OMP_NUM_THREADS = CCX_NPROC_EQUATION_SOLVER = OPENBLAS_NUM_THREADS = 1
(--threads), one core against one core.

Exit status: 0 on success, 2 if ccx fails or is missing (or bad arguments), 3 if gapfe fails.
"""

import argparse
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

sys.dont_write_bytecode = True  # no bench/__pycache__ from importing deckgen
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import deckgen  # noqa: E402

A, B, GAP, C = 1.0, 1.5, 5e-4, 2.0
E_MOD, NU, P = 200000.0, 0.3, 100.0
N, NZ, STEPS = 40, 80, 10
H = (B - A) * NZ / N
CCX_JOB = "ccx_tubes"


# ------------------------------------------------------------ closed form ------

def lame_u(r, r_in, r_out, p_in, p_out):
    """Plane-strain Lame radial displacement at r of a tube r_in..r_out (pressures compressive +)."""
    d = r_out ** 2 - r_in ** 2
    a_ = (p_in * r_in ** 2 - p_out * r_out ** 2) / d
    b_ = (p_in - p_out) * r_in ** 2 * r_out ** 2 / d
    return (1 + NU) / E_MOD * ((1 - 2 * NU) * a_ * r + b_ / r)


def closed_form():
    p_c = GAP * E_MOD * (B ** 2 - A ** 2) / (2 * A ** 2 * B * (1 - NU ** 2))
    q = max(P - p_c, 0.0) * A ** 2 * (C ** 2 - B ** 2) / (B ** 2 * (C ** 2 - A ** 2))
    # the same with the outer tube's bore at b + delta: u_in(b; p, q) - u_out(b + delta; q) = delta
    closing = lambda qq: lame_u(B, A, B, P, qq) - lame_u(B + GAP, B + GAP, C, qq, 0.0) - GAP
    f0, f1 = closing(0.0), closing(1.0)
    q_exact = max(-f0 / (f1 - f0), 0.0)
    return {"p_c": p_c, "q": q, "u_bore": lame_u(A, A, B, P, q),
            "q_exact": q_exact, "u_bore_exact": lame_u(A, A, B, P, q_exact)}


# ----------------------------------------------------------------- common ------

def die(msg, code=2):
    sys.stderr.write("ccx_contact: error: %s\n" % msg)
    sys.exit(code)


def child_env(threads):
    env = dict(os.environ)
    for key in ("OMP_NUM_THREADS", "CCX_NPROC_EQUATION_SOLVER", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        env[key] = str(threads)
    return env


def run_timed(argv, cwd, env, log_path):
    """Run argv (stdout and stderr to log_path); return (exit code, wall seconds, log text)."""
    with open(log_path, "wb") as log:
        t0 = time.perf_counter()
        code = subprocess.call(argv, cwd=cwd, env=env, stdin=subprocess.DEVNULL, stdout=log,
                               stderr=subprocess.STDOUT)
        wall = time.perf_counter() - t0
    with open(log_path, "r", errors="replace") as f:
        return code, wall, f.read()


def ids(lines, values, per_line=16):
    for k in range(0, len(values), per_line):
        lines.append(", ".join(str(v) for v in values[k:k + per_line]) + ",")


# -------------------------------------------------------------------- ccx ------

def ccx_deck(slope, sigma_inf):
    """The ccx input and the number of the bore node at mid-height. Nodes (i, j), i = 0..N across,
    j = 0..NZ up: inner tube j (N + 1) + i + 1, outer tube the same plus (N + 1)(NZ + 1). Element
    corners counter-clockwise (i,j), (i+1,j), (i+1,j+1), (i,j+1): face 2 (nodes 2-3) is the outer
    side, face 4 (nodes 4-1) the inner side."""
    per_tube_nodes, per_tube_elems = (N + 1) * (NZ + 1), N * NZ
    node = lambda tube, i, j: tube * per_tube_nodes + j * (N + 1) + i + 1
    elem = lambda tube, i, j: tube * per_tube_elems + j * N + i + 1
    out = ["*HEADING", "gapfe ccx_contact: two tubes 1-1.5 and 1.5005-2, gap 5e-4, bore pressure 100"]
    for tube, (r0, r1) in enumerate(((A, B), (B + GAP, C))):
        out.append("*NODE, NSET=%s" % ("NINNER", "NOUTER")[tube])
        for j in range(NZ + 1):
            for i in range(N + 1):
                out.append("%d, %.17g, %.17g" % (node(tube, i, j), r0 + i * (r1 - r0) / N, j * H / NZ))
        out.append("*ELEMENT, TYPE=CAX4, ELSET=%s" % ("EINNER", "EOUTER")[tube])
        for j in range(NZ):
            for i in range(N):
                out.append("%d, %d, %d, %d, %d" % (elem(tube, i, j), node(tube, i, j), node(tube, i + 1, j),
                                                  node(tube, i + 1, j + 1), node(tube, i, j + 1)))
    bore_mid = node(0, 0, NZ // 2)
    out += ["*NSET, NSET=NALL", "NINNER, NOUTER", "*ELSET, ELSET=EALL", "EINNER, EOUTER",
            "*NSET, NSET=NBOREMID", "%d," % bore_mid, "*ELSET, ELSET=EBORE"]
    ids(out, [elem(0, 0, j) for j in range(NZ)])
    out.append("*ELSET, ELSET=ESLAVE")
    ids(out, [elem(0, N - 1, j) for j in range(NZ)])
    out.append("*ELSET, ELSET=EMASTER")
    ids(out, [elem(1, 0, j) for j in range(NZ)])
    out += [
        "*SURFACE, NAME=SSLAVE, TYPE=ELEMENT", "ESLAVE, S2",
        "*SURFACE, NAME=SMASTER, TYPE=ELEMENT", "EMASTER, S4",
        "*MATERIAL, NAME=STEEL", "*ELASTIC", "%.17g, %.17g" % (E_MOD, NU),
        "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL",
        "*BOUNDARY", "NALL, 2, 2, 0.",
        "*CONTACT PAIR, INTERACTION=SI, TYPE=NODE TO SURFACE", "SSLAVE, SMASTER",
        "*SURFACE INTERACTION, NAME=SI",
        "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR", "%.17g, %.17g" % (slope, sigma_inf),
        "*STEP, INC=1000",
        "*STATIC",
        "%g, 1.0, 1e-5, %g" % (1.0 / STEPS, 1.0 / STEPS),
        "*DLOAD", "EBORE, P4, %.17g" % P,
        "*NODE PRINT, NSET=NBOREMID", "U",
        "*CONTACT PRINT", "CSTR",
        "*NODE FILE", "U",
        "*EL FILE", "S",
        "*CONTACT FILE", "CSTR, CDIS",
        "*END STEP",
    ]
    return "\n".join(out) + "\n", bore_mid


def parse_ccx_sta(path):
    """(increments, Newton iterations) summed over the converged increments of the .sta file."""
    incs, its = 0, 0
    try:
        with open(path, "r", errors="replace") as f:
            for line in f:
                parts = line.split()
                if len(parts) == 7 and all(p.isdigit() for p in parts[:4]):
                    incs, its = incs + 1, its + int(parts[3])
    except OSError:
        return None, None
    return incs or None, its or None


def parse_ccx_cvg(path):
    """All Newton iterations ccx did, cut-back attempts included (data rows of the .cvg file)."""
    try:
        with open(path, "r", errors="replace") as f:
            return sum(1 for line in f if len(line.split()) == 9 and line.split()[0].isdigit()) or None
    except OSError:
        return None


def parse_ccx_dat(path, bore_node):
    """Last-increment (u_r of bore_node, [contact pressures]) from the *NODE PRINT / *CONTACT PRINT
    blocks of the .dat file."""
    u, press, block = None, None, None
    with open(path, "r", errors="replace") as f:
        for line in f:
            s = line.strip()
            if s.startswith("displacements"):
                block = "u"
            elif s.startswith("contact stress"):
                block, press = "c", []
            elif s and block:
                parts = s.split()
                try:
                    node, value = int(parts[0]), float(parts[1].replace("D", "E"))
                except (ValueError, IndexError):
                    block = None
                    continue
                if block == "u" and node == bore_node:
                    u = value
                elif block == "c":
                    press.append(value)
    return u, press


def run_ccx(ccx, workdir, env, slope, sigma_inf, repeat):
    text, bore_node = ccx_deck(slope, sigma_inf)
    with open(os.path.join(workdir, CCX_JOB + ".inp"), "w") as f:
        f.write(text)
    walls = []
    for _ in range(repeat):
        for ext in (".dat", ".frd", ".sta", ".cvg"):
            try:
                os.remove(os.path.join(workdir, CCX_JOB + ext))
            except OSError:
                pass
        log = os.path.join(workdir, CCX_JOB + ".log")
        code, wall, out = run_timed([ccx, "-i", CCX_JOB], workdir, env, log)
        if code != 0 or "*ERROR" in out or "Job finished" not in out:
            return {"error": "ccx exit code %d; see %s\n%s" % (code, log, "\n".join(out.splitlines()[-15:]))}
        walls.append(wall)
    incs, its = parse_ccx_sta(os.path.join(workdir, CCX_JOB + ".sta"))
    u, press = parse_ccx_dat(os.path.join(workdir, CCX_JOB + ".dat"), bore_node)
    if u is None or not press:
        return {"error": "no bore displacement / contact stress in %s.dat" % CCX_JOB}
    q = statistics.fmean(press)
    if max(press) - min(press) > 1e-2 * abs(q):
        sys.stderr.write("ccx_contact: warning: ccx contact pressure not uniform along z (%g .. %g)\n"
                         % (min(press), max(press)))
    return {"wall": statistics.median(walls), "q": q, "u": u,
            "work": "%s increments, %s Newton iterations (%s in .cvg)"
                    % (incs, its, parse_ccx_cvg(os.path.join(workdir, CCX_JOB + ".cvg")))}


# ------------------------------------------------------------------ gapfe ------

def read_csv_last_increment(path):
    """Header and the rows of the last (step, inc) block of a gapfe CSV file."""
    with open(path, "r") as f:
        header = f.readline().strip().split(",")
        rows = [line.strip().split(",") for line in f if line.strip()]
    if not rows:
        return header, []
    last = max((int(r[0]), float(r[1])) for r in rows)
    return header, [dict(zip(header, r)) for r in rows if (int(r[0]), float(r[1])) == last]


def run_gapfe(exe, workdir, env, contact, element, repeat):
    deck = os.path.join(workdir, "gapfe_tubes.deck")
    with open(deck, "w") as f:
        f.write(deckgen.two_tubes_deck(n=N, nz=NZ, steps=STEPS, contact=contact))
    out = os.path.join(workdir, "gapfe_out")
    options = [] if element == "deck" else ["--element", element]
    walls = []
    for _ in range(repeat):
        shutil.rmtree(out, ignore_errors=True)
        log = os.path.join(workdir, "gapfe.log")
        code, wall, text = run_timed([exe, "run", deck, "--out", out, "--quiet"] + options, workdir, env, log)
        if code != 0:
            return {"error": "gapfe exit code %d; see %s\n%s" % (code, log, "\n".join(text.splitlines()[-10:]))}
        walls.append(wall)
    try:
        _, gaps = read_csv_last_increment(os.path.join(out, "gaps.csv"))
        _, nodes = read_csv_last_increment(os.path.join(out, "nodes.csv"))
    except (OSError, ValueError, IndexError) as e:
        return {"error": "cannot read gapfe's CSV files in %s: %s" % (out, e)}
    if not gaps:
        return {"error": "gaps.csv in %s has no rows (no gap elements in the deck?)" % out}
    # one row per gap element and pair, f_n = that element's full-ring share: the sum is the total
    q = sum(float(r["f_n"]) for r in gaps) / (2 * math.pi * B * H)
    mid = [r for r in nodes if int(r["i"]) == 1 and int(r["j"]) == NZ // 2 + 1]
    if not mid:
        return {"error": "bore node (I = 1, J = %d) missing from nodes.csv" % (NZ // 2 + 1)}
    closed = sum(1 for r in gaps if r["status"] == "closed")
    res = {"wall": statistics.median(walls), "q": q, "u": float(mid[0]["u_r"]),
           "work": "%d of %d pairs closed" % (closed, len(gaps))}
    # one more, untimed and not quiet, for the contact summary line of the log
    code, _, text = run_timed([exe, "run", deck, "--out", out + "_log"] + options, workdir, env,
                              os.path.join(workdir, "gapfe_verbose.log"))
    for line in text.splitlines():
        if code == 0 and line.startswith("contact:") and "increments" in line:
            res["work"] = line.partition(":")[2].strip()
    return res


# ------------------------------------------------------------------- main ------

def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], epilog=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--gapfe", default="/work/main/build/bench/examples/gapfe", help="gapfe executable")
    ap.add_argument("--contact", default="augmented-lagrangian",
                    help="gapfe contact policy (saac, active-set, augmented-lagrangian)")
    ap.add_argument("--element", default="quad4",
                    help="gapfe element (quad4 = bilinear like CAX4, legacy, or 'deck' for gapfe's default)")
    ap.add_argument("--repeat", type=int, default=3, help="gapfe runs; the median wall time is reported")
    ap.add_argument("--ccx-repeat", type=int, default=1, help="ccx runs (about 10 s each); median reported")
    ap.add_argument("--slope", type=float, default=100 * E_MOD / ((B - A) / N),
                    help="ccx penalty slope K (default 100 E / element size = 1.6e9)")
    ap.add_argument("--sigma-inf", type=float, default=1e-3, help="ccx tension for large clearances")
    ap.add_argument("--workdir", default=None, help="work directory (default: a new temporary one, kept)")
    ap.add_argument("--threads", type=int, default=1, help="thread count exported to both codes (default 1)")
    ap.add_argument("--ccx", default="ccx", help="ccx executable (default: ccx on PATH)")
    args = ap.parse_args()
    if args.repeat < 1 or args.ccx_repeat < 1 or args.threads < 1:
        die("--repeat, --ccx-repeat and --threads must be >= 1")

    ccx = shutil.which(args.ccx)
    if ccx is None:
        die("CalculiX executable %r not found (Debian: apt-get install calculix-ccx)" % args.ccx)
    gapfe = os.path.abspath(args.gapfe)
    if not (os.path.isfile(gapfe) and os.access(gapfe, os.X_OK)):
        die("gapfe executable %r does not exist or is not executable" % args.gapfe)
    workdir = os.path.abspath(args.workdir) if args.workdir else tempfile.mkdtemp(prefix="ccx_contact_")
    os.makedirs(workdir, exist_ok=True)
    env = child_env(args.threads)

    cf = closed_form()
    print("# two tubes %g-%g and %g-%g, gap %g, h %g, E %g, nu %g, bore pressure %g in %d increments, %dx%d "
          "cells per tube" % (A, B, B + GAP, C, GAP, H, E_MOD, NU, P, STEPS, N, NZ))
    print("# closed form: p_c = %.4f, q = %.4f, u_r(a) = %.6e; exact geometry (outer bore at b + delta): "
          "q = %.4f (%+.1e), u_r(a) = %.6e" % (cf["p_c"], cf["q"], cf["u_bore"], cf["q_exact"],
                                              cf["q_exact"] / cf["q"] - 1, cf["u_bore_exact"]))
    print("# ccx %s (K = %g, sigma_inf = %g, %d run(s)); gapfe %s (contact %s, element %s, %d run(s)); "
          "threads %d; workdir %s" % (ccx, args.slope, args.sigma_inf, args.ccx_repeat, gapfe, args.contact,
                                      args.element, args.repeat, args.threads, workdir))
    sys.stdout.flush()

    c = run_ccx(ccx, workdir, env, args.slope, args.sigma_inf, args.ccx_repeat)
    g = run_gapfe(gapfe, workdir, env, args.contact, args.element, args.repeat)

    hdr = "%-36s %8s %9s %10s %10s %13s %10s %10s" % (
        "code", "wall_s", "q", "q_err", "q_err_geo", "u_r(a)", "u_err", "u_err_geo")
    print()
    print(hdr)
    print("-" * len(hdr))
    for name, res in (("ccx 2.20 (CAX4, node-to-surface)", c), ("gapfe (%s, %s)" % (args.contact, args.element), g)):
        if "error" in res:
            print("%-36s %8s" % (name, "FAILED"))
            continue
        print("%-36s %8.3f %9.4f %+10.2e %+10.2e %13.6e %+10.2e %+10.2e" % (
            name, res["wall"], res["q"], res["q"] / cf["q"] - 1, res["q"] / cf["q_exact"] - 1,
            res["u"], res["u"] / cf["u_bore"] - 1, res["u"] / cf["u_bore_exact"] - 1))
    print("(q: contact pressure at p = %g; *_err: relative to the standard closed form, *_err_geo: to the "
          "Lame solution with the outer bore at b + delta)" % P)
    print()
    for name, res in (("ccx", c), ("gapfe", g)):
        print("%-6s %s" % (name + ":", res.get("work") or "FAILED (error on standard error)"))
    if "error" not in c and "error" not in g:
        print("ccx time / gapfe time = %.2f" % (c["wall"] / g["wall"]))
    print("# files kept in %s" % workdir)
    for name, res in (("ccx", c), ("gapfe", g)):
        if "error" in res:
            sys.stderr.write("ccx_contact: %s failed: %s\n" % (name, res["error"]))
    return 2 if "error" in c else 3 if "error" in g else 0


if __name__ == "__main__":
    sys.exit(main())
