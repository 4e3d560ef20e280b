#!/usr/bin/python3
"""Error against cost of quadratic cells (element = quad8) and bilinear ones (quad4) on the Lame tube through
`gapfe run` (BENCHMARKS.md "Quadratic cells: error against cost"): the deck of bench/deckgen.py tube_deck with
N cells through the wall and N / 2 up (a = 100, b = 200, bore pressure 100, plane strain), the L2 error of
u_r per unit height against the closed form (tests/vtu_l2.py, on the VTU's cells), and the whole process's
wall time, best of three.

    /usr/bin/python3 bench/quadratic_cost.py build/release/examples/gapfe WORKDIR
"""
import pathlib
import subprocess
import sys
import time

import meshio

root = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(root / "tests"))
sys.path.insert(0, str(root / "bench"))
import deckgen  # noqa: E402  (bench/deckgen.py)
import vtu_l2  # noqa: E402

gapfe, work = pathlib.Path(sys.argv[1]).resolve(), pathlib.Path(sys.argv[2]).resolve()
work.mkdir(parents=True, exist_ok=True)
E, NU, A, B, P = 200000.0, 0.3, 100.0, 200.0, 100.0


def lame_u(r):
    c = P * A * A / (B * B - A * A)
    return (1 + NU) / E * ((1 - 2 * NU) * c * r + c * B * B / r)


print("| element | cells through the wall | nodes | L2 error of u_r | `gapfe run` [s] |")
print("|---|---|---|---|---|")
for element, sizes in (("quad4", (16, 32, 64, 128, 256)), ("quad8", (4, 8, 16, 32, 64))):
    for cells in sizes:
        deck = work / f"{element}_{cells}.deck"
        deck.write_text(deckgen.tube_deck(cells + 1, cells // 2 + 1,
                                          extension=("format = elastic", f"element = {element}")))
        out = work / f"{element}_{cells}"
        best = float("inf")
        for _ in range(3):
            start = time.perf_counter()
            subprocess.run([str(gapfe), "run", str(deck), "--out", str(out), "--plot", "none", "--quiet"],
                           check=True, capture_output=True)
            best = min(best, time.perf_counter() - start)
        mesh = meshio.read(sorted(out.glob("step_*.vtu"))[-1])
        error = vtu_l2.radial_error(mesh, lame_u)[0]
        print(f"| {element} | {cells} | {len(mesh.points)} | {error:.3e} | {best:.3f} |", flush=True)
