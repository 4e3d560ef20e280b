#!/usr/bin/python3
"""Defaults a user can trust, through `gapfe run` (ctest `gapfe_defaults`; docs/plasticity.md):

  * A SAAC3 deck (the rate tube: 50 < r < 100, plane strain, Mises 180 with Prager hardening 500, card 0 with
    b = 0.05 and transition rate 1e-3 / s, bore pressure to 200 in 0.02 s, near its rate-enhanced limit)
    without a plasticity option runs return-mapping with its steps cut to time_tolerance, and lands within
    3% of the time-converged answer at 20 and 200 load steps. The reference is computed here: return-mapping
    in 8000 steps without time control (backward Euler is first order: 2000 steps are 0.2% off it). The
    seed's scheme (plasticity = tangent) at 20, 200 and 2000 steps is within 5% or warns: never silently off.
  * The rate-independent tube at 0.97 of its limit pressure (Mises 400, 100 < r < 200) by default within 1%
    of return-mapping in 400 steps at 20 steps; the seed's scheme there warns (6.6% low).
  * SAAC3 with gaps (bench/deckgen.py's two tubes: the rate tube inside an elastic one across a gap of 0.01,
    to 250 in 0.02 s) under each exact policy agrees with contact = saac on the closure load (the increment
    at which the first pair's gap reaches zero) and the final bore displacement to 1e-3, under both
    integrations.
  * Each law with history on each element it runs on, under each contact policy (the command's table, core/
    combinations.hpp): the plastic two tubes (rate-independent and rate-dependent, quad4 and quad4bbar,
    both integrations) under active-set and augmented-lagrangian agree with saac to 1e-3 on the bore
    displacement, and with friction (Coulomb under the exact policies, the seed's models under saac; a radial
    load, so no tangential force: these show the combination runs and changes nothing) with their
    frictionless answer; the contact driver's time control agrees with the plastic driver's (the rate tube
    inside two tubes whose gap never closes, and under contact = none, against the tube alone: 3e-3); the
    legacy quad with yield cards is refused with the library's reason in one line.

    /usr/bin/python3 tests/check_defaults.py build/release/examples/gapfe WORKDIR
"""
import csv
import pathlib
import shutil
import subprocess
import sys

root = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(root / "bench"))
import deckgen as dg  # noqa: E402
from checks import check, finish  # noqa: E402

gapfe = pathlib.Path(sys.argv[1]).resolve()
work = pathlib.Path(sys.argv[2]).resolve()
count = [0]


def run(text, *options, last=True):
    """`gapfe run` on the deck `text`: (exit code, log, warnings, folder)."""
    count[0] += 1
    folder = work / f"run{count[0]}"
    folder.mkdir()
    (folder / "input.deck").write_text(text)
    args = [gapfe, "run", folder / "input.deck", "--out", folder / "out", "--plot", "none", *options]
    done = subprocess.run(args + (["--output", "last"] if last else []), capture_output=True, text=True)
    warnings = [line for line in done.stderr.splitlines() if line.startswith("gapfe: warning:")]
    return done.returncode, done.stdout, warnings, folder / "out", done.stderr


def bore(out, a):
    """The largest |u_r| at the bore r = a at the last increment."""
    rows = list(csv.DictReader(open(out / "nodes.csv")))
    last = max(float(r["inc"]) for r in rows)
    return max(abs(float(r["u_r"])) for r in rows if float(r["inc"]) == last and abs(float(r["r"]) - a) < 1e-9)


def closure(out):
    """The load factor at which gap pair 1 closes: its open row with the gap at zero (a located event)."""
    rows = [r for r in csv.DictReader(open(out / "gaps.csv")) if r["pair"] == "1"]
    closed = [float(r["inc"]) for r in rows if r["status"] == "closed"]
    before = [float(r["inc"]) for r in rows if r["status"] == "open" and float(r["inc"]) < min(closed)]
    return max(before)


def without_plasticity_line(text):
    return "\n".join(line for line in text.splitlines() if not line.startswith("$ plasticity")) + "\n"


def rate_tube(steps, plasticity="return-mapping", extension=()):
    return dg.plastic_tube_deck(ni=21, a=50.0, b=100.0, p=200.0, steps=steps, sigma_y=180.0,
                                plasticity=plasticity, rate=(0.02 / steps, 0.05, 1e-3), hardening=500.0,
                                extension=extension)


def rate_tube_table():
    code, _, _, out, err = run(rate_tube(8000, extension=("time_tolerance = 0",)))
    check(code == 0, f"rate tube reference: exit {code} ({err[:300]})")
    reference = bore(out, 50.0)
    print(f"rate tube: reference bore u_r {reference:.6g} (return-mapping, 8000 steps)")
    for steps in (20, 200):
        code, log, warnings, out, err = run(without_plasticity_line(rate_tube(steps)))
        u = bore(out, 50.0)
        print(f"  default, {steps} steps: {u:.6g} ({u / reference - 1:+.4f})")
        check(code == 0 and not warnings, f"rate tube default {steps}: exit {code}, warnings {warnings}")
        check(abs(u / reference - 1) <= 0.03, f"rate tube default {steps}: {u} vs {reference} (3%)")
        check("integration: return-mapping (backward Euler" in log, f"rate tube default {steps}: the log names it")
    for steps in (20, 200, 2000):
        code, log, warnings, out, err = run(rate_tube(steps, "tangent"))
        u = bore(out, 50.0)
        off = abs(u / reference - 1)
        print(f"  tangent, {steps} steps: {u:.6g} ({u / reference - 1:+.4f}), warnings {len(warnings)}")
        check(code == 0, f"rate tube tangent {steps}: exit {code} ({err[:300]})")
        check(off <= 0.05 or any("plasticity = tangent" in w for w in warnings),
              f"rate tube tangent {steps}: {off:.3g} off without a warning")
        check("for reproducing legacy results" in log, f"rate tube tangent {steps}: the log names the seed's scheme")


def near_limit():
    limit = 2 / 3 ** 0.5 * 400.0 * 0.6931471805599453
    deck = lambda steps, plasticity: dg.plastic_tube_deck(ni=41, p=0.97 * limit, steps=steps, plasticity=plasticity)
    code, _, _, out, err = run(deck(400, "return-mapping"))
    check(code == 0, f"near limit reference: exit {code} ({err[:300]})")
    reference = bore(out, 100.0)
    code, _, warnings, out, err = run(without_plasticity_line(deck(20, "tangent")))
    u = bore(out, 100.0)
    print(f"near limit: reference {reference:.6g} (400 steps); default 20 steps {u:.6g} ({u / reference - 1:+.4f})")
    check(code == 0 and not warnings and abs(u / reference - 1) <= 0.01, f"near limit default: {u} vs {reference}")
    code, _, warnings, out, err = run(deck(20, "tangent"))
    u = bore(out, 100.0)
    print(f"  tangent 20 steps {u:.6g} ({u / reference - 1:+.4f}), warnings {len(warnings)}")
    check(abs(u / reference - 1) <= 0.05 or any("plasticity = tangent" in w for w in warnings),
          f"near limit tangent: {u} vs {reference} without a warning")


def two_tubes(contact, steps=20, rate=True, extension=()):
    return dg.two_tubes_deck(n=10, nz=1, a=50.0, b=100.0, gap=0.01, c=150.0, p=250.0 if rate else 230.0,
                             steps=steps, contact=contact, extension=extension, sigma_y=180.0,
                             hardening=500.0, rate=(0.02 / steps, 0.05, 1e-3) if rate else None)


def saac3_gaps():
    for plasticity in ("return-mapping", "tangent"):
        answers = {}
        for contact in ("saac", "active-set", "augmented-lagrangian"):
            code, _, _, out, err = run(two_tubes(contact, extension=(f"plasticity = {plasticity}",)), last=False)
            if not check(code == 0, f"saac3 gaps {plasticity} {contact}: exit {code} ({err[:300]})"):
                continue
            answers[contact] = (closure(out), bore(out, 50.0))
        print(f"saac3 with gaps, {plasticity}: (closure load, bore u_r) {answers}")
        if "saac" not in answers:
            continue
        for contact, (t, u) in answers.items():
            t0, u0 = answers["saac"]
            check(abs(t / t0 - 1) <= 1e-3, f"saac3 gaps {plasticity} {contact}: closure at {t} vs saac {t0}")
            check(abs(u / u0 - 1) <= 1e-3, f"saac3 gaps {plasticity} {contact}: bore {u} vs saac {u0}")


def every_combination():
    for rate in (False, True):
        for element in ("quad4", "quad4bbar"):
            for plasticity in ("tangent", "return-mapping"):
                where = f"{'rate' if rate else 'plastic'} {element} {plasticity}"
                frictions = [("saac", "extended"), ("saac", "proportional")]
                if plasticity == "return-mapping":
                    frictions += [("active-set", "coulomb"), ("augmented-lagrangian", "coulomb")]
                answers = {}
                for contact, slip in [(c, None) for c in ("saac", "active-set", "augmented-lagrangian")] + frictions:
                    more = (f"element = {element}", f"plasticity = {plasticity}")
                    more += (f"friction = 0.2", f"slip = {slip}") if slip else ()
                    code, _, _, out, err = run(two_tubes(contact, rate=rate, extension=more))
                    if check(code == 0, f"{where} {contact} {slip}: exit {code} ({err[:300]})"):
                        answers[(contact, slip)] = bore(out, 50.0)
                base = answers.get(("saac", None))
                if base is None:
                    continue
                worst = max(abs(u / base - 1) for u in answers.values())
                print(f"{where}: {len(answers)} runs, bore u_r {base:.6g}, largest difference {worst:.2g}")
                for key, u in answers.items():
                    check(abs(u / base - 1) <= 1e-3, f"{where} {key}: bore {u} vs saac {base}")
    # The contact driver's time control against the plastic driver's: the rate tube inside the two tubes with
    # a gap that never closes (30), and with the gaps soft (contact = none), against the same tube alone (the
    # same cells, loads and law); both cut to time_tolerance, so they agree to about its effect (3e-3).
    alone = dg.plastic_tube_deck(ni=11, a=50.0, b=100.0, p=200.0, steps=20, sigma_y=180.0, hardening=500.0,
                                 rate=(0.001, 0.05, 1e-3))
    code, _, _, out, err = run(without_plasticity_line(alone))
    if check(code == 0, f"rate tube alone: exit {code} ({err[:300]})"):
        u_alone = bore(out, 50.0)
        tubes = lambda gap, contact: dg.two_tubes_deck(n=10, nz=1, a=50.0, b=100.0, gap=gap, c=100.0 + gap + 50.0,
                                                       p=200.0, steps=20, contact=contact, sigma_y=180.0,
                                                       hardening=500.0, rate=(0.001, 0.05, 1e-3))
        for name, text in (("gap never closing", tubes(30.0, "active-set")), ("contact = none", tubes(0.01, "none"))):
            code, _, warnings, out, err = run(text)
            if check(code == 0 and not warnings, f"{name}: exit {code}, warnings {warnings} ({err[:300]})"):
                u = bore(out, 50.0)
                print(f"{name}: bore u_r {u:.6g} against the tube alone {u_alone:.6g} ({u / u_alone - 1:+.2g})")
                check(abs(u / u_alone - 1) <= 3e-3, f"{name}: bore {u} vs the tube alone {u_alone}")
    code, _, _, out, err = run(two_tubes("active-set", rate=False, extension=("element = legacy",)))
    lines = err.strip().splitlines()
    check(code == 1 and len(lines) == 1 and "condensed centre" in err and not (out / "nodes.csv").exists(),
          f"legacy with yield cards: exit {code}, {err!r}")


def main():
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    rate_tube_table()
    near_limit()
    saac3_gaps()
    every_combination()
    finish()


main()
