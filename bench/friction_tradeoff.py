#!/usr/bin/env python3
"""Friction's speed/accuracy trade on the press fit, and the example's force-displacement picture.

    python3 bench/friction_tradeoff.py --gapfe build/bench/examples/gapfe [--repeat 3] [--picture-only]
    python3 bench/friction_tradeoff.py --gapfe build/bench/examples/gapfe --combined [--repeat 5]

The problem is bench/deckgen.py's press_fit_deck (examples/decks/press_fit.deck with 40 steps): a hub
(25.001-50 mm) pressed on a hollow shaft (12.5-25 mm) by 75 MPa on its outer surface in step 1, then its
top face pushed down 0.04 mm in all while the shaft's bottom face is held; mu = 0.15, 50 mm long. Here
nu = 0 (argument --nu), so that the closed form is exact away from the ends:

    q_c = w E (c^2 - b^2) / (2 b c^2),   p = (q - q_c) c^2 (b^2 - a^2) / (b^2 (c^2 - a^2)),
    F   = mu p 2 pi b L                              (the push-out force at full slip)

For each slip model (proportional and extended under contact = saac, coulomb under active-set and
augmented-lagrangian) and 5 to 200 load steps over the same push: the push-out force at the end (sum of
R_z over the hub's top face, reactions.csv, last increment) against F, the self-consistent mu sum f_n
(gaps.csv), the command's linear solves (its log) and the median wall time of `gapfe run` (--repeat).
Writes bench/friction_tradeoff.csv and .png (error against time), and with the 40-step example deck
examples/decks/press_fit_pushout.png (push-out force against the push, every model).

--combined: the same fit pushed while it is pressed (press_fit_deck(ramp=True): the pressure rises with
the push in each of the 40 steps, so pairs close while the fit slides; mu = 0.2 as in the friction family
test, tests/check_friction_family.py). For every model, with events = locate and step-end for Coulomb: the
push-out force against the push (examples/decks/push_while_pressing.png) and a table of the final force
against F and mu sum f_n, the largest |f_t| / (mu f_n) of a closed pair (history.csv's cone_ratio), the
linear solves and the median wall time (docs/verification.md, "Friction under combined loading").
"""
import argparse
import csv
import math
import pathlib
import re
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import deckgen  # noqa: E402

A, B, W, C, L, E, Q, MU = 12.5, 25.0, 0.001, 50.0, 50.0, 200000.0, 75.0, 0.15
PUSH = 0.04
MODELS = [("proportional", "saac", None), ("extended", "saac", None), ("coulomb", "active-set", None),
          ("coulomb", "active-set", "step-end"), ("coulomb", "augmented-lagrangian", None)]


def label(slip, contact, events):
    return f"{slip} ({contact}{', ' + events if events else ''})"


def closed_form():
    return MU * deckgen.press_fit_normal_force(A, B, W, C, L, Q, E)


def run(gapfe, deck_text, out, repeat):
    out.mkdir(parents=True, exist_ok=True)
    deck = out / "press_fit.deck"
    deck.write_text(deck_text)
    times, log = [], ""
    for k in range(repeat):
        t0 = time.perf_counter()
        res = subprocess.run([gapfe, "run", str(deck), "--out", str(out)], capture_output=True, text=True)
        times.append(time.perf_counter() - t0)
        if res.returncode != 0:
            return None, res.stdout + res.stderr
        log = res.stdout
    return statistics.median(times), log


def curve(out):
    """(push, force) per increment: the hub's top-face reactions and its mean u_z."""
    force, push = {}, {}
    with open(out / "reactions.csv") as f:
        for row in csv.DictReader(f):
            if float(row["r"]) > B + W / 2 and float(row["R_z"]) != 0:
                key = (int(row["step"]), float(row["inc"]))
                force[key] = force.get(key, 0.0) + float(row["R_z"])
    with open(out / "nodes.csv") as f:
        top = {}
        for row in csv.DictReader(f):
            if float(row["r"]) > B + W / 2 and abs(float(row["z"]) - L) < 1e-9:
                key = (int(row["step"]), float(row["inc"]))
                top.setdefault(key, []).append(float(row["u_z"]))
    for key, u in top.items():
        push[key] = -sum(u) / len(u)
    keys = sorted(set(force) & set(push), key=lambda k: k[1])
    return [(0.0, 0.0)] + [(push[k], -force[k]) for k in keys]


def friction_sum(out):
    last, total = None, 0.0
    with open(out / "gaps.csv") as f:
        rows = list(csv.DictReader(f))
    last = max(float(r["inc"]) for r in rows)
    for r in rows:
        if float(r["inc"]) == last:
            total += float(r["f_n"])
    return MU * total


def solves(log):
    m = re.search(r"(\d+) linear solves", log)
    return int(m.group(1)) if m else -1


def combined(gapfe, repeat, tmp, plt, here):
    """--combined: the push-while-pressing fit, every model (see the top)."""
    mu = 0.2
    closed = closed_form() / MU * mu
    fig, ax = plt.subplots(figsize=(7, 4.5))
    print(f"{'model':48s} {'force/F':>8s} {'/mu sum':>8s} {'cone':>7s} {'solves':>6s} {'wall [s]':>8s}")
    for slip, contact, events in MODELS + [("coulomb", "augmented-lagrangian", "step-end")]:
        text = deckgen.press_fit_deck(slip=slip, contact=contact, events=events, mu=mu, ramp=True)
        out = tmp / f"combined_{slip}_{contact}_{events}"
        seconds, log = run(gapfe, text, out, repeat)
        name = label(slip, contact, events)
        if seconds is None:
            print(f"{name:48s} failed: {log.strip().splitlines()[-1][:200]}")
            continue
        xs, ys = zip(*curve(out))
        ax.plot([1000 * x for x in xs], [y / 1000 for y in ys], marker=".", label=name)
        with open(out / "history.csv") as f:
            cone = max(float(row["cone_ratio"]) for row in csv.DictReader(f))
        force = ys[-1]
        print(f"{name:48s} {force / closed:8.4f} {force / (friction_sum(out) / MU * mu):8.4f} {cone:7.3g} "
              f"{solves(log):6d} {seconds:8.3f}")
    pushes = [PUSH * k / 400 for k in range(401)]
    limit = [mu * deckgen.press_fit_normal_force(A, B, W, C, L, Q * x / PUSH, E) for x in pushes]
    ax.plot([1000 * x for x in pushes], [y / 1000 for y in limit], color="k", ls="--", lw=1,
            label="mu N(q): full slip at the pressure reached (closed form)")
    ax.set_xlabel("push of the hub's top face [um] (the pressure rises with it, to 75 MPa at 40 um)")
    ax.set_ylabel("push-out force [kN]")
    ax.set_ylim(0, 3.0 * closed / 1000)
    ax.set_title("pushed while pressed: Coulomb on mu N(q), the seed's models above it")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(here.parent / "examples" / "decks" / "push_while_pressing.png", dpi=110)
    print("wrote examples/decks/push_while_pressing.png")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--gapfe", required=True)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--nu", type=float, default=0.0)
    ap.add_argument("--steps", default="5,10,20,50,100,200")
    ap.add_argument("--picture-only", action="store_true")
    ap.add_argument("--combined", action="store_true", help="the fit pushed while it is pressed")
    args = ap.parse_args()
    here = pathlib.Path(__file__).resolve().parent
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    F = closed_form()
    tmp = pathlib.Path(tempfile.mkdtemp(prefix="friction_"))
    if args.combined:
        return combined(args.gapfe, args.repeat, tmp, plt, here) or 0
    # The example's picture: the 40-step deck as shipped (nu = 0.3), every model.
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for slip, contact, events in MODELS:
        text = deckgen.press_fit_deck(slip=slip, contact=contact, events=events)
        out = tmp / f"example_{slip}_{contact}_{events}"
        seconds, log = run(args.gapfe, text, out, 1)
        if seconds is None:
            print(f"{label(slip, contact, events)}: gapfe failed: {log.strip().splitlines()[-1][:300]}",
                  file=sys.stderr)
            continue
        xs, ys = zip(*curve(out))
        ax.plot([1000 * x for x in xs], [y / 1000 for y in ys], marker=".", label=label(slip, contact, events))
        if slip == "coulomb" and contact == "augmented-lagrangian":
            ax.axhline(friction_sum(out) / 1000, color="k", ls=":", lw=1, label="mu sum f_n (coulomb, a-l)")
    ax.axhline(F / 1000, color="k", ls="--", lw=1, label=f"mu p 2 pi b L = {F / 1000:.1f} kN (nu = 0 closed form)")
    ax.set_xlabel("push of the hub's top face [um]")
    ax.set_ylabel("push-out force [kN]")
    ax.set_ylim(0, 3.0 * F / 1000)
    ax.set_title("examples/decks/press_fit.deck: stick, slip, and the plateau at mu N")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(here.parent / "examples" / "decks" / "press_fit_pushout.png", dpi=110)
    print("wrote examples/decks/press_fit_pushout.png")
    if args.picture_only:
        return 0

    rows = []
    for slip, contact, events in MODELS:
        for n in [int(s) for s in args.steps.split(",")]:
            text = deckgen.press_fit_deck(slip=slip, contact=contact, steps=n, push=PUSH / n, nu=args.nu,
                                          events=events)
            out = tmp / f"{slip}_{contact}_{events}_{n}"
            seconds, log = run(args.gapfe, text, out, args.repeat)
            if seconds is None:
                rows.append(dict(model=slip, contact=contact, events=events or "locate", steps=n,
                                 force=float("nan"), error=float("nan"),
                                 self_error=float("nan"), solves=-1, seconds=float("nan")))
                print(f"{label(slip, contact, events):40s} {n:4d}  failed: {log.strip().splitlines()[-1]}")
                continue
            force = curve(out)[-1][1]
            rows.append(dict(model=slip, contact=contact, events=events or "locate", steps=n, force=force,
                             error=(force - F) / F,
                             self_error=(force - friction_sum(out)) / friction_sum(out), solves=solves(log),
                             seconds=seconds))
            r = rows[-1]
            print(f"{label(slip, contact, events):40s} {n:4d}  F {force:10.1f}  err {100 * r['error']:8.3f} %  "
                  f"vs mu sum P {100 * r['self_error']:8.3f} %  solves {r['solves']:5d}  {seconds:.3f} s")
    with open(here / "friction_tradeoff.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for slip, contact, events in MODELS:
        pts = [(r["seconds"], abs(r["error"])) for r in rows
               if r["model"] == slip and r["contact"] == contact and r["events"] == (events or "locate")
               and r["seconds"] == r["seconds"]]
        if pts:
            ax.loglog(*zip(*pts), marker="o", label=label(slip, contact, events))
    ax.set_xlabel("gapfe run wall time [s] (5 to 200 steps)")
    ax.set_ylabel("|push-out force error| vs mu p 2 pi b L")
    ax.set_title(f"press fit, nu = {args.nu:g}: friction models, error against cost")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(here / "friction_tradeoff.png", dpi=110)
    print("wrote bench/friction_tradeoff.csv, bench/friction_tradeoff.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
