#!/usr/bin/python3
"""Every warning `gapfe run` prints (docs/checks.md lists them), through the command (ctest `gapfe_warnings`):
each fires on a model that triggers it, and stays silent on its neighbour, the same model with the trigger
just removed. The models are tests/check_matrix.py's tube and fit (its deck writer) and bench/deckgen.py's
plastic tube; the friction cone's warning is checked both ways in tests/check_friction_family.py.

    /usr/bin/python3 tests/check_warnings.py build/release/examples/gapfe WORKDIR
"""
import pathlib
import shutil
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
    """element = quad4 with nu above 0.49: fires at 0.4999 and 0.49999999, not at 0.49 or on quad4bbar."""
    for nu, element, warned in ((0.4999, "quad4", True), (0.49999999, "quad4", True), (0.49, "quad4", False),
                                (0.4999, "quad4bbar", False), (0.4999, "legacy", False)):
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
    pulled by ring forces past yield in two steps; silent below yield and with return-mapping."""
    for force, plasticity, warned in ((60000.0, "tangent", True), (60000.0, "return-mapping", False),
                                      (20000.0, "tangent", False)):
        matrix.FORCE = force
        text = matrix.deck(case(load="nodal_force", element="quad4bbar", plastic=True), matrix.Body(False))
        name = f"balance {plasticity} force {force:g}"
        warnings = run(name.replace(" ", "_"), text, "--set", f"plasticity={plasticity}")
        (fires(name, warnings, "out of global equilibrium") if warned else silent(name, warnings))
        if warned:
            check("return-mapping" in warnings[0], f"{name}: the warning suggests return-mapping ({warnings})")
    matrix.FORCE = 2000.0


def stalled():
    """Newton accepted at round-off: the plastic tube at 3 x its limit pressure in one step with a hardening of
    E / 2e5 (its tangent nearly singular); silent with a hardening of E / 100."""
    for hardening, warned in ((1.0, True), (2000.0, False)):
        text = dg.plastic_tube_deck(p=960.0, steps=1, hardening=hardening)
        name = f"stall hardening {hardening:g}"
        warnings = run(name.replace(" ", "_"), text)
        (fires(name, warnings, "stopped where the residual stopped falling") if warned else silent(name, warnings))


def main():
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    locking()
    ill_conditioned()
    out_of_balance()
    stalled()
    finish()


main()
