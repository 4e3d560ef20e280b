#!/usr/bin/env python3
"""Output parity of two `gapfe` builds: every example deck and scene as it is, and the small decks under
every option combination the command offers (element x variant x solver, contact policy or plasticity
integration), run by both binaries; every CSV file they write compared cell by cell. For refactors that
must not change results.

  python3 bench/output_parity.py --before OLD/gapfe --after NEW/gapfe [--work DIR] [--tolerance 1e-12]

A numeric cell's difference counts relative to the larger of the two values, or to the largest magnitude
in its column where that is smaller (values that are round-off zeros next to O(1) ones); exit codes and
error messages must match too. Exit status 0 when every file agrees within the tolerance."""
import argparse
import csv
import itertools
import os
import subprocess
import sys

EXAMPLES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples")
DECKS = os.path.join(EXAMPLES, "decks")
ELEMENTS = ["legacy", "quad4", "quad4bbar"]
VARIANTS = ["saas", "saga"]


def cases():
    for folder, suffix in (("decks", ".deck"), ("scenes", ".toml")):
        for f in sorted(os.listdir(os.path.join(EXAMPLES, folder))):
            if f.endswith(suffix):
                yield f"as_is_{f[:-len(suffix)]}", os.path.join(EXAMPLES, folder, f), []
    for deck in ["thick_tube", "helical_sleeve"]:
        for e, v, s in itertools.product(ELEMENTS, VARIANTS, ["eigen", "cholmod"]):
            yield f"{deck}_{e}_{v}_{s}", deck, ["--element", e, "--variant", v, "--solver", s]
    for deck in ["two_tubes", "projectile"]:
        for e, v, c in itertools.product(ELEMENTS, VARIANTS, ["saac", "active-set", "augmented-lagrangian", "none"]):
            yield f"{deck}_{e}_{v}_{c}", deck, ["--element", e, "--variant", v, "--contact", c]
    for deck in ["plastic_tube", "plastic_two_tubes"]:
        for e, v, p in itertools.product(["quad4", "quad4bbar"], VARIANTS, ["tangent", "return-mapping"]):
            yield f"{deck}_{e}_{v}_{p}", deck, ["--element", e, "--variant", v, "--plasticity", p]


def run(gapfe, out, deck, options):
    os.makedirs(out, exist_ok=True)
    path = deck if os.path.isabs(deck) else os.path.join(DECKS, deck + ".deck")
    p = subprocess.run([gapfe, "run", path, *options, "--out", out, "--quiet", "--overwrite"],
                       capture_output=True, text=True)
    return p.returncode, p.stderr.replace(gapfe, "gapfe")


def number(text):
    try:
        return float(text)
    except ValueError:
        return None


def compare_csv(a, b):
    """Largest relative difference of numeric cells, or a string saying why the files cannot be compared."""
    rows_a, rows_b = list(csv.reader(open(a))), list(csv.reader(open(b)))
    if len(rows_a) != len(rows_b) or rows_a[0] != rows_b[0]:
        return f"different shape ({len(rows_a)} vs {len(rows_b)} rows)"
    scale = [0.0] * len(rows_a[0])
    for row in rows_a[1:]:
        for k, cell in enumerate(row):
            v = number(cell)
            if v is not None and k < len(scale):
                scale[k] = max(scale[k], abs(v))
    worst = 0.0
    for ra, rb in zip(rows_a[1:], rows_b[1:]):
        for k, (x, y) in enumerate(zip(ra, rb)):
            cells = list(zip(x.split(" "), y.split(" "))) if x.count(" ") == y.count(" ") else None
            if cells is None:
                return f"row {ra[:3]} column {k}: {x!r} vs {y!r}"
            for u_text, v_text in cells:
                u, v = number(u_text), number(v_text)
                if u is None or v is None:
                    if u_text != v_text:
                        return f"row {ra[:3]} column {k}: {x!r} vs {y!r}"
                    continue
                d = abs(u - v)
                if d == 0:
                    continue
                col = scale[k] if k < len(scale) else 0.0
                relative = d / max(abs(u), abs(v))
                worst = max(worst, min(relative, d / col) if col > 0 else relative)
    return worst


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--before", required=True)
    ap.add_argument("--after", required=True)
    ap.add_argument("--work", default="build/parity-out")
    ap.add_argument("--tolerance", type=float, default=1e-12)
    a = ap.parse_args()
    worst, files, problems, runs = 0.0, 0, [], 0
    for name, deck, options in cases():
        runs += 1
        results = [run(g, os.path.join(a.work, side, name), deck, options)
                   for side, g in (("before", a.before), ("after", a.after))]
        if results[0] != results[1]:
            problems.append(f"{name}: exit/error differs: {results[0]} vs {results[1]}")
            continue
        before = os.path.join(a.work, "before", name)
        for f in sorted(os.listdir(before)):
            if not f.endswith(".csv"):
                continue
            files += 1
            r = compare_csv(os.path.join(before, f), os.path.join(a.work, "after", name, f))
            if isinstance(r, str):
                problems.append(f"{name}/{f}: {r}")
            elif r > worst:
                worst, where = r, f"{name}/{f}"
    print(f"{runs} runs, {files} CSV files compared; largest relative difference {worst:.3e}"
          + (f" ({where})" if worst > 0 else ""))
    for p in problems:
        print("  " + p)
    return 0 if not problems and worst <= a.tolerance else 1


if __name__ == "__main__":
    sys.exit(main())
