#!/usr/bin/env python3
"""The shrink fit spun to lift-off (examples/decks/shrink_fit.deck): contact force against speed under every
contact policy, against the closed form (bench/closed_forms.py).

    /usr/bin/python3 bench/shrink_fit.py --gapfe build/release/examples/gapfe

A hub 25.01..50 mm cooled by 100 degrees onto a solid shaft of 25 mm (plane strain, 2.5 mm of length), then
spun up to 5,000 rad/s in 25 steps of 200 rad/s (the deck's inertia card; omega^2 moves linearly within a
step). Closed: the contact force is p(omega) 2 pi b h, p falling with omega^2 from 95.6 MPa to zero at the
lift-off speed (3,893 rad/s); then the fit is open. Writes examples/decks/shrink_fit_liftoff.png and prints,
per policy, the largest difference from the closed form and the lift-off speed the run found.
"""
import argparse
import csv
import math
import pathlib
import subprocess
import sys
import tempfile

import closed_forms

here = pathlib.Path(__file__).resolve().parent
B, W, C, H, OMEGA, STEPS = 25.0, 0.01, 50.0, 2.5, 5000.0, 25


def closed_force(omega):
    state = closed_forms.fit(closed_forms.annulus(0.0, B, omega=omega),
                             closed_forms.annulus(B + W, C, dT=-100.0, omega=omega), W)
    return state["p"] * 2 * math.pi * B * H


def speed(inc):
    """omega at load factor inc: k OMEGA / STEPS at whole steps, omega^2 linear within a step."""
    k = min(math.floor(inc), STEPS - 1)
    w0, w1 = k * OMEGA / STEPS, (k + 1) * OMEGA / STEPS
    return math.sqrt(w0 ** 2 + (inc - k) * (w1 ** 2 - w0 ** 2))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--gapfe", required=True)
    args = ap.parse_args()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4.5))
    speeds = [OMEGA * k / 400 for k in range(401)]
    ax.plot(speeds, [closed_force(w) / 1000 for w in speeds], "k--", lw=1, label="closed form (Lame, plane strain)")
    deck = here.parent / "examples" / "decks" / "shrink_fit.deck"
    for policy, marker in (("saac", "o"), ("active-set", "s"), ("augmented-lagrangian", ".")):
        with tempfile.TemporaryDirectory() as out:
            subprocess.run([args.gapfe, "run", deck, "--out", out, "--quiet", "--plot", "none", "--contact", policy],
                           check=True)
            with open(pathlib.Path(out) / "gaps.csv") as f:
                rows = list(csv.DictReader(f))
        force = {}
        for r in rows:
            force[float(r["inc"])] = force.get(float(r["inc"]), 0.0) + float(r["f_n"])
        points = sorted((speed(inc), total) for inc, total in force.items() if inc >= 1)
        worst = max(abs(total - closed_force(w)) for w, total in points) / closed_force(0)
        # an opening pair is open at its located point: the first speed with no force after one with
        lift = next((w for (_, before), (w, total) in zip(points, points[1:]) if before > 0 and total == 0), None)
        print(f"{policy:22s} largest difference from the closed form {worst:.2e} of the cold force; "
              f"lifts off at {lift:.1f} rad/s")
        ax.plot([w for w, _ in points], [t / 1000 for _, t in points], marker=marker, ls="none", ms=4, label=policy)
    ax.set_xlabel("speed [rad/s]")
    ax.set_ylabel("contact force, total ring [kN]")
    ax.set_title("examples/decks/shrink_fit.deck: cooled on, spun off")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(here.parent / "examples" / "decks" / "shrink_fit_liftoff.png", dpi=110)
    print("wrote examples/decks/shrink_fit_liftoff.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
