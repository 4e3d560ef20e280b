#!/usr/bin/python3
"""Friction under combined loading through `gapfe run` (ctest `friction_family`): a hub pressed onto a hollow
shaft while it is pushed along it, in every order, against closed forms.

One table of load programs (PROGRAMS) becomes scene files on a mesh Gmsh made (tests/data/scenes/
press_fit.msh: a structured shaft, an unstructured hub of triangles) and, for the programs a deck can say (its
BC values are the same increment in every step), card decks (bench/deckgen.py's press_fit_deck on the I-J
grid, with the legacy quadrilateral and with element = quad4bbar). Each runs with 1, 5 and 40 load steps per
phase, under contact = active-set and augmented-lagrangian, with events = locate and step-end, and must end on its closed form (mm, N, MPa; E = 200000, nu = 0, so the
radial problem is Lame's and does not feel the push):

    q_c = w E (c^2 - b^2) / (2 b c^2)                  the outer pressure that closes the gap w
    p   = (q - q_c) c^2 (b^2 - a^2) / (b^2 (c^2 - a^2))  the contact pressure (one compound tube a..c)
    N   = p 2 pi b L                                   the normal force the pairs carry (sum of f_n)
    F   = mu N                                         the friction force when every pair slips

  * sum f_n (gaps.csv, the last increment) within 1% of N;
  * a program that ends sliding: every pair slips, sum f_t = mu sum f_n (1e-6: Coulomb's cone, per pair to
    the friction Newton's tolerance), and the reaction of the driven face (history.csv) is F against the
    slide within 1%; with the twist, the axial force F cos(alpha) and the torque F (b + w) sin(alpha), alpha
    the angle of the slide's (push, twist) direction;
  * a program that pushes only while the gap is open: no pair slides after it closes, so sum f_t and the
    push force stay below 1% of F (on the unstructured hub the pressure alone gives tangential forces of
    about 2e-3 F: the triangles' axial give under a radial load, zero as the mesh is refined);
  * history.csv's cone_ratio (the largest |f_t| / (mu f_n) of a closed pair) never above 1 + 1e-6;
  * the same for gap_penalty = 10 to 1e6 on the deck of pressure and push rising together;
  * locate and step-end, where both end with every pair slipping, agree on sum f_n, sum f_t and the
    reactions to 1e-6 (a stuck pair's force is its history, which step-end sees to O(step)).

    /usr/bin/python3 tests/check_friction_family.py build/release/examples/gapfe WORKDIR
"""
import csv
import math
import pathlib
import re
import shutil
import subprocess
import sys

root = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(root / "bench"))
import deckgen  # noqa: E402  (the decks' one writer)
from checks import check, finish  # noqa: E402  (tests/checks.py: the shared tally)

gapfe = pathlib.Path(sys.argv[1]).resolve()
work = pathlib.Path(sys.argv[2]).resolve()

A, B, W, C, L, E, Q, MU = 12.5, 25.0, 0.001, 50.0, 50.0, 200000.0, 75.0, 0.2
PUSH, TWIST = 0.04, 0.04  # [mm] per phase that moves: well past the slide that takes the fit from stick to slip
N = deckgen.press_fit_normal_force(A, B, W, C, L, Q, E)
F = MU * N

# Each phase moves the loads linearly to its (pressure, push, twist) fractions of (Q, PUSH, TWIST); push > 0
# moves the hub down the shaft. `drive`: "ends" holds the shaft's bottom and drives the hub's top face (the
# push-out test); "all" holds every shaft node and drives every hub node in z and theta (a uniform slide,
# whose direction the closed form needs). `end`: the direction (push, twist) of the last slide, or None where
# nothing slides once the gap is closed. `deck`: a deck can say it (pressure and push rising together).
PROGRAMS = {
    "together": dict(phases=[(1, 1, 0)], drive="ends", end=(1, 0), deck=True),
    "pressure_first": dict(phases=[(1, 0, 0), (1, 1, 0)], drive="ends", end=(1, 0)),
    "push_first": dict(phases=[(0, 1, 0), (1, 1, 0)], drive="ends", end=None),
    "reversed": dict(phases=[(1, 0, 0), (1, 1, 0), (1, -1, 0)], drive="ends", end=(-1, 0)),
    "cyclic": dict(phases=[(1, 0, 0), (1, 1, 0), (1, -1, 0), (1, 1, 0), (1, -1, 0)], drive="ends", end=(-1, 0)),
    "push_and_twist": dict(phases=[(1, 1, 1)], drive="all", end=(1, 1), deck=True),
}
STEPS = (1, 5, 40)  # load steps per phase
POLICIES = ("active-set", "augmented-lagrangian")
EVENTS = ("locate", "step-end")


def amplitude(program, k, steps):
    """The scene's amplitude of load component k: the phase ends' fractions at their whole steps."""
    points = [[0, 0.0]] + [[steps * (i + 1), float(phase[k])] for i, phase in enumerate(program["phases"])]
    return "[" + ", ".join(f"[{s}, {v}]" for s, v in points) + "]"


def scene(program, steps, policy, events, slip="coulomb"):
    phases = len(program["phases"])
    twist = any(phase[2] for phase in program["phases"])
    held, driven = ("shaft", "hub") if program["drive"] == "all" else ("shaft_bottom", "hub_top")
    motion = f"z = {-PUSH}" + (f", theta = {TWIST}" if twist else "")
    return f"""title = "PUSH WHILE PRESSING: {program['name']}, {steps} step(s) per phase"
[mesh]
file = "{root / 'tests/data/scenes/press_fit.msh'}"
[steps]
count = {steps * phases}
[materials.steel]
surfaces = ["shaft", "hub"]
E = {E}
nu = 0.0
[materials.gap]
E = {E * 1e-9}
nu = 0.0
[[boundary]]
groups = "{held}"
fix = {'["z", "theta"]' if twist else '"z"'}
[[boundary]]
groups = "{driven}"
displacement = {{ {motion} }}
amplitude = {amplitude(program, 1, steps)}
[[load]]
curves = "hub_outside"
pressure = {Q}
amplitude = {amplitude(program, 0, steps)}
[[contact]]
faces = ["shaft_face", "hub_face"]
soft = "gap"
policy = "{policy}"
events = "{events}"
friction = {MU}
slip = "{slip}"
"""


def deck(program, steps, policy, events, slip="coulomb"):
    twist = any(phase[2] for phase in program["phases"])
    return deckgen.press_fit_deck(push=PUSH / steps, steps=steps, mu=MU, contact=policy, events=events, ramp=True,
                                  twist=TWIST / steps if twist else None, slip=slip)


def table(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def run(name, text, suffix, *extra):
    out = work / name
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    source = out / ("input" + suffix)
    source.write_text(text)
    done = subprocess.run([gapfe, "run", source, "--out", out / "result", "--plot", "none", *extra],
                          capture_output=True, text=True)
    check(done.returncode == 0, f"{name}: gapfe run exits 0 ({done.stderr.strip()[-400:]})")
    check(done.stderr == "", f"{name}: no warning ({done.stderr.strip()[-400:]})")
    # The log's contact line: no pair Newton stopped short of its tolerance, no interval halved.
    stalls = re.search(r"(\d+) stalled below 1e-4", done.stdout)
    check(stalls is not None and stalls.group(1) == "0" and "intervals halved" not in done.stdout,
          f"{name}: the friction Newton converged in every solve, no interval halved "
          f"({(stalls.group(0) if stalls else 'no friction line')})")
    return out / "result" if done.returncode == 0 else None


def cone_from_gaps(rows):
    """The largest |f_t| / (mu f_n) of a closed pair over gaps.csv's rows (infinity for friction in tension)."""
    worst = 0.0
    for g in rows:
        f_t, f_n = float(g["f_t"]), float(g["f_n"])
        if g["status"] != "open" and f_t > 0:
            worst = max(worst, f_t / (MU * f_n) if f_n > 0 else math.inf)
    return worst


def end_state(out, program):
    """The last increment: sum f_n, sum f_t, statuses, the driven face's axial reaction and torque."""
    gaps = table(out / "gaps.csv")
    last = [g for g in gaps if g["inc"] == gaps[-1]["inc"]]
    history = table(out / "history.csv") if (out / "history.csv").exists() else None
    reactions = table(out / "reactions.csv")
    final = [r for r in reactions if r["inc"] == reactions[-1]["inc"]]
    hub = [r for r in final if float(r["r"]) > B + W / 2]
    return dict(fn=sum(float(g["f_n"]) for g in last), ft=sum(float(g["f_t"]) for g in last),
                status=[g["status"] for g in last], axial=sum(float(r["R_z"]) for r in hub),
                torque=sum(float(r["R_t"]) * float(r["r"]) for r in hub), cone=cone_from_gaps(gaps),
                history_cone=max(float(h.get("cone_ratio", "nan")) for h in history) if history else None)


def expect(name, s, program):
    check(abs(s["fn"] / N - 1) < 0.01, f"{name}: sum f_n {s['fn']:.6g} within 1% of N = {N:.6g}")
    check(s["cone"] <= 1 + 1e-6, f"{name}: largest |f_t| / (mu f_n) of gaps.csv {s['cone']:.9g} <= 1 + 1e-6")
    if s["history_cone"] is not None:  # a run of more than one step: history.csv's column says the same
        check(s["history_cone"] == s["cone"], f"{name}: history.csv's cone_ratio {s['history_cone']:.9g} is "
              f"gaps.csv's largest |f_t| / (mu f_n), {s['cone']:.9g}")
    if program["end"] is None:
        check(s["ft"] < 0.01 * F, f"{name}: sum f_t {s['ft']:.3g} below 1% of F (nothing slides once closed)")
        check(abs(s["axial"]) < 0.01 * F, f"{name}: push force {s['axial']:.3g} below 1% of F")
        return
    check(all(x == "slip" for x in s["status"]), f"{name}: every pair slips at the end ({set(s['status'])})")
    check(abs(s["ft"] / (MU * s["fn"]) - 1) < 1e-6, f"{name}: sum f_t {s['ft']:.9g} = mu sum f_n {MU * s['fn']:.9g}")
    push, twist = program["end"]
    alpha = math.atan2(twist * TWIST, push * PUSH)
    # The friction on the hub opposes its slide, and the driven face's reaction balances the friction: it acts
    # along the slide, -z for the push down and +theta for the twist.
    axial, torque = -F * math.cos(alpha), F * (B + W) * math.sin(alpha)
    check(abs(s["axial"] - axial) < 0.01 * F, f"{name}: axial reaction {s['axial']:.6g} within 1% of {axial:.6g}")
    if twist:
        check(abs(s["torque"] - torque) < 0.01 * F * B,
              f"{name}: torque {s['torque']:.6g} within 1% of {torque:.6g}")


def coulomb_family():
    """Item by item the table above; returns the number of runs."""
    runs = 0
    for name, program in PROGRAMS.items():
        program["name"] = name
        # The scene on Gmsh's mesh runs the default element (the legacy quad, Tri3 for the triangles); the decks
        # run it and Quad4 with B-bar.
        inputs = [("scene", scene, ".toml", ())]
        if program.get("deck"):
            inputs += [("deck", deck, ".deck", ()), ("deck_quad4bbar", deck, ".deck", ("--element", "quad4bbar"))]
        for kind, make, suffix, extra in inputs:
            for steps in STEPS:
                for policy in POLICIES:
                    ends = {}
                    for events in EVENTS:
                        label = f"{kind}_{name}_{steps}_{policy}_{events}"
                        out = run(label, make(program, steps, policy, events), suffix, *extra)
                        runs += 1
                        if out is None:
                            continue
                        ends[events] = end_state(out, program)
                        expect(label, ends[events], program)
                    # Where both end sliding, the cone sets every pair's force, whatever the path: the two
                    # agree. A stuck pair's force is its history (step-end closes it at an interpolated point).
                    slipping = [all(x == "slip" for x in e["status"]) for e in ends.values()]
                    if len(ends) == 2 and all(slipping):
                        one, other = ends["locate"], ends["step-end"]
                        for key, scale in (("fn", N), ("ft", F), ("axial", F), ("torque", F * B)):
                            check(abs(one[key] - other[key]) <= 1e-6 * scale,
                                  f"{kind}_{name}_{steps}_{policy}: locate and step-end agree on {key} to 1e-6 "
                                  f"({one[key]:.12g}, {other[key]:.12g})")

    # Every penalty factor from 10 to 1e6 (active-set's constraint error is about 1 / factor of the adjacent
    # give: 2e-3 of N at 10), on the deck that closes while it slides, 40 steps.
    for policy in POLICIES:
        for penalty in (10, 100, 1e3, 1e4, 1e5, 1e6):
            for events in EVENTS:
                label = f"deck_together_40_{policy}_{events}_penalty_{penalty:g}"
                out = run(label, deck(PROGRAMS["together"], 40, policy, events), ".deck", "--set",
                          f"gap_penalty={penalty:g}")
                runs += 1
                if out is not None:
                    expect(label, end_state(out, PROGRAMS["together"]), PROGRAMS["together"])
    return runs


def by_increment(rows, key):
    """{inc: {key value: row}} in the order of the increments."""
    out = {}
    for r in rows:
        out.setdefault(r["inc"], {})[r[key]] = r
    return out


def seed_rules(name, out, model, mesh):
    """The seed's friction model recomputed by hand from the run's tables, pair by pair and increment by
    increment, against gaps.csv. Both models are a tangential spring on the pair's slide s = (T . d, u_t,b -
    u_t,a), d = u_b - u_a, from where the pair closed (the accepted increment before its first closed row):
    t_n = t_(n-1) - k_t (s_n - s_(n-1)), f_t = |t|. proportional (SAACFR, Eq. 12-13): k_t = mu k. extended
    (section 3.2): k_t = k while the pair sticks, 0 while it slips (the force it has is kept); it sticks in the
    increment after it closes, then as long as, at the increment before, the mean stress of the structural
    cells around it (elements.csv, the cells with node a or b) has sigma_NN < 0 and a resultant shear
    sqrt(tau_NT^2 + tau_NS^2) below mu |sigma_NN|. k, the pair's normal penalty, from two closed increments:
    k = -(f_n' - f_n) / (g' - g). A pair opens (SAAC, section 2.2) only after an increment in tension. Returns
    the largest f_t / (mu f_n) of a closed pair."""
    pair_rows = table(out / "gaps.csv")
    for r in pair_rows:
        r["pair_key"] = f"{r['element']}/{r['pair']}"
    gaps = by_increment(pair_rows, "pair_key")
    nodes, elements = (by_increment(table(out / f), k) for f, k in (("nodes.csv", "node"), ("elements.csv", "element")))
    incs = list(gaps)
    cells = [(c["material"], {c[k] for k in ("n1", "n2", "n3", "n4") if c.get(k)}) for c in mesh]
    gap_material = cells[int(pair_rows[0]["element"]) - 1][0]  # the gap elements' material
    mismatches, checked = [], 0
    for key in gaps[incs[0]]:
        first = gaps[incs[0]][key]
        a, b = first["node_a"], first["node_b"]
        xa, xb = (nodes[incs[0]][n] for n in (a, b))
        n = (float(xb["r"]) - float(xa["r"]), float(xb["z"]) - float(xa["z"]))
        size = math.hypot(*n)
        n = (n[0] / size, n[1] / size)
        tangent = (-n[1], n[0])
        around = [str(e + 1) for e, (material, corners) in enumerate(cells)
                  if material != gap_material and corners & {a, b}]

        def slide(inc):
            ua, ub = nodes[inc][a], nodes[inc][b]
            d = [float(ub[c]) - float(ua[c]) for c in ("u_r", "u_z", "u_t")]
            return (tangent[0] * d[0] + tangent[1] * d[1], d[2])

        def sticks(inc):
            mean = [sum(float(elements[inc][e][c]) for e in around) / len(around)
                    for c in ("s_rr", "s_zz", "s_rz", "s_rt", "s_zt")]
            rr, zz, rz, rt, zt = mean
            normal = n[0] * n[0] * rr + 2 * n[0] * n[1] * rz + n[1] * n[1] * zz
            shear_t = tangent[0] * (rr * n[0] + rz * n[1]) + tangent[1] * (rz * n[0] + zz * n[1])
            shear_s = rt * n[0] + zt * n[1]
            return normal < 0 and math.hypot(shear_t, shear_s) < MU * -normal

        k, t = None, None
        for i in range(1, len(incs)):
            row, before = gaps[incs[i]][key], gaps[incs[i - 1]][key]
            if row["status"] == "open":
                if before["status"] != "open" and not float(before["f_n"]) < 0:  # SAAC opens a pair in tension
                    mismatches.append(f"{incs[i]} pair {key}: opened after f_n = {before['f_n']}, not tension")
                t = None
                continue
            if before["status"] != "open" and k is None and float(row["gap"]) != float(before["gap"]):
                k = -(float(row["f_n"]) - float(before["f_n"])) / (float(row["gap"]) - float(before["gap"]))
            fresh = before["status"] == "open"
            if model == "extended":
                expected = "stick" if fresh or sticks(incs[i - 1]) else "slip"
                if row["status"] != expected:
                    mismatches.append(f"{incs[i]} pair {key}: {row['status']}, the rule says {expected}")
            t = [0.0, 0.0] if fresh else t
            spring = None if k is None else MU * k if model == "proportional" else k if row["status"] == "stick" else 0
            s1, s0 = slide(incs[i]), slide(incs[i - 1])
            if spring is None:  # k not known yet: take the row's force as the start (its size, its slide's sign)
                t = [-math.copysign(float(row["f_t"]), s1[0] - s0[0]), 0.0]
            else:
                t = [t[j] - spring * (s1[j] - s0[j]) for j in range(2)]
                checked += 1
                f_t, f_n = float(row["f_t"]), float(row["f_n"])
                if abs(math.hypot(*t) - f_t) > 1e-6 * (f_t + MU * abs(f_n)):
                    mismatches.append(f"{incs[i]} pair {key}: f_t {f_t:.9g}, the rule gives {math.hypot(*t):.9g}")

    check(checked > 0 and not mismatches,
          f"{name}: every closed pair's f_t and status follow the seed's {model} rule ({checked} increments; "
          f"{len(mismatches)} differ: {mismatches[:3]})")
    return cone_from_gaps(pair_rows)


def seed_models():
    """The seed's two models on the push-while-pressing fit (pressure and push rising together), as a deck and
    as a Gmsh scene: their rules hold (seed_rules), history.csv's cone_ratio is the rows' largest f_t / (mu
    f_n), and the run warns when it passes 1.1, naming the pair and its nodes; a push that stays short of
    slip keeps both inside the cone, without a warning."""
    program = dict(PROGRAMS["together"], name="together")
    runs = 0
    for kind, make, suffix in (("scene", scene, ".toml"), ("deck", deck, ".deck")):
        for model in ("extended", "proportional"):
            for label, push_scale in (("pushed", 1.0), ("nudged", 1e-3)):
                name = f"seed_{kind}_{model}_{label}"
                text = make(program, 40, "saac", "locate", model)
                if push_scale != 1.0:  # the same run with a push 1000 times smaller
                    text = text.replace(f"z = {-PUSH}", f"z = {-PUSH * push_scale}") if kind == "scene" else \
                        deckgen.press_fit_deck(push=PUSH * push_scale / 40, steps=40, mu=MU, contact="saac",
                                               ramp=True, slip=model)
                out_dir = work / name
                shutil.rmtree(out_dir, ignore_errors=True)
                out_dir.mkdir(parents=True)
                source = out_dir / ("input" + suffix)
                source.write_text(text)
                out = out_dir / "result"
                done = subprocess.run([gapfe, "run", source, "--out", out, "--quiet", "--plot", "none"],
                                      capture_output=True, text=True)
                runs += 1
                check(done.returncode == 0, f"{name}: gapfe run exits 0 ({done.stderr.strip()[-300:]})")
                if done.returncode:
                    continue
                subprocess.run([gapfe, "mesh", source, "--out", out_dir / "mesh", "--quiet"], check=True)
                try:
                    worst = seed_rules(name, out, model, table(out_dir / "mesh" / "mesh_elements.csv"))
                except KeyError as missing:  # a column the tables must have (node_a, node_b, cone_ratio)
                    check(False, f"{name}: the tables have a column {missing}")
                    continue
                cone = max(float(h.get("cone_ratio", "nan")) for h in table(out / "history.csv"))
                check(cone == worst, f"{name}: history.csv's cone_ratio {cone:.9g} is the "
                      f"largest f_t / (mu f_n) of gaps.csv, {worst:.9g}")
                warned = "outside Coulomb's cone" in done.stderr
                check(warned == (cone > 1.1), f"{name}: warns ({warned}) exactly when cone_ratio {cone:.3g} > 1.1")
                if label == "nudged":
                    check(cone < 1 and not warned, f"{name}: inside the cone ({cone:.3g}) without a warning")
                if warned:
                    check("gap element" in done.stderr and "nodes" in done.stderr and "slip = coulomb" in done.stderr,
                          f"{name}: the warning names the pair, its nodes and slip = coulomb ({done.stderr.strip()})")
                print(f"{name}: largest f_t / (mu f_n) {cone:.3g}")
    return runs


work.mkdir(parents=True, exist_ok=True)
runs = coulomb_family() + seed_models()
finish(f"{runs} runs, ")
