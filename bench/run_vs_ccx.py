#!/usr/bin/env python3
"""`gapfe run DECK --out DIR` against CalculiX on the same mesh: whole processes, interleaved, medians.

    python3 bench/run_vs_ccx.py [--cases tube-1e5,plastic-1e4,...] [--pairs 3]
                                [--gapfe build/bench/examples/gapfe] [--write BENCHMARKS.md]

What an analyst runs is the deck command, so that is what is timed: the process from start to exit,
reading, meshing, assembling, solving and writing every file (CSV, VTU, PVD) included; ccx likewise as
`ccx -i JOB` with its .dat output. Each case writes one I-J deck (bench/deckgen.py) and one ccx input on
the same grid (CAX4, the same nodes in the same order), then runs them interleaved: ccx, every gapfe
variant, ccx, ... (--pairs rounds). Wall time and peak resident memory (GNU time's %M) per run;
the table gives medians and the ratios ccx / gapfe of those medians. One thread everywhere
(OMP_NUM_THREADS, OPENBLAS_NUM_THREADS, CCX_NPROC_EQUATION_SOLVER = 1).

Cases (mm, MPa; a = 100, b = 200; plane strain: u_z = 0 on both ends):
  tube-1e5     Lame tube 316 x 158 square cells, bore pressure 100 (1.0e5 equations): CHOLMOD and Eigen
  tube-1e6     Lame tube 707 x 707 cells (1.0e6 equations), the bore pressure as BC-card ring forces
               (pressure cards' I5 node numbers stop at 99,999); ccx takes the same load as *DLOAD
  plastic-1e4  Mises tube 100 x 50 cells, sigma_y = 400, Prager c = 10 (uniaxial hardening modulus
               3c/2 = 15, ccx's *PLASTIC, HARDENING=KINEMATIC slope), bore pressure to 0.9 of the limit
               (2 / sqrt 3) sigma_y ln(b / a) in 20 fixed increments: return-mapping and tangent
  plastic-1e5  the same on 316 x 158 cells, return-mapping
  contact      bench/ccx_contact.py's two tubes across a radial gap (docs/theory.md V5; 40 x 80 cells each,
               6,642 equations: u_r only, u_z = 0 on every node; bore pressure 100 in 10 increments):
               gapfe augmented-lagrangian with Quad4 (bilinear, like CAX4), ccx node-to-surface penalty;
               ccx writes its U and S fields (*NODE FILE, *EL FILE) every increment, as gapfe does

--ccx-output fields adds *NODE FILE U and *EL FILE S (every increment, to the .frd) to the elastic and
plastic ccx inputs, so that both codes write the whole displacement and stress fields, as gapfe does by
default; the default (print) has ccx print one node's displacement (and the PEEQ of one row) only.

Accuracy is judged against the closed forms, not between the codes: the Lame bore displacement for the
elastic cases; the contact pressure q against the compound-cylinder closed form for the contact case; for the plastic ones the bore u_r of both codes (and their difference) and the
elastic-plastic radius against docs/theory.md V6's Mises plane-strain formula (valid for nu = 1/2, so a
guide to about 1%: p = (2 / sqrt 3) sigma_y [ln(rho / a) + (b^2 - rho^2) / (2 b^2)]).

--write FILE replaces the text between the markers `<!-- run_vs_ccx: begin -->` and
`<!-- run_vs_ccx: end -->` in FILE with the table, the command, the machine and the date.
Exit status 0, or 2 when a run fails (its log is named)."""
import argparse
import datetime
import math
import os
import platform
import shlex
import statistics
import subprocess
import sys
import tempfile
import time

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ccx_contact  # noqa: E402
import deckgen  # noqa: E402

A, B, E_MOD, NU = 100.0, 200.0, 200000.0, 0.3
CONTACT_SLOPE = 100 * ccx_contact.E_MOD / ((ccx_contact.B - ccx_contact.A) / ccx_contact.N)  # ccx_contact's K
SIGMA_Y, HARDENING_C = 400.0, 10.0
P_LIMIT = 2 / math.sqrt(3) * SIGMA_Y * math.log(B / A)


class Case:
    def __init__(self, name, ni, nj, kind, variants, p, steps=1, nodal=False):
        self.name, self.ni, self.nj, self.kind, self.variants = name, ni, nj, kind, variants
        self.p, self.steps, self.nodal = p, steps, nodal

    @property
    def equations(self):
        if self.kind == "contact":  # two tubes, u_z = 0 everywhere
            return 2 * self.ni * self.nj
        return 2 * self.ni * self.nj - 2 * self.ni  # u_z fixed on both ends


CASES = {
    "tube-1e5": Case("tube-1e5", 317, 159, "elastic",
                     [("cholmod", ["--solver", "cholmod"]), ("eigen", ["--solver", "eigen"])], p=100.0),
    "tube-1e6": Case("tube-1e6", 708, 708, "elastic", [("cholmod", ["--solver", "cholmod"])], p=100.0,
                     nodal=True),
    "plastic-1e4": Case("plastic-1e4", 101, 51, "plastic",
                        [("return-mapping", ["--plasticity", "return-mapping"]),
                         ("tangent", ["--plasticity", "tangent"])], p=0.9 * P_LIMIT, steps=20),
    "plastic-1e5": Case("plastic-1e5", 317, 159, "plastic",
                        [("return-mapping", ["--plasticity", "return-mapping"])], p=0.9 * P_LIMIT, steps=20),
    "contact": Case("contact", ccx_contact.N + 1, ccx_contact.NZ + 1, "contact",
                    [("augmented-lagrangian", ["--element", "quad4"])], p=ccx_contact.P,
                    steps=ccx_contact.STEPS),
}


def die(msg):
    sys.stderr.write("run_vs_ccx: error: %s\n" % msg)
    sys.exit(2)


def child_env():
    env = dict(os.environ)
    for k in ("OMP_NUM_THREADS", "CCX_NPROC_EQUATION_SOLVER", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        env[k] = "1"
    return env


GNU_TIME = "/usr/bin/time" if os.access("/usr/bin/time", os.X_OK) else None


def run_measured(argv, cwd, log_path):
    """(exit code, wall seconds, peak RSS MiB) of one whole process; its output goes to log_path.

    The peak comes from GNU time (`/usr/bin/time -f %M`, Debian package `time`) when it is there: a child
    forked from this Python process inherits Python's resident set until it execs, and Linux keeps that in
    the child's ru_maxrss, so os.wait4 alone reports the script's own size (100+ MB after it has read a
    large CSV) for a small run. Without GNU time, os.wait4's figure is used and marked with '~'."""
    rss_path = log_path + ".rss"
    wrapped = [GNU_TIME, "-f", "%M", "-o", rss_path] + argv if GNU_TIME else argv
    with open(log_path, "wb") as log:
        t0 = time.perf_counter()
        proc = subprocess.Popen(wrapped, cwd=cwd, env=child_env(), stdin=subprocess.DEVNULL, stdout=log,
                                stderr=subprocess.STDOUT)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - t0
    proc.returncode = os.waitstatus_to_exitcode(status)
    rss = usage.ru_maxrss / 1024.0
    if GNU_TIME:
        try:
            rss = float(open(rss_path).read().split()[-1]) / 1024.0  # KiB; GNU time may prefix a status line
        except (OSError, ValueError, IndexError):
            pass
    return proc.returncode, wall, rss


# ---------------------------------------------------------------------------------- closed forms ------

def comparison_options(doc, cases, runs):
    """The options of a script that times `gapfe run` on these cases (bench/estimate_cost.py, limits.py,
    dolfinx_tube.py): --cases, --runs, --gapfe and --work; the caller adds its own and parses."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", default=cases)
    ap.add_argument("--runs", type=int, default=runs)
    ap.add_argument("--gapfe", default="build/bench/examples/gapfe")
    ap.add_argument("--work", default=None)
    return ap


def gapfe_and_work(args, prefix):
    """(the gapfe program's absolute path, the work folder: --work or a new temporary one, made) of parsed
    comparison_options."""
    work = args.work or tempfile.mkdtemp(prefix=prefix)
    os.makedirs(work, exist_ok=True)
    return os.path.abspath(args.gapfe), work


def case_decks(names, work):
    """For each case in the comma-separated `names`: (name, case, gapfe deck path, its first variant's
    options), the deck written into `work`."""
    for name in names.split(","):
        case = CASES[name]
        deck, _ = write_inputs(case, work)
        yield name, case, deck, case.variants[0][1]


def lame_bore(p):
    """Plane-strain Lame u_r(a) of the tube under bore pressure p."""
    d = B * B - A * A
    return (1 + NU) / E_MOD * ((1 - 2 * NU) * p * A * A / d * A + p * A * A * B * B / d / A)


def plastic_radius_closed_form(p):
    """rho from p = (2 / sqrt 3) sigma_y [ln(rho / a) + (b^2 - rho^2) / (2 b^2)] (docs/theory.md V6), bisection."""
    k = 2 / math.sqrt(3) * SIGMA_Y
    lo, hi = A, B
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if k * (math.log(mid / A) + (B * B - mid * mid) / (2 * B * B)) < p:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


# ------------------------------------------------------------------------------------------ inputs ------

def node(i, j, ni):  # 0-based grid indices; the deck's node(I, J) = (J - 1) ni + I, 1-based
    return j * ni + i + 1


def ids(lines, values, per_line=16):
    for k in range(0, len(values), per_line):
        lines.append(", ".join(str(v) for v in values[k:k + per_line]) + ",")


def write_inputs(case, work, ccx_fields=False):
    """The gapfe deck and the ccx input of `case` in `work`; returns (deck path, ccx job name)."""
    ni, nj = case.ni, case.nj
    if case.kind == "contact":
        deck_path, job = os.path.join(work, "contact.deck"), "ccx_contact"
        with open(deck_path, "w") as f:
            f.write(deckgen.two_tubes_deck(n=ccx_contact.N, nz=ccx_contact.NZ, steps=ccx_contact.STEPS,
                                           contact="augmented-lagrangian"))
        text, _ = ccx_contact.ccx_deck(CONTACT_SLOPE, 1e-3)
        with open(os.path.join(work, job + ".inp"), "w") as f:
            f.write(text)
        return deck_path, job
    if case.kind == "elastic":
        deck = deckgen.tube_deck(ni, nj, a=A, b=B, p=case.p, nodal=case.nodal)
    else:
        deck = deckgen.plastic_tube_deck(ni=ni, nj=nj, a=A, b=B, p=case.p, steps=case.steps, sigma_y=SIGMA_Y,
                                         hardening=HARDENING_C)
    deck_path = os.path.join(work, case.name + ".deck")
    with open(deck_path, "w") as f:
        f.write(deck)
    h = (B - A) / (ni - 1) * (nj - 1)
    nr, nz = ni - 1, nj - 1
    out = ["*HEADING", "run_vs_ccx %s" % case.name, "*NODE, NSET=NALL"]
    for j in range(nj):
        for i in range(ni):
            out.append("%d, %.17g, %.17g" % (node(i, j, ni), A + i * (B - A) / nr, j * h / nz))
    out.append("*ELEMENT, TYPE=CAX4, ELSET=EALL")
    for j in range(nz):
        for i in range(nr):
            out.append("%d, %d, %d, %d, %d" % (j * nr + i + 1, node(i, j, ni), node(i + 1, j, ni),
                                               node(i + 1, j + 1, ni), node(i, j + 1, ni)))
    out.append("*NSET, NSET=NZFIX")
    ids(out, [node(i, 0, ni) for i in range(ni)] + [node(i, nz, ni) for i in range(ni)])
    out.append("*NSET, NSET=NBORE")
    out.append("%d," % node(0, nz // 2, ni))
    out.append("*ELSET, ELSET=EBORE")
    ids(out, [j * nr + 1 for j in range(nz)])  # face 4 (nodes 4-1) of column 0 lies on r = a
    out.append("*ELSET, ELSET=EROW")
    ids(out, [(nz // 2) * nr + i + 1 for i in range(nr)])
    out += ["*MATERIAL, NAME=STEEL", "*ELASTIC", "%.17g, %.17g" % (E_MOD, NU)]
    if case.kind == "plastic":
        slope = 1.5 * HARDENING_C
        out += ["*PLASTIC, HARDENING=KINEMATIC", "%.17g, 0." % SIGMA_Y, "%.17g, 1." % (SIGMA_Y + slope)]
    out += ["*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL", "*BOUNDARY", "NZFIX, 2, 2, 0."]
    if case.kind == "plastic":
        out += ["*STEP, INC=1000", "*STATIC, DIRECT", "%.17g, 1." % (1.0 / case.steps)]
    else:
        out += ["*STEP", "*STATIC"]
    out += ["*DLOAD", "EBORE, P4, %.17g" % case.p, "*NODE PRINT, NSET=NBORE", "U"]
    if ccx_fields:
        out += ["*NODE FILE", "U", "*EL FILE", "S" + (", PEEQ" if case.kind == "plastic" else "")]
    if case.kind == "plastic":
        out += ["*EL PRINT, ELSET=EROW", "PEEQ"]
    out += ["*END STEP"]
    job = "ccx_" + case.name.replace("-", "_")
    with open(os.path.join(work, job + ".inp"), "w") as f:
        f.write("\n".join(out) + "\n")
    return deck_path, job


# ---------------------------------------------------------------------------------------- results ------

def ccx_results(case, work, job):
    """(bore u_r, plastic radius or None) from the last blocks of the .dat; for the contact case
    (contact pressure q, None)."""
    if case.kind == "contact":
        _, press = ccx_contact.parse_ccx_dat(os.path.join(work, job + ".dat"),
                                             ccx_contact.ccx_deck(CONTACT_SLOPE, 1e-3)[1])
        return (statistics.fmean(press) if press else None), None
    lines = open(os.path.join(work, job + ".dat"), errors="replace").read().splitlines()
    u, peeq, block = None, {}, None
    bore = node(0, (case.nj - 1) // 2, case.ni)
    for line in lines:
        s = line.strip()
        if s.startswith("displacements"):
            block = "u"
            continue
        if s.startswith("equivalent plastic strain"):
            block, peeq = "peeq", {}
            continue
        parts = s.split()
        if not parts:
            continue
        try:
            if block == "u" and int(parts[0]) == bore:
                u = float(parts[1])
            elif block == "peeq":
                peeq.setdefault(int(parts[0]), []).append(float(parts[2]))
        except (ValueError, IndexError):
            block = None
    radius = None
    if peeq:
        nr, row = case.ni - 1, (case.nj - 1) // 2
        plastic = [e for e, v in peeq.items() if max(v) > 0]
        if plastic:
            i = max(plastic) - row * nr - 1  # the outermost element of the row with PEEQ > 0
            radius = A + (i + 1) * (B - A) / nr  # its outer edge
    return u, radius


def gapfe_results(case, out):
    """(bore u_r, plastic radius or None) from the last increment of nodes.csv / elements.csv; for the
    contact case (contact pressure q, None) from gaps.csv (bench/ccx_contact.py: the f_n rows sum to
    the total contact force)."""
    if case.kind == "contact":
        _, gaps = ccx_contact.read_csv_last_increment(os.path.join(out, "gaps.csv"))
        return sum(float(r["f_n"]) for r in gaps) / (2 * math.pi * ccx_contact.B * ccx_contact.H), None
    bore = node(0, (case.nj - 1) // 2, case.ni)
    u = None
    with open(os.path.join(out, "nodes.csv")) as f:
        head = f.readline().strip().split(",")
        c_node, c_u = head.index("node"), head.index("u_r")
        for line in f:
            cells = line.split(",")
            if int(cells[c_node]) == bore:
                u = float(cells[c_u])  # the last increment's row wins
    radius = None
    if case.kind == "plastic":
        with open(os.path.join(out, "elements.csv")) as f:
            head = f.readline().strip().split(",")
            c_inc, c_r, c_q = head.index("inc"), head.index("r"), head.index("eqps")
            rows = [line.split(",") for line in f]
        last = max(float(c[c_inc]) for c in rows)
        outer = [float(c[c_r]) for c in rows if float(c[c_inc]) == last and float(c[c_q]) > 0]
        if outer:
            nr = case.ni - 1
            radius = max(outer) + 0.5 * (B - A) / nr  # outer edge of the outermost plastic cell
    return u, radius


def phases(log_path):
    for line in open(log_path, errors="replace"):
        if line.startswith("time [s]:"):
            return line[len("time [s]:"):].strip()
    return ""


# ------------------------------------------------------------------------------------------ driver ------

def machine():
    model = "?"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return "%s, %d cores, %s" % (model, os.cpu_count() or 0, platform.platform())


def fmt_ratio(x):
    return "%.1fx" % x if x < 10 else "**%.1fx**" % x


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], epilog=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", default="tube-1e5,plastic-1e4,plastic-1e5,tube-1e6,contact",
                    help="comma-separated, from: " + ", ".join(CASES))
    ap.add_argument("--pairs", type=int, default=3, help="interleaved rounds (ccx, gapfe variants); >= 1")
    ap.add_argument("--gapfe", default="build/bench/examples/gapfe", help="the gapfe command")
    ap.add_argument("--ccx", default="ccx")
    ap.add_argument("--work", default=None, help="work directory (default: a new temporary one, kept)")
    ap.add_argument("--write", default=None, help="put the table into this Markdown file between the markers")
    ap.add_argument("--ccx-output", choices=["print", "fields"], default="print",
                    help="what ccx writes in the elastic and plastic cases (see above)")
    args = ap.parse_args()
    names = [c for c in args.cases.split(",") if c]
    for c in names:
        if c not in CASES:
            die("unknown case '%s' (known: %s)" % (c, ", ".join(CASES)))
    if args.pairs < 1:
        die("--pairs must be >= 1")
    gapfe = os.path.abspath(args.gapfe)
    if not os.access(gapfe, os.X_OK):
        die("no gapfe command at %s (cmake --build build/bench --target gapfe_command)" % gapfe)
    work = args.work or tempfile.mkdtemp(prefix="run_vs_ccx_")
    os.makedirs(work, exist_ok=True)
    print("work directory:", work, flush=True)

    rows = []
    for name in names:
        case = CASES[name]
        deck, job = write_inputs(case, work, args.ccx_output == "fields")
        timing = {"ccx": []}
        timing.update({v: [] for v, _ in case.variants})
        answers, phase = {}, {}
        for k in range(args.pairs):
            log = os.path.join(work, job + ".log")
            os.sync()  # before every timed run: no write-back of an earlier run's files inside it
            code, wall, rss = run_measured([args.ccx, "-i", job], work, log)
            if code != 0 or "*ERROR" in open(log, errors="replace").read():
                die("ccx failed on %s (exit %d): see %s" % (name, code, log))
            timing["ccx"].append((wall, rss))
            answers["ccx"] = ccx_results(case, work, job)
            for v, extra in case.variants:
                out = os.path.join(work, "%s_%s" % (name, v))
                log = out + ".log"
                os.sync()
                code, wall, rss = run_measured([gapfe, "run", deck, "--out", out] + extra, work, log)
                if code != 0:
                    die("gapfe failed on %s, %s (exit %d): see %s" % (name, v, code, log))
                timing[v].append((wall, rss))
                answers[v] = gapfe_results(case, out)
                phase[v] = phases(log)
            print("  %s round %d: %s" % (name, k + 1, ", ".join(
                "%s %.2f s" % (key, t[-1][0]) for key, t in timing.items())), flush=True)
        med = {key: (statistics.median(w for w, _ in t), statistics.median(r for _, r in t))
               for key, t in timing.items()}
        rows.append((case, med, answers, phase))

    u_lame = {name: lame_bore(CASES[name].p) for name in names}
    q_contact = ccx_contact.closed_form()["q"]
    lines = ["| case | equations | code | wall s (median of %d) | peak MiB | ccx / gapfe time | ccx / gapfe memory "
             "| bore u_r (contact: q) | error | plastic radius (closed form) |" % args.pairs,
             "|---|---|---|---|---|---|---|---|---|---|"]
    for case, med, answers, phase in rows:
        ref_u = u_lame[case.name] if case.kind == "elastic" else q_contact if case.kind == "contact" else None
        rho = plastic_radius_closed_form(case.p) if case.kind == "plastic" else None
        for key in ["ccx"] + [v for v, _ in case.variants]:
            wall, rss = med[key]
            u, radius = answers[key]
            if ref_u is not None:
                err = "%.1e vs %s" % ((u - ref_u) / ref_u, "closed form" if case.kind == "contact" else "Lame") \
                    if u is not None else "?"
            else:
                uc = answers["ccx"][0]
                err = "%+.1e vs ccx" % ((u - uc) / uc) if key != "ccx" and u and uc else ""
            rad = ("%.2f (%.2f)" % (radius, rho) if radius else "") if rho else ""
            label = ("ccx 2.20 (CAX4%s)" % (", U and S fields" if args.ccx_output == "fields" or case.kind == "contact"
                                            else "") if key == "ccx" else "gapfe, " + key)
            ratio_t = "" if key == "ccx" else fmt_ratio(med["ccx"][0] / wall)
            ratio_m = "" if key == "ccx" else "%.1fx" % (med["ccx"][1] / rss)
            lines.append("| %s | %d | %s | %.3g | %.0f | %s | %s | %s | %s | %s |" % (
                case.name if key == "ccx" else "", case.equations, label, wall, rss, ratio_t, ratio_m,
                "%.6g" % u if u is not None else "?", err, rad))
    phase_lines = []
    for case, med, answers, phase in rows:
        for v, _ in case.variants:
            phase_lines.append("- %s, %s: %s" % (case.name, v, phase.get(v, "")))
    scaling = ""
    if "tube-1e5" in names and "tube-1e6" in names:
        a = next(m for c, m, _, _ in rows if c.name == "tube-1e5")["cholmod"][0]
        b = next(m for c, m, _, _ in rows if c.name == "tube-1e6")["cholmod"][0]
        scaling = "gapfe (CHOLMOD) from 1e5 to 1e6 equations: %.1fx the time." % (b / a)
    command = "python3 bench/run_vs_ccx.py " + " ".join(shlex.quote(a) for a in sys.argv[1:])
    text = "\n".join(lines)
    print()
    print(text)
    print("\n".join(phase_lines))
    if scaling:
        print(scaling)
    if args.write:
        block = ["<!-- run_vs_ccx: begin -->",
                 "```sh", command, "```", "",
                 "Machine: %s. Date: %s. `gapfe`: %s." % (
                     machine(), datetime.datetime.now().strftime("%Y-%m-%d %H:%M"), gapfe),
                 "", text, "", "gapfe's own phase timer (the log's `time [s]` line, last round):", ""]
        block += phase_lines
        if scaling:
            block += ["", scaling]
        block += ["<!-- run_vs_ccx: end -->"]
        doc = open(args.write).read()
        begin, end = doc.find("<!-- run_vs_ccx: begin -->"), doc.find("<!-- run_vs_ccx: end -->")
        if begin < 0 or end < begin:
            die("%s has no <!-- run_vs_ccx: begin --> ... <!-- run_vs_ccx: end --> markers" % args.write)
        doc = doc[:begin] + "\n".join(block) + doc[end + len("<!-- run_vs_ccx: end -->"):]
        with open(args.write, "w") as f:
            f.write(doc)
        print("table written to", args.write)


if __name__ == "__main__":
    main()
