#!/usr/bin/env python3
"""Plasticity speed/accuracy trade on the thick tube (docs/theory.md V6): runs bench_plastic (Google Benchmark)
and prints a Markdown table of Tangent vs ReturnMapping at 5-200 steps (limit-pressure error, bore
displacement error, linear solves, median wall time), the cost of one plastic step against an elastic
solve of the same mesh, and writes a CSV and, where matplotlib is installed, a PNG of error against time.

  python3 bench/plastic_tradeoff.py --bench build/bench/bench/bench_plastic [--repetitions 5]
  python3 bench/plastic_tradeoff.py --from-json bench/plastic_tradeoff.json   # table and plot again
"""
import argparse
import json
import pathlib
import sys

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.dont_write_bytecode = True
from gbench import medians, run  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bench", default="build/bench/bench/bench_plastic")
    ap.add_argument("--repetitions", type=int, default=5)
    ap.add_argument("--from-json")
    args = ap.parse_args()
    data = json.loads(pathlib.Path(args.from_json).read_text()) if args.from_json else run(args.bench, args.repetitions)
    if not args.from_json:
        (HERE / "plastic_tradeoff.json").write_text(json.dumps(data, indent=1))
    rows = medians(data)

    table = []
    for integration in ("Tangent", "ReturnMapping"):
        for steps in (5, 10, 20, 50, 100, 200):
            lim = rows.get(f"BM_Limit<gapfe::{integration}>/{steps}")
            par = rows.get(f"BM_Partial<gapfe::{integration}>/{steps}")
            if lim is None or par is None:
                continue
            table.append((integration, steps, lim["limit_error"], lim["solves"], lim["real_time"],
                          par["u_error"], par["real_time"]))
    print("| integration | steps | limit-pressure error | linear solves | time [ms] | bore u error at p(0.15) | time [ms] |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for t in table:
        print(f"| {t[0]} | {t[1]} | {t[2]:.2e} | {t[3]:.0f} | {t[4]:.2f} | {t[5]:.2e} | {t[6]:.2f} |")
    with open(HERE / "plastic_tradeoff.csv", "w") as f:
        f.write("integration,steps,limit_error,solves,limit_ms,u_error,partial_ms\n")
        for t in table:
            f.write(",".join(str(x) for x in t) + "\n")

    elastic = rows.get("BM_StepCost_Elastic")
    if elastic:
        print(f"\nstep cost, {elastic['equations']:.0f} equations: elastic solve {elastic['real_time']:.2f} ms")
        for integration in ("Tangent", "ReturnMapping"):
            p = rows.get(f"BM_StepCost_Plastic<gapfe::{integration}>")
            if p:
                print(f"  {integration}: {p['real_time']:.2f} ms, {p['solves']:.0f} linear solves, "
                      f"{p['real_time'] / elastic['real_time']:.2f} x the elastic solve, "
                      f"{p['real_time'] / elastic['real_time'] / p['solves']:.2f} x per linear solve")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("(matplotlib not found: no PNG; /usr/bin/python3 with python3-matplotlib makes it)", file=sys.stderr)
        return
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    for integration, marker in (("Tangent", "o"), ("ReturnMapping", "s")):
        sel = [t for t in table if t[0] == integration]
        ax[0].loglog([t[4] for t in sel], [t[2] for t in sel], marker=marker, label=integration)
        ax[1].loglog([t[6] for t in sel], [max(t[5], 1e-16) for t in sel], marker=marker, label=integration)
        for t in sel:
            ax[0].annotate(str(t[1]), (t[4], t[2]), fontsize=7, textcoords="offset points", xytext=(3, 3))
            ax[1].annotate(str(t[1]), (t[6], max(t[5], 1e-16)), fontsize=7, textcoords="offset points",
                           xytext=(3, 3))
    ax[0].set(xlabel="wall time [ms]", ylabel="|p - p_L| / p_L at 20 u_y",
              title="limit pressure (closed form), 40 Quad4BBar")
    ax[1].set(xlabel="wall time [ms]", ylabel="bore u error vs 1000-step ReturnMapping",
              title="partial yield, p(rho = 0.15) = 288.3 MPa")
    for a in ax:
        a.grid(True, which="both", alpha=0.3)
        a.legend()
    fig.tight_layout()
    fig.savefig(HERE / "plastic_tradeoff.png", dpi=110)
    print("wrote bench/plastic_tradeoff.png")


if __name__ == "__main__":
    main()
