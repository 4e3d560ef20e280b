#!/usr/bin/env python3
"""Side-by-side benchmark: CalculiX (ccx) vs. gapfe pushing a press-fitted hub along its shaft.

    python3 bench/ccx_friction.py --gapfe build/bench/examples/gapfe [--steps 20] [--repeat 3]

The problem, the same for both codes (units mm, N, MPa): bench/deckgen.py's press_fit_deck, refined to
NS x NZ cells in the shaft and NH x NZ in the hub -- a hollow shaft a = 12.5 .. b = 25, a hub b + w .. c = 50
(w = 0.001), length L = 50; E = 200000, nu = 0; step 1 presses the hub by q = 75 on its outer surface, then its
top face (z = L) is pushed down 0.04 in STEPS equal increments while the shaft's bottom face (z = 0) is
held axially; Coulomb friction mu = 0.15 at the interface. Closed form (nu = 0: exact away from the ends):

    p = (q - q_c) c^2 (b^2 - a^2) / (b^2 (c^2 - a^2)),  q_c = w E (c^2 - b^2) / (2 b c^2),
    F = mu p 2 pi b L                                   (the push-out force once the fit slides)

gapfe: `gapfe run DECK --out DIR --element quad4bbar` (bilinear with B-bar; with nu = 0 the same as CAX4's
full integration: no volumetric locking to relieve) with contact = active-set and slip = coulomb (the deck's
`$` lines), once with events = step-end (statuses settle at each step's end, as ccx does) and once with
events = locate (the default: every closure located), --repeat runs each, median wall time; F is the sum
of R_z over the hub's top face in reactions.csv at the last increment.

ccx: the script writes ccx_pressfit.inp -- shaft and hub as two CAX4 meshes; *CONTACT PAIR, TYPE=NODE TO
SURFACE (slave: the shaft's outer face S2, master: the hub's bore S4), *SURFACE BEHAVIOR,
PRESSURE-OVERCLOSURE=LINEAR with slope K = 100 E / element size, *FRICTION mu with stick slope 2e5
(--stick-slope; ccx's tangential penalty: 2e6 and K itself make ccx 2.20 cut back until it gives up), and
*CONTROLS that let it take up to 20 + 40 iterations per increment; step 1 *STATIC with *DLOAD P2 = q on the hub's outer faces, step 2 *STATIC in
STEPS increments with *BOUNDARY u_z = -0.04 on the hub's top nodes (the shaft's bottom nodes hold u_z = 0 in
both steps); *NODE PRINT, TOTALS=ONLY RF of the hub's top nodes. F is 180 times the last total RF_y in the
.dat (ccx reports an axisymmetric model's forces for its 2-degree segment); the
increments and Newton iterations come from the .sta file. ccx runs --ccx-repeat times (median).

Both with OMP_NUM_THREADS = CCX_NPROC_EQUATION_SOLVER = OPENBLAS_NUM_THREADS = 1: one core against one.
Prints both errors against F and the wall-time ratio ccx / gapfe. Exit status 0, 2 when ccx fails or is
missing, 3 when gapfe fails.
"""
import argparse
import math
import os
import shutil
import statistics
import sys
import tempfile

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ccx_contact  # noqa: E402  (run_timed, child_env, ids, parse_ccx_sta)
import deckgen  # noqa: E402

A, B, W, C, L = 12.5, 25.0, 0.001, 50.0, 50.0
E_MOD, Q, MU, PUSH = 200000.0, 75.0, 0.15, 0.04
CCX_JOB = "ccx_pressfit"


def closed_form():
    qc = W * E_MOD * (C * C - B * B) / (2 * B * C * C)
    p = (Q - qc) * C * C * (B * B - A * A) / (B * B * (C * C - A * A))
    return MU * p * 2 * math.pi * B * L


def ccx_deck(ns, nh, nz, steps, stick=None, controls=False):
    """The ccx input; nodes (i, j) of part k (0 shaft, 1 hub) numbered part by part, row by row."""
    parts = ((A, B, ns), (B + W, C, nh))
    base, ebase, out = [], [], ["*HEADING", "gapfe ccx_friction: hub on shaft, pressed by 75, pushed 0.04"]
    n0 = e0 = 0
    for k, (r0, r1, n) in enumerate(parts):
        base.append(n0), ebase.append(e0)
        out.append("*NODE, NSET=N%d" % k)
        for j in range(nz + 1):
            for i in range(n + 1):
                out.append("%d, %.17g, %.17g" % (n0 + j * (n + 1) + i + 1, r0 + i * (r1 - r0) / n, j * L / nz))
        out.append("*ELEMENT, TYPE=CAX4, ELSET=E%d" % k)
        for j in range(nz):
            for i in range(n):
                c = n0 + j * (n + 1) + i + 1
                out.append("%d, %d, %d, %d, %d" % (e0 + j * n + i + 1, c, c + 1, c + n + 2, c + n + 1))
        n0 += (n + 1) * (nz + 1)
        e0 += n * nz
    node = lambda k, i, j: base[k] + j * (parts[k][2] + 1) + i + 1
    elem = lambda k, i, j: ebase[k] + j * parts[k][2] + i + 1
    out += ["*ELSET, ELSET=EALL", "E0, E1", "*NSET, NSET=NSHAFTBOTTOM"]
    ccx_contact.ids(out, [node(0, i, 0) for i in range(ns + 1)])
    out.append("*NSET, NSET=NHUBTOP")
    ccx_contact.ids(out, [node(1, i, nz) for i in range(nh + 1)])
    out.append("*ELSET, ELSET=ESLAVE")
    ccx_contact.ids(out, [elem(0, ns - 1, j) for j in range(nz)])
    out.append("*ELSET, ELSET=EMASTER")
    ccx_contact.ids(out, [elem(1, 0, j) for j in range(nz)])
    out.append("*ELSET, ELSET=EOUTER")
    ccx_contact.ids(out, [elem(1, nh - 1, j) for j in range(nz)])
    slope = 100 * E_MOD / ((B - A) / ns)
    out += [
        "*SURFACE, NAME=SSLAVE, TYPE=ELEMENT", "ESLAVE, S2",
        "*SURFACE, NAME=SMASTER, TYPE=ELEMENT", "EMASTER, S4",
        "*MATERIAL, NAME=STEEL", "*ELASTIC", "%.17g, 0." % E_MOD,
        "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL",
        "*CONTACT PAIR, INTERACTION=SI, TYPE=NODE TO SURFACE", "SSLAVE, SMASTER",
        "*SURFACE INTERACTION, NAME=SI",
        "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR", "%.17g, 1e-3" % slope,
        "*FRICTION", "%.17g, %.17g" % (MU, stick if stick else slope),
        "*BOUNDARY", "NSHAFTBOTTOM, 2, 2, 0.", "NHUBTOP, 2, 2, 0.",
        "*STEP, INC=1000", "*STATIC", "0.25, 1.0, 1e-5, 0.25",
        "*DLOAD", "EOUTER, P2, %.17g" % Q,
        "*END STEP",
        "*STEP, INC=10000", "*STATIC", "%g, 1.0, 1e-6, %g" % (1.0 / steps, 1.0 / steps),
    ] + (["*CONTROLS, PARAMETERS=TIME INCREMENTATION", "20, 40, 9, 200, 10, 4, , 5, , "] if controls else []) + [
        "*BOUNDARY", "NHUBTOP, 2, 2, %.17g" % -PUSH,
        "*NODE PRINT, NSET=NHUBTOP, TOTALS=ONLY", "RF",
        "*END STEP",
    ]
    return "\n".join(out) + "\n"


def parse_total_rf(path):
    """The axial (y) component of the last 'total force' line of the .dat file, times 180: ccx expands
    an axisymmetric model into a 2-degree segment and reports its forces for that segment."""
    last, take = None, False
    with open(path, "r", errors="replace") as f:
        for line in f:
            s = line.strip()
            if s.startswith("total force"):
                take = True
            elif take and s:
                parts = s.replace("D", "E").split()
                try:
                    last = 180.0 * float(parts[1])
                except (ValueError, IndexError):
                    pass
                take = False
    return last


def run_ccx(ccx, workdir, env, args):
    with open(os.path.join(workdir, CCX_JOB + ".inp"), "w") as f:
        f.write(ccx_deck(args.ns, args.nh, args.nz, args.steps, stick=args.stick_slope, controls=True))
    walls = []
    for _ in range(args.ccx_repeat):
        log = os.path.join(workdir, CCX_JOB + ".log")
        code, wall, out = ccx_contact.run_timed([ccx, "-i", CCX_JOB], workdir, env, log)
        if code != 0 or "*ERROR" in out or "Job finished" not in out:
            return {"error": "ccx exit code %d; see %s\n%s" % (code, log, "\n".join(out.splitlines()[-15:]))}
        walls.append(wall)
    incs, its = ccx_contact.parse_ccx_sta(os.path.join(workdir, CCX_JOB + ".sta"))
    force = parse_total_rf(os.path.join(workdir, CCX_JOB + ".dat"))
    if force is None:
        return {"error": "no total reaction force in %s.dat" % CCX_JOB}
    return {"wall": statistics.median(walls), "force": -force, "work": "%s increments, %s Newton iterations"
            % (incs, its)}


def run_gapfe(exe, workdir, env, args, events):
    deck = os.path.join(workdir, "press_fit_%s.deck" % events)
    with open(deck, "w") as f:
        f.write(deckgen.press_fit_deck(ns=args.ns, nh=args.nh, nz=args.nz, steps=args.steps,
                                       push=PUSH / args.steps, events=events))
    out = os.path.join(workdir, "gapfe_out_" + events)
    walls = []
    for _ in range(args.repeat):
        shutil.rmtree(out, ignore_errors=True)
        log = os.path.join(workdir, "gapfe.log")
        code, wall, text = ccx_contact.run_timed([exe, "run", deck, "--out", out, "--element", "quad4bbar"], workdir,
                                                 env, log)
        if code != 0:
            return {"error": "gapfe exit code %d; see %s\n%s" % (code, log, "\n".join(text.splitlines()[-10:]))}
        walls.append(wall)
    _, rows = ccx_contact.read_csv_last_increment(os.path.join(out, "reactions.csv"))
    force = -sum(float(r["R_z"]) for r in rows if float(r["r"]) > B + W / 2)
    work = next((line.partition(":")[2].strip() for line in text.splitlines() if line.startswith("contact:")), "")
    return {"wall": statistics.median(walls), "force": force, "work": work}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], epilog=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--gapfe", default="/work/main/build/bench/examples/gapfe")
    ap.add_argument("--steps", type=int, default=20)
    ap.add_argument("--ns", type=int, default=12)
    ap.add_argument("--nh", type=int, default=16)
    ap.add_argument("--nz", type=int, default=40)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--ccx-repeat", type=int, default=1)
    ap.add_argument("--workdir", default=None)
    ap.add_argument("--stick-slope", type=float, default=2e5,
                    help="ccx *FRICTION stick slope (its tangential penalty; 2e6 and above diverge in ccx 2.20)")
    args = ap.parse_args()
    ccx = shutil.which("ccx")
    if ccx is None:
        ccx_contact.die("ccx not found (apt-get install calculix-ccx)")
    workdir = args.workdir or tempfile.mkdtemp(prefix="ccx_friction_")
    os.makedirs(workdir, exist_ok=True)
    env = ccx_contact.child_env(1)
    F = closed_form()
    runs = {}
    for events in ("step-end", "locate"):
        runs[events] = run_gapfe(args.gapfe, workdir, env, args, events)
        if "error" in runs[events]:
            sys.stderr.write(runs[events]["error"] + "\n")
            return 3
    c = run_ccx(ccx, workdir, env, args)
    print("press fit, %d x %d + %d x %d cells, %d push steps; closed form F = mu p 2 pi b L = %.1f N"
          % (args.ns, args.nz, args.nh, args.nz, args.steps, F))
    for events, g in runs.items():
        print("gapfe (events = %s): F = %.1f N (%+.3f %%), %.3f s; %s"
              % (events, g["force"], 100 * (g["force"] - F) / F, g["wall"], g["work"]))
    if "error" in c:
        sys.stderr.write("ccx failed: " + c["error"] + "\n")
        return 2
    print("ccx:   F = %.1f N (%+.3f %%), %.3f s; %s" % (c["force"], 100 * (c["force"] - F) / F, c["wall"], c["work"]))
    for events, g in runs.items():
        print("wall-time ratio ccx / gapfe (events = %s): %.1f" % (events, c["wall"] / g["wall"]))
    print("workdir: %s" % workdir)
    return 0


if __name__ == "__main__":
    sys.exit(main())
