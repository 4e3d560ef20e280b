#!/usr/bin/env python3
"""Rate-dependent plasticity speed/accuracy trade (Drysdale-Zak, SAAC3): runs bench_rate (Google Benchmark)
and prints a Markdown table of the two integrations (tangent: the seed's SAAC3 scheme; return-mapping: the
implicit return) at dt from 1e-3 to 1e2 relaxation times on the constant-rate bar and on the SAAC3X tube
(largest stress error along the path against the 1-D ODE, error at the end, steps, median wall time), the
cost of one rate-dependent step against an elastic solve of the same mesh, a CSV and, where matplotlib is
installed, a PNG of error against time.

  /usr/bin/python3 bench/rate_tradeoff.py --bench build/bench/bench/bench_rate [--repetitions 3]
  /usr/bin/python3 bench/rate_tradeoff.py --from-json bench/rate_tradeoff.json   # table and plot again
"""
import argparse
import json
import pathlib
import sys

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.dont_write_bytecode = True
from gbench import medians, run  # noqa: E402
CASES = (("BM_ConstantRate", "constant-rate bar"), ("BM_Saac3x", "SAAC3X tube"))
INTEGRATIONS = (("Tangent", "tangent"), ("ReturnMapping", "return-mapping"))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bench", default="build/bench/bench/bench_rate")
    ap.add_argument("--repetitions", type=int, default=3)
    ap.add_argument("--from-json")
    args = ap.parse_args()
    data = json.loads(pathlib.Path(args.from_json).read_text()) if args.from_json else run(args.bench, args.repetitions)
    if not args.from_json:
        (HERE / "rate_tradeoff.json").write_text(json.dumps(data, indent=1))
    rows = medians(data)

    table = []
    for case, label in CASES:
        for integration, name in INTEGRATIONS:
            for k in range(6):
                b = rows.get(f"{case}<gapfe::{integration}>/{k}")
                if b is not None:
                    table.append((label, name, b["lambda_dt"], b["steps"], b["stress_error"], b["end_error"],
                                  b["real_time"]))
    print("| case | integration | lambda dt | steps | largest stress error / sigma_ss | error at the end | time [ms] |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for t in table:
        print(f"| {t[0]} | {t[1]} | {t[2]:g} | {t[3]:.0f} | {t[4]:.2e} | {t[5]:.2e} | {t[6]:.2f} |")
    with open(HERE / "rate_tradeoff.csv", "w") as f:
        f.write("case,integration,lambda_dt,steps,stress_error,end_error,ms\n")
        for t in table:
            f.write(",".join(str(x) for x in t) + "\n")

    elastic = rows.get("BM_StepCost_Elastic")
    if elastic:
        print(f"\nstep cost (thick tube, 400 x 8 cells): elastic solve {elastic['real_time']:.2f} ms")
        for integration, name in INTEGRATIONS:
            p = rows.get(f"BM_StepCost_Rate<gapfe::{integration}>")
            if p:
                print(f"  {name}: {p['real_time']:.2f} ms, {p['solves']:.0f} linear solves, "
                      f"{p['plastic_points']:.0f} plastic points, {p['real_time'] / elastic['real_time']:.2f} x the "
                      f"elastic solve")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("(matplotlib not found: no PNG; /usr/bin/python3 with python3-matplotlib makes it)", file=sys.stderr)
        return
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    for a, (case, label) in zip(ax, CASES):
        for (integration, name), marker in zip(INTEGRATIONS, ("o", "s")):
            sel = [t for t in table if t[0] == label and t[1] == name]
            a.loglog([t[6] for t in sel], [max(t[4], 1e-16) for t in sel], marker=marker, label=name)
            for t in sel:
                a.annotate(f"{t[2]:g}", (t[6], max(t[4], 1e-16)), fontsize=7, textcoords="offset points",
                           xytext=(3, 3))
        a.set(xlabel="wall time [ms]", ylabel="largest |sigma - sigma_ODE| / sigma_ss",
              title=f"{label}: labels are lambda dt")
        a.grid(True, which="both", alpha=0.3)
        a.legend()
    fig.tight_layout()
    fig.savefig(HERE / "rate_tradeoff.png", dpi=110)
    print("wrote bench/rate_tradeoff.png")


if __name__ == "__main__":
    main()
