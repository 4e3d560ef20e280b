#!/usr/bin/env python3
"""Write card decks (BRL-CR-670 Appendix A) column-exact, for the examples and the benchmarks.

    python3 bench/deckgen.py tube --ni 301 --nj 167 > tube.deck    # thick tube, 2 ni nj DOFs
    python3 bench/deckgen.py tube --ni 707 --nj 707 --wide > big.deck  # `$ fields = wide`: 1e6 DOFs
    python3 bench/deckgen.py two-tubes --n 40 --nz 80 > tubes.deck  # two tubes across a radial gap
    python3 bench/deckgen.py examples                               # rewrites examples/decks/*.deck

Each card helper returns one 80-column line; the field widths are the seed's formats.
"""
import argparse
import math
import pathlib


def f(value, width, decimals=None):
    """A real in `width` columns with an explicit decimal point (so no implied-decimal surprises)."""
    if decimals is not None:
        text = f"{value:{width}.{decimals}f}"
        if len(text) <= width:
            return text
    for digits in range(width - 2, 0, -1):
        text = f"{value:{width}.{digits}g}"
        if "." not in text and "e" not in text:
            text = f"{value:.1f}".rjust(width)
        if len(text) <= width:
            return text
    raise ValueError(f"{value} does not fit in {width} columns")


def i(value, width):
    text = f"{value:{width}d}"
    assert len(text) == width, (value, width)
    return text


def segment(points, kind, wide=False):
    """Data 4: up to three (I, J, R, Z) points, then the type in columns 67-71 (3(2I3, 2F8.3), I5); with
    wide (the deck's `$ fields = wide`), 3(2I5, 2F12.3), I5 with the type in columns 103-107."""
    iw, cw = (5, 12) if wide else (3, 8)
    line = ""
    for k in range(3):
        if k < len(points):
            pi, pj, r, z = points[k]
            line += i(pi, iw) + i(pj, iw) + f(r, cw) + f(z, cw)  # explicit point: any decimals fit
        else:
            line += " " * (2 * iw + 2 * cw)
    return line + i(kind, 5)


def control(numtc=0, nummat=1, numpc=0, numsc=0, numst=0, tref=0.0, inert=0, nlinc=1, inci=0, incf=0, iplot=0):
    """Data 2 (6I5, F5.0, 6I5)."""
    return (i(1, 5) + i(numtc, 5) + i(nummat, 5) + i(numpc, 5) + i(numsc, 5) + i(numst, 5) + f(tref, 5, 1)
            + i(inert, 5) + i(nlinc, 5) + i(inci, 5) + i(incf, 5) + i(iplot, 5))


def mesh_control(maxi, maxj, nseg, nbc, nmtl):
    return "".join(i(v, 5) for v in (maxi, maxj, nseg, nbc, nmtl))


def bc(i1, i2, j1, j2, code, xr=0.0, xz=0.0, xt=0.0):
    """Data 5 (4I5, I10, 3F10.0)."""
    return i(i1, 5) + i(i2, 5) + i(j1, 5) + i(j2, 5) + i(code, 10) + f(xr, 10) + f(xz, 10) + f(xt, 10)


def block(mat, i1, i2, j1, j2, beta=0.0, alpha=0.0, iang=0, nang=0, ijdir=0):
    """Data 6 (5I5, 2F10.0, 3I5)."""
    return (i(mat, 5) + i(i1, 5) + i(i2, 5) + i(j1, 5) + i(j2, 5) + f(beta, 10) + f(alpha, 10) + i(iang, 5)
            + i(nang, 5) + i(ijdir, 5))


def material(ident, rows, density=0.0, free_expansion=False, yield_card=None, elastic_format=False):
    """Data 10a, 10b (two cards per temperature row) and, in saac decks, Data 11 (blank = elastic).

    rows: (T, E_N, E_S, E_T, nu_NS, nu_NT, nu_ST, G_NS, G_ST, G_TN, a_N, a_S, a_T)."""
    out = [i(ident, 5) + i(len(rows), 5) + f(density, 10) + f(1.0 if free_expansion else 0.0, 10)]
    for row in rows:
        out.append("".join(f(v, 10) for v in row[:7]))
        out.append("".join(f(v, 10) for v in row[7:]))
    if not elastic_format:
        out.append("" if yield_card is None else "".join(f(v, 10) for v in yield_card))
    return out


def isotropic(E, nu, alpha=0.0, T=0.0):
    G = E / (2 * (1 + nu))
    return (T, E, E, E, nu, nu, nu, G, G, G, alpha, alpha, alpha)


def edge(m, n, value, wide=False):
    """Data 13-15 (2I5, F10.0; wide: 2I10, F10.0)."""
    w = 10 if wide else 5
    return i(m, w) + i(n, w) + f(value, 10)


def tube_deck(ni, nj, a=100.0, b=200.0, h=None, p=100.0, extension=("format = elastic",), nodal=False,
              wide=False, nu=0.3):
    """Thick tube a <= r <= b, 0 <= z <= h, plane strain (u_z = 0 on both ends), internal pressure p.
    Nodes (ni x nj grid): node(I, J) = (J - 1) ni + I. Legacy pressure cards (I5 node numbers) reach only
    node 99999 and segment cards (I3) index 999: wide=True writes `$ fields = wide` and the widened cards;
    with nodal=True the pressure is given as its consistent ring forces on BC cards instead."""
    if wide:
        extension = tuple(extension) + ("fields = wide",)
    seg = lambda points, kind: segment(points, kind, wide)
    h = h if h is not None else (b - a) * (nj - 1) / (ni - 1)
    node = lambda I, J: (J - 1) * ni + I
    force = p * 2 * math.pi * a * h / (nj - 1)  # total ring force per bore node (half at the ends)
    lines = [f"$ {e}" for e in extension]
    lines += [f"THICK TUBE {a:g} < r < {b:g}, internal pressure {p:g}, plane strain ({ni} x {nj} grid)",
              control(numpc=0 if nodal else nj - 1), mesh_control(ni, nj, 4, 5 if nodal else 2, 1),
              seg([(1, 1, a, 0.0), (ni, 1, b, 0.0)], 1), seg([(ni, 1, b, 0.0), (ni, nj, b, h)], 1),
              seg([(ni, nj, b, h), (1, nj, a, h)], 1), seg([(1, nj, a, h), (1, 1, a, 0.0)], 1),
              bc(1, ni, 1, 1, 2), bc(1, ni, nj, nj, 2)]
    if nodal:
        lines += [bc(1, 1, 2, nj - 1, 0, force), bc(1, 1, 1, 1, 2, force / 2), bc(1, 1, nj, nj, 2, force / 2)]
    lines += [block(1, 1, ni, 1, nj)]
    lines += material(1, [isotropic(200000.0, nu, 1.2e-5)], density=7.85e-9, elastic_format=True)
    if not nodal:
        lines += [edge(node(1, J + 1), node(1, J), p, wide) for J in range(1, nj)]
    return "\n".join(lines) + "\n"


def helical_sleeve_deck():
    """A steel shaft (r < 20) with a two-ply +-30 degree wound composite sleeve (20 < r < 30), fixed at
    z = 0 and twisted by a transverse shear of 10 on its end face z = 100 (SAGA: needs u_theta)."""
    ni, nj = 7, 11
    node = lambda I, J: (J - 1) * ni + I
    lines = ["$ format = elastic",
             "$ Shaft with a helically wound sleeve in torsion: materials 1 steel, 2 composite (+-30 deg plies)",
             "SHAFT WITH +-30 DEG WOUND SLEEVE, END SHEAR 10 (TORSION)",
             control(nummat=2, numst=ni - 1), mesh_control(ni, nj, 4, 1, 2),
             segment([(1, 1, 0.0, 0.0), (ni, 1, 30.0, 0.0)], 1), segment([(ni, 1, 30.0, 0.0), (ni, nj, 30.0, 100.0)], 1),
             segment([(ni, nj, 30.0, 100.0), (1, nj, 0.0, 100.0)], 1), segment([(1, nj, 0.0, 100.0), (1, 1, 0.0, 0.0)], 1),
             bc(1, ni, 1, 1, 7), block(1, 1, 5, 1, nj), block(2, 5, ni, 1, nj, 0.0, 30.0, 1, 1)]
    lines += material(1, [isotropic(200000.0, 0.3)], elastic_format=True)
    lines += material(2, [(0.0, 140000.0, 10000.0, 10000.0, 0.3, 0.3, 0.4, 5000.0, 3500.0, 5000.0, 0.0, 0.0, 0.0)],
                      elastic_format=True)
    lines += [edge(node(I + 1, nj), node(I, nj), 10.0) for I in range(1, ni)]
    return "\n".join(lines) + "\n"


def two_tubes_deck(n=40, nz=80, a=1.0, b=1.5, gap=5e-4, c=2.0, h=None, p=100.0, steps=10, contact="saac",
                   extension=(), sigma_y=None, hardening=0.0, rate=None):
    """Two tubes across a radial gap (docs/theory.md V5, plane strain): inner a..b and outer b + gap..c, n x nz
    cells each, one column of gap elements (material 2, IJDIR = 1) between them, bore pressure ramped to
    p in `steps` equal steps (INCF = 0). E = 200000, nu = 0.3; the gap material is 1e-9 as stiff.
    Grid: I = 1..2n + 2 across, J = 1..nz + 1 up; h defaults to square cells of the inner tube.
    sigma_y: the inner tube yields (Mises, Prager hardening c = `hardening`); rate = (delta t, b, transition
    rate): a SAAC3 deck (card 0 first), Drysdale-Zak rate dependence in the inner tube."""
    h = h if h is not None else (b - a) * nz / n
    ni, nj = 2 * n + 2, nz + 1
    node = lambda I, J: (J - 1) * ni + I
    lines = [f"$ contact = {contact}"] + [f"$ {e}" for e in extension]
    if rate:
        lines += ["$ format = saac3", rate_card(*rate)]
    title_at = len(lines)
    lines += [f"TWO TUBES {a:g}-{b:g} AND {b + gap:g}-{c:g}, GAP {gap:g}, PRESSURE {p:g} IN {steps} STEPS",
              control(nummat=2 if sigma_y is None else 3, numpc=nz, nlinc=steps, incf=0), mesh_control(ni, nj, 8, 1, 3),
              segment([(1, 1, a, 0.0), (n + 1, 1, b, 0.0)], 1), segment([(n + 2, 1, b + gap, 0.0), (ni, 1, c, 0.0)], 1),
              segment([(1, nj, a, h), (n + 1, nj, b, h)], 1), segment([(n + 2, nj, b + gap, h), (ni, nj, c, h)], 1),
              segment([(1, 1, a, 0.0), (1, nj, a, h)], 1), segment([(n + 1, 1, b, 0.0), (n + 1, nj, b, h)], 1),
              segment([(n + 2, 1, b + gap, 0.0), (n + 2, nj, b + gap, h)], 1), segment([(ni, 1, c, 0.0), (ni, nj, c, h)], 1),
              bc(1, ni, 1, nj, 2), block(1, 1, n + 1, 1, nj), block(2, n + 1, n + 2, 1, nj, ijdir=1),
              block(1 if sigma_y is None else 3, n + 2, ni, 1, nj)]
    if sigma_y is None:
        lines += material(1, [isotropic(200000.0, 0.3)])
    else:  # the inner tube (material 1) yields (Mises); the outer tube (material 3) stays elastic
        k = sigma_y / math.sqrt(3.0)
        lines[title_at] = lines[title_at].replace("TWO TUBES", "PLASTIC TUBE IN A TUBE")
        lines += material(1, [isotropic(200000.0, 0.3)], yield_card=[sigma_y] * 3 + [k] * 3 + [hardening])
    lines += material(2, [isotropic(200000.0e-9, 0.0)])
    if sigma_y is not None:
        lines += material(3, [isotropic(200000.0, 0.3)])
    lines += [edge(node(1, J + 1), node(1, J), p / steps) for J in range(1, nj)]
    return "\n".join(lines) + "\n"


def rate_card(dt, b, rate0, strain_rate=0.0, shear_step=0.0):
    """Data 0 (SAAC3, SAAC3X): delta t, b, the transition strain rate, STRRATE, STRSTEP in 5E12.6."""
    return "".join(f"{x:12.5E}" for x in (dt, b, rate0, strain_rate, shear_step))


def plastic_tube_deck(ni=41, a=100.0, b=200.0, p=300.0, steps=15, sigma_y=400.0, plasticity="return-mapping",
                      extension=(), rate=None, nj=2, hardening=0.0):
    """Thick tube a..b (docs/theory.md V6), plane strain, nj - 1 square cells high (default one), Mises (Hill
    with equal yields, shear sigma_y / sqrt 3), Prager hardening c = `hardening` (card 11's C; 0: perfectly
    plastic), bore pressure ramped to p in `steps` equal steps (INCF = 0). Mises first yield at about 173
    and the limit (2 / sqrt 3) sigma_y ln(b / a) = 320.15 (sigma_y = 400).
    rate = (delta t, b, transition rate): a SAAC3 deck (card 0 first), Drysdale-Zak rate dependence."""
    h = (b - a) / (ni - 1) * (nj - 1)
    k = sigma_y / math.sqrt(3.0)
    lines = [f"$ plasticity = {plasticity}"] + [f"$ {e}" for e in extension]
    if rate:
        lines += ["$ format = saac3", rate_card(*rate)]
    title = f"PLASTIC TUBE {a:g} < r < {b:g}, SIGMA_Y {sigma_y:g}, PRESSURE {p:g} IN {steps} STEPS"
    if rate:
        title = f"RATE TUBE {a:g}-{b:g}, SIGMA_0 {sigma_y:g}, B {rate[1]:g}, {p:g} IN {steps} STEPS OF {rate[0]:g} S"
    ends = [bc(1, ni, 1, 2, 2)] if nj == 2 else [bc(1, ni, 1, 1, 2), bc(1, ni, nj, nj, 2)]  # u_z = 0
    lines += [title,
              control(numpc=nj - 1, nlinc=steps, incf=0), mesh_control(ni, nj, 4, len(ends), 1),
              segment([(1, 1, a, 0.0), (ni, 1, b, 0.0)], 1), segment([(ni, 1, b, 0.0), (ni, nj, b, h)], 1),
              segment([(ni, nj, b, h), (1, nj, a, h)], 1), segment([(1, nj, a, h), (1, 1, a, 0.0)], 1),
              *ends, block(1, 1, ni, 1, nj)]
    lines += material(1, [isotropic(200000.0, 0.3)],
                      yield_card=[sigma_y, sigma_y, sigma_y, k, k, k, hardening])
    lines += [edge(J * ni + 1, (J - 1) * ni + 1, p / steps) for J in range(1, nj)]
    return "\n".join(lines) + "\n"


def saac3x_deck(ri=999.0, ro=1000.0, length=1.0, dt=5e-5, steps=150, sigma_0=400.0, b=0.05, rate0=1e-3,
                strain_rate=1.0, shear_step=230.94, plasticity="return-mapping"):
    """SAAC3X (docs/theory.md 8.7; seed section 4.2): a thin-walled tube ri..ro, 0 <= z <= length (mm, MPa, s),
    one cell, Mises sigma_0 = 400 MPa, b = 0.05, rate_0 = 1e-3 / s, c = 0. Card 0's STRSTEP puts the shear
    stress tau = 230.94 MPa (just below the static shear yield sigma_0 / sqrt 3) on the top face in step 1,
    and STRRATE then pulls the top face at 1 / s (u_z = STRRATE L (t - dt)). No BC or load cards: the
    command drives both faces (docs/decks.md "SAAC3X"). dt = 5e-5 s is 0.73 relaxation times at the steady state."""
    k = sigma_0 / math.sqrt(3.0)
    lines = [f"$ plasticity = {plasticity}", "$ format = saac3",
             rate_card(dt, b, rate0, strain_rate, shear_step),
             f"SAAC3X THIN TUBE {ri:g}-{ro:g}: TAU {shear_step:g} THEN RATE {strain_rate:g}/S, {steps} STEPS OF {dt:g} S",
             control(nlinc=steps), mesh_control(2, 2, 4, 0, 1),
             segment([(1, 1, ri, 0.0), (2, 1, ro, 0.0)], 1), segment([(2, 1, ro, 0.0), (2, 2, ro, length)], 1),
             segment([(2, 2, ro, length), (1, 2, ri, length)], 1), segment([(1, 2, ri, length), (1, 1, ri, 0.0)], 1),
             block(1, 1, 2, 1, 2)]
    lines += material(1, [isotropic(200000.0, 0.3)], yield_card=[sigma_0, sigma_0, sigma_0, k, k, k, 0.0])
    return "\n".join(lines) + "\n"


def projectile_deck(steps=10, g_load=20000.0):
    """A projectile (mm, t, s, N, MPa): a steel cup (base 0 < z < 20, wall 30 < r < 40 up to z = 120)
    holding a separate filler insert (r < 29.9, 20.1 < z < 120; E = 3000, nu = 0.4, like a cast
    explosive) across a radial gap of 0.1 (gap elements closing along I) and an axial gap of 0.1 (closing
    along J), with the corner gap element where they meet. Setback: axial acceleration g_load x g, and
    the base pressure that drives it (total mass x acceleration / base area), both ramped in `steps`.
    The insert falls onto the base first, then bulges under its own weight and closes the radial gap
    from the bottom up. u_z = 0 at one node (the loads balance, so its reaction is ~0)."""
    r_in = [0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 29.9]
    rs = r_in + [30.0, 35.0, 40.0]
    zs = [0.0, 10.0, 20.0, 20.1] + [20.0 + 10.0 * k for k in range(1, 11)]
    ni, nj = len(rs), len(zs)
    node = lambda I, J: (J - 1) * ni + I
    steel, filler = 7.85e-9, 1.8e-9
    accel = g_load * 9810.0  # mm/s^2
    mass = steel * math.pi * (40.0 ** 2 * 20.0 + (40.0 ** 2 - 30.0 ** 2) * 100.0) + filler * math.pi * 29.9 ** 2 * 99.9
    p_base = mass * accel / (math.pi * 40.0 ** 2)
    segs = []
    for J, z in enumerate(zs, start=1):
        segs += [segment([(1, J, 0.0, z), (7, J, 29.9, z)], 1), segment([(7, J, 29.9, z), (8, J, 30.0, z)], 1),
                 segment([(8, J, 30.0, z), (10, J, 40.0, z)], 1)]
    lines = ["$ contact = augmented-lagrangian",
             "$ Projectile: 1 steel cup, 2 gap elements (IJDIR 2 under the insert, 1 beside it), 3 filler insert",
             f"PROJECTILE CUP AND FILLER, SETBACK {g_load:g} G, BASE PRESSURE {p_base:.1f}",
             control(nummat=3, numpc=ni - 1, inert=1, nlinc=steps, inci=0, incf=0),
             mesh_control(ni, nj, len(segs), 1, 5)] + segs
    lines += [bc(ni, ni, nj, nj, 2),
              block(1, 1, ni, 1, 3), block(1, 8, ni, 3, nj),      # steel base and wall
              block(2, 1, 8, 3, 4, ijdir=2),                      # axial gap row (and the corner)
              block(2, 7, 8, 4, nj, ijdir=1),                     # radial gap column
              block(3, 1, 7, 4, nj)]                              # filler
    lines += material(1, [isotropic(200000.0, 0.3)], density=steel)
    lines += material(2, [isotropic(0.3, 0.0)])
    lines += material(3, [isotropic(3000.0, 0.4)], density=filler)
    lines += [f(accel / steps, 10) + f(0.0, 10) + f(0.0, 10)]
    lines += [edge(node(I, 1), node(I + 1, 1), p_base / steps) for I in range(1, ni)]
    return "\n".join(lines) + "\n"


def press_fit_deck(ns=6, nh=8, nz=10, a=12.5, b=25.0, w=0.001, c=50.0, length=50.0, q=75.0, push=0.001,
                   steps=40, mu=0.15, contact="active-set", slip="coulomb", nu=0.0, events=None, ramp=False,
                   twist=None):
    """A hub clamped on a hollow shaft and pushed along it (the friction example; units mm, N, MPa).

    Shaft a..b (ns cells), a column of gap elements b..b + w (material 2, IJDIR = 1), hub b + w..c (nh
    cells), nz rows over the length. Step 1 presses the hub on by the pressure q on its outer surface
    (INCF = 1: its own pressure cards; the later steps' cards are zero); every step moves the hub's top
    face down by `push` (BC increments) while the shaft's bottom face is held. E = 200000 and nu = 0: with
    Poisson's ratio the hub's axial growth under the pressure, held at its pushed face, would already slide
    the whole fit in step 1 (nu = 0.3: 11 um), and the closed form is exact. `events` (locate or step-end)
    adds that option line. ramp=True: the pressure rises by q / steps in every step instead (INCF = 0), in
    the steps that push (the fit closes while it slides). twist (u_theta per step, a 3-DOF deck): every
    hub node is driven down by `push` and along theta by `twist` per step and every shaft node held (so
    the slide is uniform along the fit).
    Closed form (plane stress Lame, one material): contact pressure p = (q - q_c) c^2 (b^2 - a^2) /
    (b^2 (c^2 - a^2)), q_c = w E (c^2 - b^2) / (2 b c^2) closing the gap; slip force mu p 2 pi b L."""
    ni, nj = ns + nh + 2, nz + 1
    node = lambda I, J: (J - 1) * ni + I
    lines = [f"$ contact = {contact}", f"$ friction = {mu:g}", f"$ slip = {slip}"]
    lines += [f"$ events = {events}"] if events else []
    if twist is None:
        conditions = [bc(1, ns + 1, 1, 1, 2), bc(ns + 2, ni, nj, nj, 2, xz=-push)]
    else:
        conditions = [bc(1, ns + 1, 1, nj, 6), bc(ns + 2, ni, 1, nj, 6, xz=-push, xt=twist)]
    lines += [
             f"HUB {b + w:g}-{c:g} PRESSED ON SHAFT {a:g}-{b:g} BY {q:g} ON ITS OD, PUSHED DOWN {push:g} PER STEP"
             + (f", TURNED {twist:g}" if twist is not None else "") + (", PRESSURE RAMPED" if ramp else ""),
             control(nummat=2, numpc=nz, nlinc=steps, incf=0 if ramp else 1), mesh_control(ni, nj, 8, 2, 3),
             segment([(1, 1, a, 0.0), (ns + 1, 1, b, 0.0)], 1), segment([(ns + 2, 1, b + w, 0.0), (ni, 1, c, 0.0)], 1),
             segment([(1, nj, a, length), (ns + 1, nj, b, length)], 1),
             segment([(ns + 2, nj, b + w, length), (ni, nj, c, length)], 1),
             segment([(1, 1, a, 0.0), (1, nj, a, length)], 1), segment([(ns + 1, 1, b, 0.0), (ns + 1, nj, b, length)], 1),
             segment([(ns + 2, 1, b + w, 0.0), (ns + 2, nj, b + w, length)], 1),
             segment([(ni, 1, c, 0.0), (ni, nj, c, length)], 1),
             *conditions,
             block(1, 1, ns + 1, 1, nj), block(2, ns + 1, ns + 2, 1, nj, ijdir=1), block(1, ns + 2, ni, 1, nj)]
    lines += material(1, [isotropic(200000.0, nu)])
    lines += material(2, [isotropic(200000.0e-9, 0.0)])
    for step in range(1, 2 if ramp else steps + 1):
        lines += [edge(node(ni, J), node(ni, J + 1), q / steps if ramp else q if step == 1 else 0.0)
                  for J in range(1, nj)]
    return "\n".join(lines) + "\n"


def shrink_fit_deck(ns=10, nh=20, nz=1, b=25.0, w=0.01, c=50.0, h=2.5, cooling=100.0, omega=0.0, steps=1,
                    contact="saac", E=200000.0, nu=0.3, alpha=1.2e-5, rho=7.85e-9):
    """A hub b + w..c cooled by `cooling` onto a solid steel shaft 0..b across a column of gap elements
    (material 2, IJDIR = 1), then spun up to `omega` [rad/s] (units mm, N, MPa, t; plane strain: u_z = 0 on
    both faces). The temperature field is given at every node (card 9, one card a node: the shaft at 0, the
    hub at -cooling, T_ref = 0), which a deck applies in its first load step; the spin rises by omega / steps
    in every step (INCI = 0), so omega^2 grows quadratically with the step. bench/closed_forms.py has its
    closed form (Lame in plane strain with the temperature change and the spin): with the defaults the cold
    contact pressure is 95.6 and the fit lifts off at 3,893 rad/s."""
    ni, nj = ns + nh + 2, nz + 1
    rs = [b * i / ns for i in range(ns + 1)] + [b + w + (c - b - w) * k / nh for k in range(nh + 1)]
    temperatures = [f(rs[I - 1], 10) + f(h * (J - 1) / nz, 10) + f(0.0 if I <= ns + 1 else -cooling, 10)
                    for J in range(1, nj + 1) for I in range(1, ni + 1)]
    lines = [f"$ contact = {contact}",
             f"SHRINK FIT: HUB {b + w:g}-{c:g} COOLED BY {cooling:g} ONTO A SOLID SHAFT 0-{b:g}, SPUN TO {omega:g} RAD/S",
             control(numtc=len(temperatures), nummat=2, inert=1 if omega else 0, nlinc=steps),
             mesh_control(ni, nj, 8, 2, 3),
             segment([(1, 1, 0.0, 0.0), (ns + 1, 1, b, 0.0)], 1), segment([(ns + 2, 1, b + w, 0.0), (ni, 1, c, 0.0)], 1),
             segment([(1, nj, 0.0, h), (ns + 1, nj, b, h)], 1), segment([(ns + 2, nj, b + w, h), (ni, nj, c, h)], 1),
             segment([(1, 1, 0.0, 0.0), (1, nj, 0.0, h)], 1), segment([(ns + 1, 1, b, 0.0), (ns + 1, nj, b, h)], 1),
             segment([(ns + 2, 1, b + w, 0.0), (ns + 2, nj, b + w, h)], 1), segment([(ni, 1, c, 0.0), (ni, nj, c, h)], 1),
             bc(1, ni, 1, 1, 2), bc(1, ni, nj, nj, 2),
             block(1, 1, ns + 1, 1, nj), block(2, ns + 1, ns + 2, 1, nj, ijdir=1), block(1, ns + 2, ni, 1, nj)]
    lines += temperatures
    lines += material(1, [isotropic(E, nu, alpha)], density=rho)
    lines += material(2, [isotropic(E * 1e-9, 0.0)])
    if omega:
        lines += [f(0.0, 10) + f(omega / steps, 10) + f(0.0, 10)]
    return "\n".join(lines) + "\n"


def press_fit_normal_force(a=12.5, b=25.0, w=0.001, c=50.0, length=50.0, q=75.0, E=200000.0):
    """press_fit_deck's closed form (nu = 0): the normal force N = p 2 pi b L the fit carries under the outer
    pressure q, p = (q - q_c) c^2 (b^2 - a^2) / (b^2 (c^2 - a^2)) with q_c = w E (c^2 - b^2) / (2 b c^2) the
    pressure that closes the gap (0 below it); mu N is the push-out force at full slip."""
    qc = w * E * (c * c - b * b) / (2 * b * c * c)
    return max(q - qc, 0.0) * c * c * (b * b - a * a) / (b * b * (c * c - a * a)) * 2 * math.pi * b * length


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="what", required=True)
    t = sub.add_parser("tube")
    t.add_argument("--ni", type=int, required=True)
    t.add_argument("--nj", type=int, required=True)
    t.add_argument("--nodal", action="store_true", help="pressure as BC-card ring forces (for > 99999 nodes)")
    t.add_argument("--wide", action="store_true", help="`$ fields = wide`: grid indices > 999, nodes > 99999")
    tt = sub.add_parser("two-tubes")
    tt.add_argument("--n", type=int, default=40)
    tt.add_argument("--nz", type=int, default=80)
    tt.add_argument("--steps", type=int, default=10)
    tt.add_argument("--contact", default="saac")
    pf = sub.add_parser("press-fit")
    pf.add_argument("--steps", type=int, default=40)
    pf.add_argument("--slip", default="coulomb")
    pf.add_argument("--contact", default="augmented-lagrangian")
    sub.add_parser("examples")
    args = ap.parse_args()
    if args.what == "tube":
        print(tube_deck(args.ni, args.nj, nodal=args.nodal, wide=args.wide), end="")
    elif args.what == "press-fit":
        print(press_fit_deck(steps=args.steps, push=0.04 / args.steps, slip=args.slip, contact=args.contact), end="")
    elif args.what == "two-tubes":
        print(two_tubes_deck(args.n, args.nz, steps=args.steps, contact=args.contact), end="")
    else:
        out = pathlib.Path(__file__).resolve().parent.parent / "examples" / "decks"
        out.mkdir(exist_ok=True)
        (out / "thick_tube.deck").write_text(tube_deck(9, 3, h=10.0))
        (out / "thick_tube_wide.deck").write_text(tube_deck(9, 3, h=10.0, wide=True))  # `$ fields = wide`
        (out / "helical_sleeve.deck").write_text(helical_sleeve_deck())
        (out / "two_tubes.deck").write_text(two_tubes_deck(n=20, nz=2, a=50.0, b=75.0, gap=0.02, c=100.0,
                                                           steps=20, contact="active-set"))
        (out / "projectile.deck").write_text(projectile_deck())
        (out / "press_fit.deck").write_text(press_fit_deck())
        (out / "push_while_pressing.deck").write_text(press_fit_deck(mu=0.2, ramp=True))
        (out / "shrink_fit.deck").write_text(shrink_fit_deck(omega=5000.0, steps=25))
        (out / "plastic_tube.deck").write_text(plastic_tube_deck())
        (out / "rate_tube.deck").write_text(plastic_tube_deck(rate=(1e-3, 0.05, 1e-3)))
        (out / "saac3x_tube.deck").write_text(saac3x_deck())
        (out / "plastic_two_tubes.deck").write_text(two_tubes_deck(n=20, nz=2, a=50.0, b=75.0, gap=0.02, c=100.0,
                                                                   p=200.0, steps=20, sigma_y=250.0,
                                                                   extension=("plasticity = return-mapping",)))


if __name__ == "__main__":
    main()
