#!/usr/bin/env python3
"""The peer of `clothfit bench` for the thread, cloth, slab and
holes fits: the same synthetic problems fitted the way a user would without
clothfit - the model formulas of docs/models.md in NumPy and SciPy's
least_squares (trust-region reflective, bounds, finite-difference
Jacobian), from the same start, with the same bounds, free parameters and
sigma-normalised residuals.

    scipy_models.py fit MODEL SPEC.json TRAIN.csv HELD.csv [REPEATS]
    scipy_models.py check MODEL PARAMS.json TABLE.csv

MODEL: thread, cloth, slab or holes (Algorithm 3.1 on the whole tile: the
parameter file also holds the tile's nine "counts" and "texels"). SPEC.json (written by the bench): "params"
(a parameter file, docs/formats.md: the start, with the cloth's weave),
"truth" (a parameter file of the true values), "names", "lower", "upper",
"free" (the parameter vector as clothfit's fit report lists it; the start
and true values are read from the files by these names). TRAIN.csv: the table to
fit; HELD.csv: held-out directions with the true model's values. `fit`
solves REPEATS times (default 1; one Python start for all) and prints one
JSON object: seconds_each (each solve's time, the solve only), seconds
(their median), value_error (relative RMS at HELD), param_error (largest
relative error of a free parameter), nfev, success. `check` prints the largest relative difference between the
table's values and this model at PARAMS (a test compares it with
clothfit's). Exits 3 when SciPy/NumPy are missing.
"""
import json
import math
import re
import sys
import time

try:
    import numpy as np
    from scipy.optimize import least_squares

    from peer_table import read_columns
except ImportError:  # the bench skips the peer with a message
    sys.stderr.write("scipy_models: SciPy/NumPy not available\n")
    sys.exit(3)


def read_table(path):
    """A clothfit table: (wi, wo) as n x 3 arrays, values n x 3, sigma."""
    col = read_columns(path)

    rows = len(next(iter(col.values())))

    def direction(prefix, theta, phi):
        if prefix + "_x" not in col and theta not in col:
            # A transmittance table may leave out the light: +z (docs/formats.md).
            return np.tile([0.0, 0.0, 1.0], (rows, 1))
        if prefix + "_x" in col:
            v = np.stack([col[prefix + "_" + a] for a in "xyz"], axis=1)
            return v / np.linalg.norm(v, axis=1, keepdims=True)
        t, p = np.radians(col[theta]), np.radians(col[phi])
        return np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p),
                         np.cos(t)], axis=1)

    wi = direction("wi", "theta_i", "phi_i")
    wo = direction("wo", "theta_o", "phi_o")
    if "r" in col:
        values = np.stack([col["r"], col["g"], col["b"]], axis=1)
    else:
        values = np.repeat(col["value"][:, None], 3, axis=1)
    if "sigma_r" in col:
        sigma = np.stack([col["sigma_r"], col["sigma_g"], col["sigma_b"]], 1)
    elif "sigma" in col:
        sigma = np.repeat(col["sigma"][:, None], 3, axis=1)
    else:
        sigma = np.ones_like(values)
    return wi, wo, values, sigma


# --- Thread (docs/models.md; Sadeghi et al. 2013, eq. 2-4) -----------------------

def gaussian(s, x):
    return np.exp(-x * x / (2.0 * s * s)) / (s * math.sqrt(2.0 * math.pi))


def fresnel(cos_theta, eta):
    c = np.clip(cos_theta, 0.0, 1.0)
    g = np.sqrt(eta * eta - 1.0 + c * c)
    return 0.5 * (g - c) ** 2 / (g + c) ** 2 * (
        1.0 + (c * (g + c) - 1.0) ** 2 / (c * (g - c) + 1.0) ** 2)


def dot(a, b):
    return np.sum(a * b, axis=1)


def angle_between(a, b):
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), dot(a, b))


def masking(cos_i, cos_o, angle_d):
    """M or P of docs/models.md (0 unless both cosines are positive)."""
    u = np.exp(-angle_d ** 2 / (2.0 * math.radians(20.0) ** 2))
    both = (cos_i > 0.0) & (cos_o > 0.0)
    m = (1.0 - u) * cos_i * cos_o + u * np.minimum(cos_i, cos_o)
    return np.where(both, m, 0.0)


def geometry(t, n, wi, wo):
    """The angles of docs/models.md for tangent t and normal n (arrays n x 3)."""
    g = {}
    sin_i, sin_o = wi @ t, wo @ t
    pi, po = wi - np.outer(sin_i, t), wo - np.outer(sin_o, t)
    b = np.cross(t, n)
    qi = wi - np.outer(wi @ b, b)
    qo = wo - np.outer(wo @ b, b)
    pi2, po2, qi2, qo2 = dot(pi, pi), dot(po, po), dot(qi, qi), dot(qo, qo)
    g["valid"] = (pi2 > 1e-24) & (po2 > 1e-24)
    g["psi_valid"] = g["valid"] & (qi2 > 1e-24) & (qo2 > 1e-24)
    cos_i, cos_o = np.sqrt(np.maximum(pi2, 1e-300)), np.sqrt(
        np.maximum(po2, 1e-300))
    g["cos_theta_i"], g["cos_theta_o"] = cos_i, cos_o
    theta_i = np.arcsin(np.clip(sin_i, -1.0, 1.0))
    theta_o = np.arcsin(np.clip(sin_o, -1.0, 1.0))
    g["theta_h"] = 0.5 * (theta_i + theta_o)
    g["cos2_theta_d"] = np.cos(0.5 * (theta_i - theta_o)) ** 2
    cos_phi_d = np.clip(dot(pi, po) / (cos_i * cos_o), -1.0, 1.0)
    g["cos_half_phi_d"] = np.sqrt(np.maximum(0.5 * (1.0 + cos_phi_d), 0.0))
    g["cos_phi_i"], g["cos_phi_o"] = (pi @ n) / cos_i, (po @ n) / cos_o
    g["phi_d"] = angle_between(pi, po)
    qi_len = np.sqrt(np.maximum(qi2, 1e-300))
    qo_len = np.sqrt(np.maximum(qo2, 1e-300))
    g["cos_psi_i"], g["cos_psi_o"] = (qi @ n) / qi_len, (qo @ n) / qo_len
    g["psi_d"] = angle_between(qi, qo)
    return g


def thread_bsdf(p, g):
    """f_s (n x 3) of docs/models.md; 0 where the geometry is undefined."""
    fr = fresnel(np.sqrt(g["cos2_theta_d"]) * g["cos_half_phi_d"], p["eta"])
    inv_cos2 = 1.0 / g["cos2_theta_d"]
    th = g["theta_h"]
    surface = fr * g["cos_half_phi_d"] * inv_cos2 * gaussian(
        math.radians(p["gamma_s_deg"]), th)
    volume = (1.0 - fr) ** 2 * inv_cos2 / (
        g["cos_theta_i"] + g["cos_theta_o"]) * (
        (1.0 - p["kd"]) * gaussian(math.radians(p["gamma_v_deg"]), th) +
        p["kd"])
    f = surface[:, None] + np.outer(volume, p["albedo"])
    return np.where(g["valid"][:, None], f, 0.0)


def thread_model(p, wi, wo):
    """A thread table (thread frame: t = +x, normal +z)."""
    g = geometry(np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0]), wi, wo)
    return p.get("scale", 1.0) * thread_bsdf(p, g)


# --- Cloth (docs/models.md; eq. 5-13) --------------------------------------------

def cloth_model(p, wi, wo):
    """f = rho / wi.z of a cloth patch (reflection rows)."""
    z = np.array([0.0, 0.0, 1.0])
    numerator = np.zeros((len(wi), 3))
    q = np.zeros(len(wi))
    coverage_sum = 0.0
    for th in p["threads"]:
        d = np.array([1.0, 0.0, 0.0] if th["direction"] == "u"
                     else [0.0, 1.0, 0.0])
        s_j = np.zeros((len(wi), 3))
        w_j = np.zeros(len(wi))
        offsets = np.array(th["offsets_deg"]) * th.get("offset_scale", 1.0)
        for offset in offsets:
            psi = math.radians(offset)
            t = math.cos(psi) * d + math.sin(psi) * z
            n = math.cos(psi) * z - math.sin(psi) * d
            g = geometry(t, n, wi, wo)
            ok = g["psi_valid"]
            reweight = np.where(ok, masking(g["cos_psi_i"], g["cos_psi_o"],
                                            g["psi_d"]), 0.0)
            weight = masking(g["cos_phi_i"], g["cos_phi_o"], g["phi_d"]) * \
                reweight * g["cos_theta_i"]
            s_j += thread_bsdf(th, g) * np.where(ok, weight, 0.0)[:, None]
            w_j += reweight
        s_j /= len(offsets)
        w_j /= len(offsets)
        numerator += th["coverage"] * s_j
        q += th["coverage"] * w_j
        coverage_sum += th["coverage"]
    q += (1.0 - coverage_sum) * wi[:, 2]
    safe_q = np.where(q > 0.0, q, 1.0)
    rho = np.where((q > 0.0)[:, None], numerator / safe_q[:, None], 0.0)
    return p.get("scale", 1.0) * rho / wi[:, 2:3]


# --- Slab (docs/models.md; single scattering) ------------------------------------

def slab_model(p, wi, wo):
    tau = np.broadcast_to(np.asarray(p["tau"], dtype=float), (3,))
    a = np.asarray(p["albedo"], dtype=float) / (4.0 * math.pi)
    mu_i, mu_o = np.abs(wi[:, 2:3]), np.abs(wo[:, 2:3])
    reflect = a * (1.0 - np.exp(-tau * (1.0 / mu_i + 1.0 / mu_o))) / (
        mu_i + mu_o)
    diff = mu_o - mu_i
    close = np.abs(diff) < 1e-9
    safe = np.where(close, 1.0, diff)
    transmit = np.where(
        close, a * tau / mu_i ** 2 * np.exp(-tau / mu_i),
        a * (np.exp(-tau / mu_o) - np.exp(-tau / mu_i)) / safe)
    same_side = (wi[:, 2:3] * wo[:, 2:3]) > 0.0
    return p.get("scale", 1.0) * np.where(same_side, reflect, transmit)


# --- Holes (docs/models.md, Algorithm 3.1 on the whole tile) -----------------------

def holes_model(p, wi, wo):
    """Transmittance of a holed layer: Algorithm 3.1 on the tile's nine
    counts ("counts": walls top/left/bottom/right, triangles topRight/
    topLeft/bottomLeft/bottomRight, opaques; "texels": the tile's area),
    which is linear in the counts, so the tile is one texel of them."""
    c = np.asarray(p["counts"], dtype=float)
    texels = float(p["texels"])
    h = float(p["thickness_texels"])
    z = np.maximum(np.abs(wo[:, 2]), 1e-9)
    rx = np.clip(-h * wo[:, 0] / z, -1.0, 1.0)
    ry = np.clip(-h * wo[:, 1] / z, -1.0, 1.0)
    right, left, top, bottom = rx > 0, rx < 0, ry > 0, ry < 0
    h_walls = np.where(right, c[3], np.where(left, c[1], 0.0))
    v_walls = np.where(top, c[0], np.where(bottom, c[2], 0.0))
    d = np.select([right & top, right & bottom, left & top, left & bottom],
                  [c[4], c[7], c[5], c[6]], 0.0)
    ax, ay = np.abs(rx), np.abs(ry)
    half = 0.5 * ax * ay
    occluded = (h_walls * (ax - half) + v_walls * (ay - half) + d * half) / (
        texels)
    transparent = 1.0 - occluded - c[8] / texels
    wall = np.broadcast_to(np.asarray(p.get("wall_color", 0.0), dtype=float),
                           (3,))
    return transparent[:, None] + wall * occluded[:, None]


MODELS = {"thread": thread_model, "cloth": cloth_model, "slab": slab_model,
          "holes": holes_model}


# --- Parameter vectors as clothfit's fit report names them ------------------

CHANNEL = {"_r": 0, "_g": 1, "_b": 2}


def set_named(p, name, value):
    """Sets `name` ("kd", "albedo_g", "threads[1].gamma_s_deg", "tau") in
    the parameter dict p."""
    m = re.match(r"threads\[(\d+)\]\.(.*)", name)
    if m:
        p, name = p["threads"][int(m.group(1))], m.group(2)
    key, channel = name, None
    if name[-2:] in CHANNEL and name[:-2] in ("albedo", "tau", "wall_color"):
        key, channel = name[:-2], CHANNEL[name[-2:]]
    if channel is None:
        p[key] = value
        return
    if key == "tau" and not isinstance(p.get("tau"), list):
        return  # one tau for all channels: "tau" is the free entry
    values = list(np.broadcast_to(np.asarray(p.get(key, 0.0), dtype=float), (3,)))
    values[channel] = value
    p[key] = values


def get_named(p, name):
    """The value of `name` in the parameter dict p (as set_named)."""
    m = re.match(r"threads\[(\d+)\]\.(.*)", name)
    if m:
        p, name = p["threads"][int(m.group(1))], m.group(2)
    if name[-2:] in CHANNEL and name[:-2] in ("albedo", "tau", "wall_color"):
        values = np.broadcast_to(np.asarray(p.get(name[:-2], 0.0),
                                            dtype=float), (3,))
        return float(values[CHANNEL[name[-2:]]])
    defaults = {"scale": 1.0, "offset_scale": 1.0}
    return float(np.asarray(p.get(name, defaults.get(name)), dtype=float))


def with_values(params, names, x):
    p = json.loads(json.dumps(params))
    for name, value in zip(names, x):
        set_named(p, name, float(value))
    return p


def fit(model_name, spec_path, train_path, held_path, repeats="1"):
    spec = json.load(open(spec_path))
    model = MODELS[model_name]
    wi, wo, y, sigma = read_table(train_path)
    hwi, hwo, truth_values, _ = read_table(held_path)
    names, free = spec["names"], np.array(spec["free"], dtype=bool)
    x0 = np.array([get_named(spec["params"], n) for n in names])
    lo, hi = np.array(spec["lower"]), np.array(spec["upper"])
    x0[free] = np.clip(x0[free], lo[free], hi[free])

    def full(xf):
        x = x0.copy()
        x[free] = xf
        return x

    def residuals(xf):
        m = model(with_values(spec["params"], names, full(xf)), wi, wo)
        return ((m - y) / sigma).ravel()

    seconds = []
    for _ in range(max(1, int(repeats))):
        start = time.perf_counter()
        result = least_squares(residuals, x0[free],
                               bounds=(lo[free], hi[free]), method="trf")
        seconds.append(time.perf_counter() - start)
    x = full(result.x)
    m = model(with_values(spec["params"], names, x), hwi, hwo)
    error = math.sqrt(np.sum((m - truth_values) ** 2) /
                      np.sum(truth_values ** 2))
    truth = np.array([get_named(spec["truth"], n) for n in names])
    rel = [abs(x[i] - truth[i]) / abs(truth[i])
           for i in range(len(x)) if free[i] and truth[i] != 0.0]
    print(json.dumps({"seconds_each": seconds,
                      "seconds": float(np.median(seconds)),
                      "value_error": error,
                      "param_error": max(rel) if rel else 0.0,
                      "nfev": int(result.nfev),
                      "success": bool(result.success)}))


def check(model_name, params_path, table_path):
    params = json.load(open(params_path))
    wi, wo, values, _ = read_table(table_path)
    m = MODELS[model_name](params, wi, wo)
    scale = max(float(np.max(np.abs(values))), 1e-300)
    print(json.dumps({"rows": len(values),
                      "max_relative_difference":
                          float(np.max(np.abs(m - values))) / scale}))


if __name__ == "__main__":
    if len(sys.argv) in (6, 7) and sys.argv[1] == "fit":
        fit(*sys.argv[2:])
    elif len(sys.argv) == 5 and sys.argv[1] == "check":
        check(*sys.argv[2:])
    else:
        sys.stderr.write(__doc__)
        sys.exit(2)
