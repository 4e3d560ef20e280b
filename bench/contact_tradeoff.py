#!/usr/bin/env python3
"""Speed/accuracy trade of the contact policies on the two-tube problem (BENCHMARKS.md "Contact").

For each policy (saac, active-set, augmented-lagrangian) and 5, 10, 20, 50, 100 load steps, run
`gapfe run` on bench/deckgen.py's two-tube deck (inner 1-1.5, outer 1.5005-2, 40 x 80 cells each, bore
pressure 100, plane strain) and report the closure-load error, the final contact-pressure error (both
against docs/theory.md V5's closed form), the linear solves and the wall time (median of --repeat runs).
Writes contact_tradeoff.csv and, when matplotlib is available, contact_tradeoff.png (error vs time).

    python3 bench/contact_tradeoff.py --gapfe build/bench/examples/gapfe
"""
import argparse, csv, math, os, pathlib, re, statistics, subprocess, sys, tempfile, time

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import deckgen  # noqa: E402

A, B, C, GAP, E, NU, P, H = 1.0, 1.5, 2.0, 5e-4, 200000.0, 0.3, 100.0, 1.0
P_CLOSE = GAP * E * (B * B - A * A) / (2 * A * A * B * (1 - NU * NU))
Q_EXACT = (P - P_CLOSE) * A * A * (C * C - B * B) / (B * B * (C * C - A * A))


def run(gapfe, deck, out, element):
    t0 = time.perf_counter()
    r = subprocess.run([gapfe, "run", str(deck), "--out", str(out), "--element", element], capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if r.returncode != 0:
        sys.exit(f"gapfe failed on {deck}: {r.stderr}")
    solves = int(re.search(r"(\d+) linear solves", r.stdout).group(1))
    return wall, solves


def closure_and_pressure(out, steps):
    rows = list(csv.DictReader(open(out / "gaps.csv")))
    last_open, closure = 0.0, None
    for row in rows:
        if row["status"] == "closed":
            closure = last_open
            break
        last_open = float(row["inc"])
    final = max(float(r["inc"]) for r in rows)
    force = sum(float(r["f_n"]) for r in rows if float(r["inc"]) == final)
    return closure / steps * P, force / (2 * math.pi * B * H)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--gapfe", default="build/bench/examples/gapfe")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--element", default="quad4")
    ap.add_argument("--out", default=".")
    ap.add_argument("--from-csv", help="plot an earlier contact_tradeoff.csv instead of running")
    a = ap.parse_args()
    table = []
    if a.from_csv:
        table = [{k: (v if k == "policy" else float(v)) for k, v in r.items()} for r in csv.DictReader(open(a.from_csv))]
        return plot(table, pathlib.Path(a.out))
    work = pathlib.Path(tempfile.mkdtemp(prefix="gapfe_tradeoff_"))
    print(f"# closed form: p_c = {P_CLOSE:.4f}, q(100) = {Q_EXACT:.4f}; element {a.element}; median of {a.repeat}")
    print(f"{'policy':22s} {'steps':>5s} {'closure_err':>11s} {'q_err':>9s} {'solves':>6s} {'wall_s':>7s}")
    for policy in ("saac", "active-set", "augmented-lagrangian"):
        for steps in (5, 10, 20, 50, 100):
            deck = work / f"{policy}_{steps}.deck"
            deck.write_text(deckgen.two_tubes_deck(n=40, nz=80, steps=steps, contact=policy))
            out = work / f"{policy}_{steps}"
            out.mkdir(exist_ok=True)
            walls = []
            for _ in range(a.repeat):
                wall, solves = run(a.gapfe, deck, out, a.element)
                walls.append(wall)
            pc, q = closure_and_pressure(out, steps)
            row = dict(policy=policy, steps=steps, closure_err=(pc - P_CLOSE) / P_CLOSE, q_err=(q - Q_EXACT) / Q_EXACT,
                       solves=solves, wall_s=statistics.median(walls))
            table.append(row)
            print(f"{policy:22s} {steps:5d} {row['closure_err']:+11.2e} {row['q_err']:+9.2e} {solves:6d} {row['wall_s']:7.3f}")
    outdir = pathlib.Path(a.out)
    with open(outdir / "contact_tradeoff.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(table[0]))
        w.writeheader()
        w.writerows(table)
    plot(table, outdir)


def plot(table, outdir):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not found (apt-get install python3-matplotlib): no PNG")
        return
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    for policy in ("saac", "active-set", "augmented-lagrangian"):
        rows = [r for r in table if r["policy"] == policy]
        for k, key in enumerate(("closure_err", "q_err")):
            ax[k].loglog([r["wall_s"] for r in rows], [max(abs(r[key]), 1e-8) for r in rows], "o-", label=policy)
            for r in rows:
                ax[k].annotate(str(r["steps"]), (r["wall_s"], max(abs(r[key]), 1e-8)), fontsize=7)
    ax[0].set_title("closure-load error vs wall time (labels: steps)")
    ax[1].set_title("final contact-pressure error vs wall time")
    for x in ax:
        x.set_xlabel("wall time [s]")
        x.set_ylabel("relative error")
        x.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(outdir / "contact_tradeoff.png", dpi=110)
    print(f"wrote {outdir / 'contact_tradeoff.png'}")


if __name__ == "__main__":
    main()
