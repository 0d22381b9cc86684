#!/usr/bin/env python3
"""limma's empirical-Bayes moderated t-test (lmFit + eBayes), as ported by inmoose, on small
deterministic inputs: the reference for contactmap's squeezeVar / fitFDist / eBayes.

Run with a Python that has inmoose (the committed file was made with inmoose 0.9.1, numpy 2.4.6,
scipy 1.17.1; the script prints the versions it runs with):
    python3 -m venv /tmp/limma_venv && /tmp/limma_venv/bin/pip install inmoose 'pandas<3'
    /tmp/limma_venv/bin/python scripts/moderated_references.py

Writes one file, data/diff/moderated.tsv.gz (gzip, mtime 0), with the rows of three cases in
this order:
- two_by_two     80 features, 2 + 2 replicates (df_residual 2), features 0..9 changed;
- three_by_three 80 features, 3 + 3 replicates (df_residual 4), features 0..9 changed;
- equal_variances 20 features, 2 + 2 replicates, every feature's two groups the same spread
  about a different centre, so the log-variance moment is <= 0: df_prior = inf, s2_prior =
  mean(s2), s2_post = s2_prior, df_total = the cap sum(df_residual) = 40.

TSV columns (tab-separated, one row per feature of each case): case, feature, A1 A2 A3 B1 B2 B3
(the inputs: exact 4-decimal numbers, the values the reference was computed from; `nan` for a
replicate the case lacks, A3 and B3 of the 2 + 2 cases), coefficient (mean B - mean A),
stdev_unscaled, sigma (residual sd), df_residual, s2_post, df_total, t, p_value, then the case's
df_prior (`inf` when infinite) and s2_prior, repeated on each of its rows; floats written with repr
(shortest round trip, <= 17 digits).

Inputs need no random generator: value(i, j) = round(c_i + a_i * sin(1.7 i + 2.9 j + 0.5)
+ delta_i * [j in B], 4) with j the sample's index 0..n-1 over A then B, c_i = 8 + 2 sin(0.37 i),
a_i = 0.3 exp(0.9 sin(0.23 i)), delta_i = (3.0 if i even else -2.5) for i < 10 else 0 (the
equal_variances case: A = c_i -/+ 0.25, B = c_i + d_i -/+ 0.25, d_i = 0.1 sin(i)). The Rust test
should read the inputs from the file rather than rebuild them.

limma semantics checked here (inmoose.limma mirrors R limma 3.55 fitFDist/squeezeVar/eBayes):
- design (intercept, group-B indicator); the tested coefficient is the second one;
- eBayes(trend=False, robust=False): no covariate, no winsorising (inmoose's robust=True raises
  NotImplementedError; R's robust=True winsorises the log-variances and is not covered here);
- fitFDist: x = max(s2, 1e-5 median(s2)) (zero variances offset); z = log x;
  e = z - digamma(d/2) + log(d/2); emean = mean(e); evar = sum((e - emean)^2)/(n - 1) -
  mean(trigamma(d/2)); evar > 0: d0 = 2 trigammaInverse(evar), s0^2 = exp(emean + digamma(d0/2)
  - log(d0/2)); else d0 = inf and s0^2 = mean(x) (the pooled variance);
- s2_post = (d0 s0^2 + d s2)/(d0 + d), or s0^2 when d0 is infinite;
- t = coef / (stdev_unscaled sqrt(s2_post)); df_total = min(d + d0, sum over features of d);
  p = 2 pt(-|t|, df_total).
A hand-written numpy/scipy computation of these formulas (p-values through the incomplete beta
function rather than scipy.stats.t) must agree with inmoose to 1e-10 relative (plus 1e-12
absolute, for coefficients and t that cancel to about 0: inmoose's QR leaves ~1e-15 there, e.g.
equal_variances feature 0, whose exact coefficient is 0 and inmoose's 8.9e-16).
scripts/moderated_references.R checks the written file against R's limma itself (Debian's
r-bioc-limma 3.54.1): every column agrees to 1e-11 relative or better (t, coefficient; the rest
to 1e-13), df_prior to 2e-15.
"""

import gzip
import math
import os

import numpy as np
import pandas as pd
import patsy
import scipy
import scipy.special as sp
import inmoose
import importlib
from inmoose.limma import eBayes, lmFit

# inmoose 0.9.1's fitFDist returns df2 = np.inf as a Python float when the moment is <= 0; eBayes's
# B-statistic code then does `~(df_prior > 1e6)` on a Python bool (-2) and fails with a KeyError
# after t and p are computed. Handing it a numpy float instead changes no number.
inmoose_squeezevar = importlib.import_module("inmoose.limma.squeezeVar")  # the module, not the function
_fit_f_dist = inmoose_squeezevar.fitFDist


def _fit_f_dist_numpy(*args, **kwargs):
    out = _fit_f_dist(*args, **kwargs)
    out["df2"] = np.float64(out["df2"])
    return out


inmoose_squeezevar.fitFDist = _fit_f_dist_numpy

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
OUT = os.path.join(ROOT, "data", "diff")


def inputs(n_features, n_a, n_b):
    rows = []
    for i in range(n_features):
        c = 8.0 + 2.0 * math.sin(0.37 * i)
        a = 0.3 * math.exp(0.9 * math.sin(0.23 * i))
        delta = (3.0 if i % 2 == 0 else -2.5) if i < 10 else 0.0
        row = []
        for j in range(n_a + n_b):
            v = c + a * math.sin(1.7 * i + 2.9 * j + 0.5) + (delta if j >= n_a else 0.0)
            row.append(round(v, 4))
        rows.append(row)
    return rows


def equal_variance_inputs(n_features):
    rows = []
    for i in range(n_features):
        c = 8.0 + 2.0 * math.sin(0.37 * i)
        d = 0.1 * math.sin(i)
        rows.append([round(c - 0.25, 4), round(c + 0.25, 4), round(c + d - 0.25, 4), round(c + d + 0.25, 4)])
    return rows


def trigamma_inverse(x):
    # Newton on 1/trigamma, as in limma (scalar, x in the ordinary range)
    assert 1e-6 <= x <= 1e7
    y = 0.5 + 1.0 / x
    for _ in range(100):
        tri = sp.polygamma(1, y)
        dif = tri * (1.0 - tri / x) / sp.polygamma(2, y)
        y += dif
        if -dif / y < 1e-14:
            break
    return y


def by_hand(y, n_a, n_b):
    y = np.asarray(y, dtype=float)
    a, b = y[:, :n_a], y[:, n_a:]
    coef = b.mean(axis=1) - a.mean(axis=1)
    d = n_a + n_b - 2
    s2 = (((a - a.mean(axis=1, keepdims=True)) ** 2).sum(axis=1)
          + ((b - b.mean(axis=1, keepdims=True)) ** 2).sum(axis=1)) / d
    su = math.sqrt(1.0 / n_a + 1.0 / n_b)
    x = np.maximum(s2, 1e-5 * np.median(s2))
    e = np.log(x) - sp.digamma(d / 2) + math.log(d / 2)
    n = len(e)
    emean = e.mean()
    evar = ((e - emean) ** 2).sum() / (n - 1) - sp.polygamma(1, d / 2)
    if evar > 0:
        d0 = 2.0 * trigamma_inverse(evar)
        s02 = math.exp(emean + sp.digamma(d0 / 2) - math.log(d0 / 2))
        s2_post = (d0 * s02 + d * s2) / (d0 + d)
    else:
        d0 = math.inf
        s02 = x.mean()
        s2_post = np.full(n, s02)
    t = coef / (su * np.sqrt(s2_post))
    df_total = min(d + d0, d * n)
    p = sp.betainc(df_total / 2, 0.5, df_total / (df_total + t * t))
    return dict(coefficient=coef, stdev_unscaled=np.full(n, su), sigma=np.sqrt(s2),
                df_residual=np.full(n, float(d)), s2_post=s2_post, df_total=np.full(n, df_total),
                t=t, p_value=p, df_prior=d0, s2_prior=s02)


def with_inmoose(y, n_a, n_b):
    names = [f"A{k + 1}" for k in range(n_a)] + [f"B{k + 1}" for k in range(n_b)]
    data = pd.DataFrame(np.asarray(y, dtype=float), columns=names)
    samples = pd.DataFrame({"group": ["A"] * n_a + ["B"] * n_b}, index=names)
    design = patsy.dmatrix("~ group", samples)  # columns Intercept, group[T.B]
    fit = eBayes(lmFit(data, design))  # trend=False, robust=False
    col = "group[T.B]"
    n = len(y)
    return names, dict(
        coefficient=np.asarray(fit.coefficients[col], dtype=float),
        stdev_unscaled=np.asarray(fit.stdev_unscaled[col], dtype=float),
        sigma=np.asarray(fit.sigma, dtype=float),
        df_residual=np.broadcast_to(np.asarray(fit.df_residual, dtype=float), (n,)),
        s2_post=np.asarray(fit.s2_post, dtype=float),
        df_total=np.broadcast_to(np.asarray(fit.df_total, dtype=float), (n,)),
        t=np.asarray(fit.t[col], dtype=float),
        p_value=np.asarray(fit.p_value[col], dtype=float),
        df_prior=float(np.asarray(fit.df_prior)),
        s2_prior=float(np.asarray(fit.s2_prior)),
    )


COLUMNS = ["coefficient", "stdev_unscaled", "sigma", "df_residual", "s2_post", "df_total", "t",
           "p_value"]


def close(a, b, rel=1e-10, floor=1e-12):
    # relative, with an absolute floor for values that cancel to ~0 (a coefficient that is a
    # difference of means about 8, and its t): least squares by QR leaves ~1e-15 there
    a, b = float(a), float(b)
    if math.isinf(a) or math.isinf(b):
        return a == b
    return abs(a - b) <= rel * max(abs(a), abs(b)) + floor


REPLICATES = ["A1", "A2", "A3", "B1", "B2", "B3"]


def run_case(name, y, n_a, n_b):
    """Checks inmoose against the formulas; returns the case's rows of the output table."""
    names, ref = with_inmoose(y, n_a, n_b)
    hand = by_hand(y, n_a, n_b)
    for key in COLUMNS:
        worst = 0.0
        for k, (u, v) in enumerate(zip(ref[key], hand[key])):
            assert close(u, v), (name, key, k, u, v)
            if not math.isinf(u):
                worst = max(worst, abs(u - v) / max(abs(u), abs(v), 1e-300))
        print(f"{name}: {key} inmoose vs by hand, worst relative difference {worst:.2e}")
    assert close(ref["df_prior"], hand["df_prior"]), (ref["df_prior"], hand["df_prior"])
    assert close(ref["s2_prior"], hand["s2_prior"]), (ref["s2_prior"], hand["s2_prior"])

    df_prior = "inf" if math.isinf(ref["df_prior"]) else repr(ref["df_prior"])
    s2_prior = repr(ref["s2_prior"])
    lines = []
    for i, row in enumerate(y):
        value = dict(zip(names, row))
        cells = [name, str(i)]
        cells += [f"{value[r]:.4f}" if r in value else "nan" for r in REPLICATES]
        cells += [repr(float(ref[key][i])) for key in COLUMNS]
        cells += [df_prior, s2_prior]
        lines.append("\t".join(cells))
    print(name, f"{len(y)} features, replicates {n_a} + {n_b}, df_prior {df_prior}, "
          f"s2_prior {s2_prior}, df_total {float(ref['df_total'][0])!r}, "
          f"{int((ref['p_value'] < 0.01).sum())} with p < 0.01")
    return lines


def main():
    print(f"inmoose {inmoose.__version__}, numpy {np.__version__}, scipy {scipy.__version__}")
    os.makedirs(OUT, exist_ok=True)
    lines = ["\t".join(["case", "feature"] + REPLICATES + COLUMNS + ["df_prior", "s2_prior"])]
    lines += run_case("two_by_two", inputs(80, 2, 2), 2, 2)
    lines += run_case("three_by_three", inputs(80, 3, 3), 3, 3)
    lines += run_case("equal_variances", equal_variance_inputs(20), 2, 2)
    path = os.path.join(OUT, "moderated.tsv.gz")
    # mtime 0 (the file name stored in the header is "moderated.tsv"): the same inputs give the
    # same bytes
    with open(path, "wb") as raw:
        with gzip.GzipFile(filename="moderated.tsv", mode="wb", fileobj=raw, mtime=0,
                           compresslevel=9) as f:
            f.write(("\n".join(lines) + "\n").encode())
    print(path, os.path.getsize(path), "bytes")


if __name__ == "__main__":
    main()
