"""The L2 error of a run's radial displacement against a closed form, integrated over the VTU's cells with the
cells' own shape functions (tests/check_quadratic.py, bench/quadratic_cost.py): 4-node quadrangles, 8-node
quadrangles (serendipity) on 4 x 4 Gauss points, 6-node triangles on 5 x 5 Gauss points of the collapsed
square. Reads what meshio reads, so the VTU's quadratic cells are checked against a real reader too.
"""
import math

import numpy as np


def quad4_shapes(xi, eta):
    corners = [(-1, -1), (1, -1), (1, 1), (-1, 1)]
    n = [0.25 * (1 + a * xi) * (1 + b * eta) for a, b in corners]
    return np.array(n), np.array([[0.25 * a * (1 + b * eta) for a, b in corners],
                                  [0.25 * b * (1 + a * xi) for a, b in corners]])


def quad8_shapes(xi, eta):
    corners = [(-1, -1), (1, -1), (1, 1), (-1, 1)]
    n = [0.25 * (1 + a * xi) * (1 + b * eta) * (a * xi + b * eta - 1) for a, b in corners]
    n += [0.5 * (1 - xi * xi) * (1 - eta), 0.5 * (1 + xi) * (1 - eta * eta), 0.5 * (1 - xi * xi) * (1 + eta),
          0.5 * (1 - xi) * (1 - eta * eta)]
    dxi = [0.25 * a * (1 + b * eta) * (2 * a * xi + b * eta) for a, b in corners]
    dxi += [-xi * (1 - eta), 0.5 * (1 - eta * eta), -xi * (1 + eta), -0.5 * (1 - eta * eta)]
    deta = [0.25 * b * (1 + a * xi) * (a * xi + 2 * b * eta) for a, b in corners]
    deta += [-0.5 * (1 - xi * xi), -eta * (1 + xi), 0.5 * (1 - xi * xi), -eta * (1 - xi)]
    return np.array(n), np.array([dxi, deta])


def tri6_shapes(s, t):
    l1, l2, l3 = 1 - s - t, s, t
    n = [l1 * (2 * l1 - 1), l2 * (2 * l2 - 1), l3 * (2 * l3 - 1), 4 * l1 * l2, 4 * l2 * l3, 4 * l3 * l1]
    ds = [1 - 4 * l1, 4 * l2 - 1, 0, 4 * (l1 - l2), 4 * l3, -4 * l3]
    dt = [1 - 4 * l1, 0, 4 * l3 - 1, -4 * l2, 4 * l2, 4 * (l1 - l3)]
    return np.array(n), np.array([ds, dt])


def rules():
    """Quadrature on the reference square (4 x 4 Gauss) and triangle (Gauss on the collapsed square, 5 x 5)."""
    x, w = np.polynomial.legendre.leggauss(4)
    square = [(a, b, wa * wb) for a, wa in zip(x, w) for b, wb in zip(x, w)]
    x, w = np.polynomial.legendre.leggauss(5)
    triangle = []
    for a, wa in zip(x, w):
        for b, wb in zip(x, w):
            u, v = (a + 1) / 2, (b + 1) / 2  # Duffy: s = u, t = v (1 - u)
            triangle.append((u, v * (1 - u), wa * wb * (1 - u) / 4))
    return {"quad": (square, quad4_shapes), "quad8": (square, quad8_shapes), "triangle6": (triangle, tri6_shapes)}


RULES = rules()


def radial_error(mesh, exact):
    """(L2 error of u_r, cells, their kinds) of a meshio mesh against exact(r): sqrt of the integral of
    (u_h - u)^2 2 pi r dA per unit height of the section (a deck's grid of square cells is as high as two of
    its cells); cells of other kinds are counted in the kinds only."""
    u = mesh.point_data["displacement"][:, 0]
    err, cells, kinds = 0.0, 0, set()
    for block in mesh.cells:
        kinds.add(block.type)
        if block.type not in RULES:
            continue
        rule, shapes = RULES[block.type]
        for nodes in block.data:
            x = mesh.points[nodes, :2]
            for s, t, w in rule:
                n, dn = shapes(s, t)
                jac = dn @ x
                r = n @ x[:, 0]
                d = n @ u[nodes] - exact(r)
                err += d * d * 2 * math.pi * r * abs(np.linalg.det(jac)) * w
            cells += 1
    height = mesh.points[:, 1].max() - mesh.points[:, 1].min()
    return math.sqrt(err / height), cells, kinds


