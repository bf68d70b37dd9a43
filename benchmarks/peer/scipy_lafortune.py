#!/usr/bin/env python3
"""The peer of `clothfit bench`: the per-texel Lafortune fit done
the way a user would do it today without clothfit - SciPy's least_squares
(trust-region reflective, bounds, finite-difference Jacobians) per texel and
channel, no lookup table.

    scipy_lafortune.py TRAIN.csv TEST.csv LOBES

TRAIN/TEST are clothfit measurement tables (docs/formats.md) with s,t texel
columns and wi_x..wo_z direction columns, cosine-weighted values r,g,b.
Model (Daubert et al. 2001, eq. 2; models/lafortune.h):
    f1(l, v) = l.z (rho_d + sum_k [Cx lx vx + Cy ly vy + Cz lz vz]^N)
with the same start (the paper's) and bounds as clothfit:
rho_d in [0, 1000], |C| <= 3, N in [0.5, 200].
Prints one JSON object: seconds (the fits only), fits, value_error (mean over
texels of the relative RMS at the TEST rows), the solver's evaluations.
Exits 3 when SciPy is missing (the bench then says so and skips the peer).
"""
import json
import sys
import time

try:
    import numpy as np
    from scipy.optimize import least_squares

    from peer_table import read_columns
except ImportError:  # the bench skips the peer with a message
    sys.stderr.write("scipy_lafortune: SciPy/NumPy not available\n")
    sys.exit(3)


def f1(x, lobes, xx, yy, zz, lz):
    total = np.full_like(xx, x[0])
    for k in range(lobes):
        cx, cy, cz, n = x[1 + 4 * k: 5 + 4 * k]
        a = cx * xx + cy * yy + cz * zz
        total += np.where(a > 0.0, np.abs(a) ** n, 0.0)
    return np.maximum(lz, 0.0) * total


def paper_start(lobes):
    """Grey diffuse 0.5, a moderate highlight, slightly anisotropic lobes
    (Cx = 1.22 Cy for the first, Cy = 1.22 Cx for the second)."""
    x = [0.5]
    for k in range(lobes):
        ax, ay = (1.22, 1.0) if k % 2 == 0 else (1.0, 1.22)
        x += [-ax, -ay, 1.0, 10.0]
    return np.array(x)


def bounds(lobes):
    lo, hi = [0.0], [1000.0]
    for _ in range(lobes):
        lo += [-3.0, -3.0, -3.0, 0.5]
        hi += [3.0, 3.0, 3.0, 200.0]
    return np.array(lo), np.array(hi)


def terms(t, rows):
    return (t["wi_x"][rows] * t["wo_x"][rows], t["wi_y"][rows] * t["wo_y"][rows],
            t["wi_z"][rows] * t["wo_z"][rows], t["wi_z"][rows])


def main():
    train, test, lobes = read_columns(sys.argv[1]), read_columns(sys.argv[2]), int(
        sys.argv[3])
    texels = sorted(set(zip(train["s"].astype(int), train["t"].astype(int))))
    lo, hi = bounds(lobes)
    errors, evaluations, fits = [], 0, 0
    seconds = 0.0
    for s, t in texels:
        rows = (train["s"] == s) & (train["t"] == t)
        test_rows = (test["s"] == s) & (test["t"] == t)
        xx, yy, zz, lz = terms(train, rows)
        txx, tyy, tzz, tlz = terms(test, test_rows)
        se = ss = 0.0
        for channel in "rgb":
            y = train[channel][rows]
            start = time.perf_counter()
            result = least_squares(
                lambda x: f1(x, lobes, xx, yy, zz, lz) - y,
                np.clip(paper_start(lobes), lo, hi), bounds=(lo, hi),
                method="trf")
            seconds += time.perf_counter() - start
            evaluations += result.nfev
            fits += 1
            model = f1(result.x, lobes, txx, tyy, tzz, tlz)
            truth = test[channel][test_rows]
            se += float(np.sum((model - truth) ** 2))
            ss += float(np.sum(truth ** 2))
        errors.append(np.sqrt(se / ss) if ss > 0 else 0.0)
    print(json.dumps({"seconds": seconds, "fits": fits,
                      "texels": len(texels),
                      "value_error": float(np.mean(errors)),
                      "evaluations": evaluations}))


if __name__ == "__main__":
    main()
