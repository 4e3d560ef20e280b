#!/usr/bin/python3
"""Every warning `gapfe run` prints (docs/checks.md lists them), through the command (ctest `gapfe_warnings`):
each fires on a model that triggers it, and stays silent on its neighbour, the same model with the trigger
just removed. The models are tests/check_matrix.py's tube and fit (its deck writer) and bench/deckgen.py's
plastic tube; the friction cone's warning is checked both ways in tests/check_friction_family.py.

    /usr/bin/python3 tests/check_warnings.py build/release/examples/gapfe WORKDIR
"""
import os
import pathlib
import shutil
import subprocess
import sys

root = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(root / "bench"))
import deckgen as dg  # noqa: E402
import check_matrix as matrix  # noqa: E402  (the tube and the fit as decks, and its run())
from checks import check, finish  # noqa: E402

work = pathlib.Path(sys.argv[2]).resolve()


def case(**values):
    c = {"load": "pressure", "element": "legacy", "dofs": 2, "contact": None, "plastic": False, "name": "warning"}
    c.update(values)
    c["policy"] = c["contact"]
    return c


def run(name, text, *options):
    """`gapfe run` on the deck `text` (with the command line's `options`); its error stream's warnings."""
    folder = work / name
    folder.mkdir()
    (folder / "input.deck").write_text(text)
    done = matrix.run(folder / "input.deck", folder / "out", 2, *options)
    check(done.returncode == 0, f"{name}: exit {done.returncode} ({done.stderr.strip()[:300]})")
    return [line for line in done.stderr.splitlines() if line.startswith("gapfe: warning:")]


def fires(name, warnings, words):
    check(len(warnings) == 1 and words in warnings[0], f"{name}: one warning saying '{words}' ({warnings})")


def silent(name, warnings):
    check(not warnings, f"{name}: no warning ({warnings})")


def locking():
    """element = quad4 with nu above 0.49: fires at 0.4999 and 0.49999999, not at 0.49, on quad4bbar, or on
    quad8's quadrilaterals (their linear pressure does not lock; tests/check_quadratic.py has the triangles)."""
    for nu, element, warned in ((0.4999, "quad4", True), (0.49999999, "quad4", True), (0.49, "quad4", False),
                                (0.4999, "quad4bbar", False), (0.4999, "legacy", False), (0.4999, "quad8", False)):
        matrix.NU = nu
        name = f"locking nu {nu} {element}"
        warnings = run(name.replace(" ", "_"), matrix.deck(case(element=element), matrix.Body(False)))
        (fires(name, warnings, "bilinear quad locks") if warned else silent(name, warnings))
    matrix.NU = 0.3


def ill_conditioned():
    """A residual |K u - f| / |f| above 1e-4: the fit closed under a penalty of 1e11 x the adjacent stiffness
    (saac and active-set; measured 5.6e-4 and 2.1e-3, and 1.2e-4 under active-set at 1e10); silent at the
    policies' defaults (1e2 and 1e4)."""
    text = lambda policy: matrix.deck(case(contact=policy), matrix.Body(True))
    for policy in matrix.POLICIES[:2]:
        name = f"penalty 1e11 {policy}"
        fires(name, run(name.replace(" ", "_"), text(policy), "--set", "gap_penalty=1e11"), "ill-conditioned")
        name = f"penalty default {policy}"
        silent(name, run(name.replace(" ", "_"), text(policy)))


def out_of_balance():
    """Global equilibrium off by more than 1e-8: the seed's tangent scheme (one solve per increment) on a tube
    held at its bottom only, its bore pressed to 150 (past first yield, Mises 250 with Prager 2000) in 100
    steps, residual below 1e-2 and the balance 7.7e-4 off; silent with return-mapping. Pulled by ring forces
    past yield in two steps (7.5% off), the same scheme leaves a residual above 1e-2: one warning, the
    residual's, and the balance adds none; silent below yield."""
    bore = case(load="bore_pressure", element="quad4bbar", plastic=True)
    matrix.STEPS, matrix.P_BORE = 100, 150.0
    for plasticity, warned in (("tangent", True), ("return-mapping", False)):
        name = f"balance bore {plasticity}"
        warnings = run(name.replace(" ", "_"), matrix.deck(bore, matrix.Body(False)), "--set",
                       f"plasticity={plasticity}")
        if warned:
            fires(name, warnings, "out of global equilibrium")
            check("return-mapping" in warnings[0], f"{name}: the warning suggests return-mapping ({warnings})")
        else:
            silent(name, warnings)
    matrix.STEPS, matrix.P_BORE = 2, 100.0
    for force, words in ((60000.0, "was accepted with a relative residual"), (20000.0, None)):
        matrix.FORCE = force
        text = matrix.deck(case(load="nodal_force", element="quad4bbar", plastic=True), matrix.Body(False))
        name = f"balance pulled {force:g}"
        warnings = run(name.replace(" ", "_"), text, "--set", "plasticity=tangent")
        (fires(name, warnings, words) if words else silent(name, warnings))
    matrix.FORCE = 2000.0


def seed_residual():
    """The seed's one-solve plasticity past a relative residual of 1e-2: the SAAC3 tube of docs/checks.md
    (50 < r < 100, Mises 180, Prager 500, b = 0.05, transition rate 1e-3, bore pressure 200 in 0.02 s) in
    20 steps, and the rate-independent tube at 0.97 of its limit pressure in 20 steps; silent in 200 steps
    (residual 0.0042, 0.3% off) and with return-mapping. One warning: the global balance's is not added."""
    saac3 = lambda steps, plasticity: dg.plastic_tube_deck(ni=21, a=50.0, b=100.0, p=200.0, steps=steps,
                                                           sigma_y=180.0, plasticity=plasticity,
                                                           rate=(0.02 / steps, 0.05, 1e-3), hardening=500.0)
    near_limit = lambda steps: dg.plastic_tube_deck(ni=41, p=0.97 * 320.15, steps=steps, plasticity="tangent")
    for name, text, warned in (("seed saac3 20", saac3(20, "tangent"), True),
                               ("seed saac3 20 return-mapping", saac3(20, "return-mapping"), False),
                               ("seed near limit 20", near_limit(20), True),
                               ("seed near limit 200", near_limit(200), False)):
        warnings = run(name.replace(" ", "_"), text)
        if warned:
            fires(name, warnings, "was accepted with a relative residual")
            check("return-mapping" in warnings[0], f"{name}: the warning suggests return-mapping ({warnings})")
        else:
            silent(name, warnings)


def time_error():
    """A rate-dependent run under return-mapping keeps an increment past time_tolerance only where its steps
    were cut to 1/1024: the rate tube in 2 steps with time_tolerance = 1e-9, without gaps and with them (the
    SAAC3 two tubes); silent at the default tolerance in 20 steps, both."""
    tube = lambda steps, *more: dg.plastic_tube_deck(ni=21, a=50.0, b=100.0, p=200.0, steps=steps, sigma_y=180.0,
                                                     rate=(0.02 / steps, 0.05, 1e-3), hardening=500.0,
                                                     extension=more)
    tubes = lambda steps, *more: dg.two_tubes_deck(n=10, nz=1, a=50.0, b=100.0, gap=0.01, c=150.0, p=250.0,
                                                   steps=steps, contact="active-set", sigma_y=180.0, hardening=500.0,
                                                   rate=(0.02 / steps, 0.05, 1e-3), extension=more)
    for name, make in (("tube", tube), ("two tubes", tubes)):
        fires(f"time error {name} 1e-9", run(f"time_error_{name[:3]}_tight", make(2, "time_tolerance = 1e-9")),
              "estimated time error")
        silent(f"time error {name} default", run(f"time_error_{name[:3]}_default", make(20)))


def stalled():
    """Newton accepted at round-off: the plastic tube at 3 x its limit pressure in one step with a hardening of
    E / 2e5 (its tangent nearly singular); silent with a hardening of E / 100."""
    for hardening, warned in ((1.0, True), (2000.0, False)):
        text = dg.plastic_tube_deck(p=960.0, steps=1, hardening=hardening)
        name = f"stall hardening {hardening:g}"
        warnings = run(name.replace(" ", "_"), text)
        (fires(name, warnings, "stopped where the residual stopped falling") if warned else silent(name, warnings))


OPENMP_BLAS = pathlib.Path("/usr/lib/x86_64-linux-gnu/openblas-openmp")


def openmp_blas():
    """--threads 2 with an OpenBLAS that threads through OpenMP (Debian's libopenblas0-openmp, loaded in place
    of the default pthread build): the program keeps OpenMP on one thread, so the run goes on one thread and
    says so; with the default BLAS, two threads and no warning. Same displacements either way."""
    text = matrix.deck(case(), matrix.Body(False))
    answers = []
    for name, env in (("threads_pthread_blas", {}), ("threads_openmp_blas", {"LD_LIBRARY_PATH": str(OPENMP_BLAS)})):
        if env and not (OPENMP_BLAS / "libblas.so.3").exists():
            print(f"skipped {name}: {OPENMP_BLAS} is not installed (.ci/setup installs libopenblas0-openmp)")
            continue
        folder = work / name
        folder.mkdir()
        (folder / "input.deck").write_text(text)
        gapfe = pathlib.Path(sys.argv[1]).resolve()
        done = subprocess.run([gapfe, "run", folder / "input.deck", "--out", folder / "out", "--threads", "2"],
                              capture_output=True, text=True, env={**os.environ, **env})
        check(done.returncode == 0, f"{name}: exit {done.returncode} ({done.stderr.strip()[:300]})")
        warnings = [line for line in done.stderr.splitlines() if line.startswith("gapfe: warning:")]
        threads = [line for line in done.stdout.splitlines() if line.startswith("threads:")]
        if env:
            fires(name, warnings, "OpenBLAS threads with OpenMP")
            check(threads == ["threads: 2; OpenBLAS on 1"],
                  f"{name}: the log says {threads}, not 'threads: 2; OpenBLAS on 1'")
        else:
            silent(name, warnings)
            check(threads == ["threads: 2"], f"{name}: the log says {threads}, not 'threads: 2'")
        answers.append((folder / "out" / "nodes.csv").read_text() if done.returncode == 0 else None)
    if len(answers) == 2:
        check(answers[0] == answers[1], "the OpenMP BLAS run's nodes.csv differs from the default's")


def main():
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    locking()
    ill_conditioned()
    out_of_balance()
    seed_residual()
    time_error()
    stalled()
    openmp_blas()
    finish()


main()
