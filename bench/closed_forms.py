#!/usr/bin/env python3
"""Closed forms the tests and the benchmarks share: compound cylinders in plane strain (Lame with a uniform
temperature change and a spin in each body), for fits that a gap, a temperature or a spin closes and opens.

Each annulus r1 <= r <= r2 (r1 = 0: a solid shaft) has u = A r + B / r - kappa r^3 / 8 with kappa = rho omega^2
/ (lambda + 2 G), the particular solution of the spin's body force rho omega^2 r; a uniform temperature change
dT only enters the stresses, sigma_r = (lambda + 2 G) u' + lambda u / r - (3 lambda + 2 G) alpha dT (eps_z = 0).
A fit of a shaft and a hub across the gap w is closed with the contact pressure p that makes the gap zero, or
open with the gap its free bodies leave. Units: those of the inputs (the tests use mm, N, MPa, t, s).
"""
import numpy as np

E, NU, ALPHA, RHO = 200000.0, 0.3, 1.2e-5, 7.85e-9  # steel in mm, N, MPa, t


def annulus(r1, r2, dT=0.0, rho=RHO, omega=0.0):
    """u(r) and sigma_r(r) of an annulus as (coefficient of A, of B, constant) for u = A r + B / r - kappa r^3 / 8."""
    lam, G = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
    kappa = rho * omega ** 2 / (lam + 2 * G)
    u = lambda r: (r, 1 / r if r > 0 else 0.0, -kappa * r ** 3 / 8)
    # sigma_r = (lambda + 2 G) eps_r + lambda eps_theta - (3 lambda + 2 G) alpha dT, eps_r = u', eps_theta = u / r
    sigma_r = lambda r: (2 * lam + 2 * G, -2 * G / r ** 2 if r > 0 else 0.0,
                         -(4 * lam + 6 * G) * kappa * r ** 2 / 8 - (3 * lam + 2 * G) * ALPHA * dT)
    return dict(r1=r1, r2=r2, u=u, s=sigma_r)


def fit(shaft, hub, w, p_out=0.0, u_bore=None, branch=None):
    """The fit's state: closed with contact pressure p, or open with its gap (u_h(b + w) - u_s(b) + w);
    `branch` "open" or "closed" forces one (the gap or pressure it would have)."""
    def solve(closed):  # unknowns A_s, B_s, A_h, B_h, p
        rows, rhs = [], []
        add = lambda coefficients, value: (rows.append(coefficients), rhs.append(value))
        a, b, c = shaft["s"](shaft["r2"]); add([a, b, 0, 0, 1 if closed else 0], -c)  # sigma_r,s(b) = -p
        a, b, c = hub["s"](hub["r1"]); add([0, 0, a, b, 1 if closed else 0], -c)      # sigma_r,h(b + w) = -p
        a, b, c = hub["s"](hub["r2"]); add([0, 0, a, b, 0], -p_out - c)              # sigma_r,h(c) = -p_out
        if shaft["r1"] == 0:
            add([0, 1, 0, 0, 0], 0.0)  # a solid shaft: B_s = 0
        elif u_bore is not None:
            a, b, c = shaft["u"](shaft["r1"]); add([a, b, 0, 0, 0], u_bore - c)
        else:
            a, b, c = shaft["s"](shaft["r1"]); add([a, b, 0, 0, 0], -c)  # a free bore
        if closed:  # u_h(b + w) - u_s(b) = -w
            ah, bh, ch = hub["u"](hub["r1"]); as_, bs, cs = shaft["u"](shaft["r2"])
            add([-as_, -bs, ah, bh, 0], -w - ch + cs)
        else:
            add([0, 0, 0, 0, 1], 0.0)
        As, Bs, Ah, Bh, p = np.linalg.solve(np.array(rows), np.array(rhs))
        value = lambda body, A, B, r: np.dot(body["u"](r), (A, B, 1.0))
        gap = w + value(hub, Ah, Bh, hub["r1"]) - value(shaft, As, Bs, shaft["r2"])
        return dict(closed=closed, p=p if closed else 0.0, gap=0.0 if closed else gap)
    if branch:
        return solve(branch == "closed")
    state = solve(False)
    return state if state["gap"] >= 0 else solve(True)


