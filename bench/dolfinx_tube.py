#!/usr/bin/env python3
"""`gapfe run` against DOLFINx on the plane-strain Lame tube: the same grid, whole processes, one thread each.

    /usr/bin/python3 bench/dolfinx_tube.py [--cases tube-1e5,tube-1e6] [--runs 2]
                                           [--gapfe build/bench/examples/gapfe]

The peer is DOLFINx 0.5 (Debian's python3-dolfinx) written as a researcher would write it: the
axisymmetric weak form on Q1 quadrilaterals weighted by r, the bore pressure as a boundary integral, u_z = 0
on both ends (plane strain), MUMPS's Cholesky through PETSc, the displacement written as XDMF. This file is
that program too (`--peer NR NZ OUT`). Its forms are compiled once beforehand (FFCx's cache), so the timed
runs measure the solve, not the JIT. gapfe runs bench/run_vs_ccx.py's deck of the same case (the same
nodes: a = 100, b = 200, NR x NZ square cells, bore pressure 100, E = 2e5, nu = 0.3) with every default
output. The two alternate, --runs rounds; each row gives the best wall time of each (the machine is shared),
the peak resident memory (ru_maxrss of the process and its children), and the ratio DOLFINx / gapfe.
Both check the bore's u_r against Lame's closed form (the gapfe run's nodes.csv; the peer prints its own).
"""
import argparse
import csv
import os
import subprocess
import sys
import tempfile
import time

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

A, B, P, E_MOD, NU = 100.0, 200.0, 100.0, 2.0e5, 0.3


def lame_bore_ur():
    """u_r at r = a of the plane-strain Lame tube (docs/theory.md V1)."""
    c = P * A * A / (B * B - A * A)
    return (1 + NU) / E_MOD * ((1 - 2 * NU) * c * A + c * B * B / A)


def peer(nr, nz, out):
    """The DOLFINx program: solve the tube on nr x nz Q1 cells, write u as XDMF, print the bore's u_r."""
    import numpy as np
    import ufl
    from dolfinx import fem, io, mesh
    from dolfinx.fem.petsc import LinearProblem
    from mpi4py import MPI
    from petsc4py import PETSc

    start = time.perf_counter()
    height = nz * (B - A) / nr
    domain = mesh.create_rectangle(MPI.COMM_WORLD, [np.array([A, 0.0]), np.array([B, height])], [nr, nz],
                                   mesh.CellType.quadrilateral)
    V = fem.VectorFunctionSpace(domain, ("Lagrange", 1))
    r = ufl.SpatialCoordinate(domain)[0]
    lam = E_MOD * NU / ((1 + NU) * (1 - 2 * NU))
    mu = E_MOD / (2 * (1 + NU))

    def strain(u):  # (rr, zz, hoop, rz) as a 3 x 3 tensor in (r, theta, z)
        return ufl.as_tensor([[u[0].dx(0), 0, 0.5 * (u[0].dx(1) + u[1].dx(0))],
                              [0, u[0] / r, 0],
                              [0.5 * (u[0].dx(1) + u[1].dx(0)), 0, u[1].dx(1)]])

    def stress(u):
        return lam * ufl.tr(strain(u)) * ufl.Identity(3) + 2 * mu * strain(u)

    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    bore = mesh.locate_entities_boundary(domain, 1, lambda x: np.isclose(x[0], A))
    tags = mesh.meshtags(domain, 1, bore, np.full(len(bore), 1, dtype=np.int32))
    ds = ufl.Measure("ds", domain=domain, subdomain_data=tags)
    a = ufl.inner(stress(u), strain(v)) * r * ufl.dx
    L = P * v[0] * r * ds(1)
    ends = mesh.locate_entities_boundary(domain, 1, lambda x: np.isclose(x[1], 0) | np.isclose(x[1], height))
    dofs = fem.locate_dofs_topological(V.sub(1), 1, ends)
    bc = fem.dirichletbc(PETSc.ScalarType(0), dofs, V.sub(1))
    problem = LinearProblem(a, L, bcs=[bc], petsc_options={"ksp_type": "preonly", "pc_type": "cholesky",
                                                           "pc_factor_mat_solver_type": "mumps"})
    uh = problem.solve()
    with io.XDMFFile(domain.comm, out, "w") as xdmf:
        xdmf.write_mesh(domain)
        xdmf.write_function(uh)
    x = V.tabulate_dof_coordinates()
    at_bore = np.isclose(x[:, 0], A)
    values = uh.x.array.reshape(-1, 2)[at_bore, 0]
    print(f"equations {V.dofmap.index_map.size_global * 2}; bore u_r {values.mean():.9e}; "
          f"{time.perf_counter() - start:.3f} s in the program")


def timed(cmd, cwd, env):
    """(wall seconds, peak resident MB, output) of one whole process; exits on failure, naming it."""
    with tempfile.TemporaryFile() as sink:
        t0 = time.perf_counter()
        proc = subprocess.Popen(cmd, cwd=cwd, env=env, stdin=subprocess.DEVNULL, stdout=sink,
                                stderr=subprocess.STDOUT)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - t0
        sink.seek(0)
        text = sink.read().decode(errors="replace")
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"dolfinx_tube: {' '.join(cmd)} failed ({os.waitstatus_to_exitcode(status)}):\n{text[-2000:]}")
    return wall, usage.ru_maxrss / 1024.0, text


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--peer", nargs=3, metavar=("NR", "NZ", "OUT"), help="run the DOLFINx program only")
    ap.add_argument("--cases", default="tube-1e5,tube-1e6")
    ap.add_argument("--runs", type=int, default=2)
    ap.add_argument("--gapfe", default="build/bench/examples/gapfe")
    ap.add_argument("--work", default=None)
    args = ap.parse_args()
    if args.peer:
        peer(int(args.peer[0]), int(args.peer[1]), args.peer[2])
        return
    import run_vs_ccx  # noqa: E402  (the cases and their decks)
    gapfe = os.path.abspath(args.gapfe)
    work = args.work or tempfile.mkdtemp(prefix="dolfinx_tube_")
    os.makedirs(work, exist_ok=True)
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    me = os.path.abspath(__file__)
    print("| case | equations | gapfe [s] | DOLFINx [s] | ratio | peak MB gapfe / DOLFINx | bore u_r error gapfe |")
    print("|---|---|---|---|---|---|---|")
    for name in args.cases.split(","):
        case = run_vs_ccx.CASES[name]
        deck, _ = run_vs_ccx.write_inputs(case, work)
        nr, nz = case.ni - 1, case.nj - 1
        xdmf = os.path.join(work, f"{name}.xdmf")
        timed(["/usr/bin/python3", me, "--peer", str(nr), str(nz), xdmf], work, env)  # compiles the forms
        ours, theirs = [], []
        for _ in range(args.runs):
            out = os.path.join(work, f"{name}_gapfe")
            ours.append(timed([gapfe, "run", deck, "--out", out, "--overwrite"], work, env))
            theirs.append(timed(["/usr/bin/python3", me, "--peer", str(nr), str(nz), xdmf], work, env))
        with open(os.path.join(work, f"{name}_gapfe", "nodes.csv")) as f:
            rows = [r for r in csv.DictReader(f) if abs(float(r["r"]) - A) < 1e-9 and r["step"] == "1"]
        u_bore = sum(float(r["u_r"]) for r in rows) / len(rows)
        g, d = min(o[0] for o in ours), min(t[0] for t in theirs)
        print(f"| {name} | {case.equations:,} | {g:.3f} | {d:.3f} | {d / g:.2f}x | "
              f"{max(o[1] for o in ours):.0f} / {max(t[1] for t in theirs):.0f} | "
              f"{(u_bore - lame_bore_ur()) / lame_bore_ur():.1e} |", flush=True)


if __name__ == "__main__":
    main()
