"""scripts/bspline_wall_quadrature: the point quadrature error of quadratic B-splines next
to a wall, in 1D (see the script's header)."""
import numpy as np

H = 20


def basis(knots, x):
    """Values and derivatives of all quadratic B-splines of a knot vector at x."""
    n = len(knots) - 3
    N, D = np.zeros(n), np.zeros(n)
    for i in range(n):
        t = knots[i:i + 4]
        if t[0] <= x < t[1]:
            den = (t[2] - t[0]) * (t[1] - t[0])
            N[i], D[i] = (x - t[0]) ** 2 / den, 2 * (x - t[0]) / den
        elif t[1] <= x < t[2]:
            A, B = (t[2] - t[0]) * (t[2] - t[1]), (t[3] - t[1]) * (t[2] - t[1])
            N[i] = (x - t[0]) * (t[2] - x) / A + (t[3] - x) * (x - t[1]) / B
            D[i] = (t[2] + t[0] - 2 * x) / A + (t[3] + t[1] - 2 * x) / B
        elif t[2] <= x < t[3]:
            den = (t[3] - t[1]) * (t[3] - t[2])
            N[i], D[i] = (t[3] - x) ** 2 / den, -2 * (t[3] - x) / den
    return N, D


def errors(knots, x, V):
    B = np.array([basis(knots, p)[1] for p in x])
    Nm = np.array([basis(knots, p)[0] for p in x])
    K, f = B.T @ (V[:, None] * B), -(Nm * V[:, None]).sum(0)
    wall = basis(knots, 0.0)[0]
    free = [i for i in range(len(f)) if wall[i] == 0 and K[i, i] > 0]
    u = np.zeros(len(f))
    u[free] = np.linalg.solve(K[np.ix_(free, free)], f[free])
    e = np.abs(B @ u + (H - x))
    return e[x < 3].max(), e[(x > 3) & (x < 17)].max()


def placement(knots, n, gauss):
    if not gauss:
        x = np.array([c + (j + 0.5) / n for c in range(H) for j in range(n)])
        return x, np.full(len(x), 1.0 / n)
    g, w = np.polynomial.legendre.leggauss(n)
    cuts = sorted({0.0, float(H)} | {t for t in knots if 0 < t < H})
    x = [a + (b - a) * (1 + gi) / 2 for a, b in zip(cuts, cuts[1:]) for gi in g]
    V = [(b - a) * wi / 2 for a, b in zip(cuts, cuts[1:]) for wi in w]
    return np.array(x), np.array(V)


def main(argv, script):
    """Prints the table (arguments are ignored, as they always were)."""
    top = H + 3
    knot_vectors = [
        ("clamped 0,0,0,1/2,3/2,... (the solver's)", [0, 0, 0] + [k + 0.5 for k in range(top)]),
        ("0,0,0,3/2,5/2,... (h/2 knot dropped)", [0, 0, 0] + [k + 0.5 for k in range(1, top)]),
        ("0,0,0,1,2,... (nodes at cell centres)", [0, 0, 0] + list(range(1, top))),
    ]
    print("| knot vector | placement | points per cell | error, first 3 cells | error, inside |")
    print("|---|---|---|---|---|")
    for label, k in knot_vectors:
        k = np.array(k, float)
        for gauss in (False, True):
            for n in (2, 3, 4):
                near, inside = errors(k, *placement(k, n, gauss))
                print(f"| {label} | {'gauss' if gauss else 'cells'} | {n} | {near:.2g} | {inside:.2g} |")
    return 0
