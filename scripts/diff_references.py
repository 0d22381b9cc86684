#!/usr/bin/env python3
"""pydeseq2 0.5.4's answers on small count matrices, which the `diff` room's tests compare with.

Run with a Python that has pydeseq2 0.5.4:
    python3 -m venv /tmp/deseq_venv && /tmp/deseq_venv/bin/pip install pydeseq2==0.5.4
    /tmp/deseq_venv/bin/python scripts/diff_references.py

Writes, for each case (seed 20261130):
- data/diff/<case>.tsv.gz: one row per feature: the counts per sample (A1.., B1..), then
  pydeseq2's genewise_dispersions, MAP_dispersions, dispersion_outlier (0/1), log2FoldChange,
  lfcSE, pvalue, padj (9 significant digits);
- data/diff/<case>.json: size factors, trend coefficients, prior variance, and how far
  pydeseq2 with scipy's default L-BFGS-B tolerances lands from the same pydeseq2 run to
  convergence (quantiles of the relative differences per column).

The reference is pydeseq2 0.5.4 with every `scipy.optimize.minimize` it calls solved to its
minimum (`converged_minimize`): the answer its own model defines. At its default tolerances L-BFGS-B stops
early on flat losses (the dispersion trend, many dispersions; a start on a bound where the
slope is under 1e-5 does not move), a few percent from the optimum; tightening its
tolerances makes its line search fail on a tenth of the features, which pydeseq2 then fits on a
grid. The JSON records how far the default run lands.

Design `~condition`, contrast B vs A, `independent_filter=False` (contactmap's q-values are plain
Benjamini-Hochberg), `cooks_filter=True`, `refit_cooks=True` (no effect below 7 replicates).
"""

import gzip
import json
import os
import warnings

import numpy as np
import pandas as pd
import pydeseq2
import pydeseq2.default_inference as default_inference
import pydeseq2.utils as utils
import scipy.optimize
from pydeseq2.dds import DeseqDataSet
from pydeseq2.default_inference import DefaultInference
from pydeseq2.ds import DeseqStats

assert pydeseq2.__version__ == "0.5.4", pydeseq2.__version__
warnings.filterwarnings("ignore")

root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "diff")
CASES = {
    # name: (replicates per condition, features, planted Cook's outliers)
    "two_by_two": ((2, 2), 300, 0),
    "three_by_three": ((3, 3), 300, 4),
}


def simulate(seed, replicates, n_features, n_outliers):
    """NB counts: means log-uniform 5..5000, dispersion 0.01 + 1/mean (a trend plus noise),
    depths 0.6..1.6, one feature in eight changed by N(0, 1.5) in log; `n_outliers` counts
    multiplied by 20."""
    rng = np.random.default_rng(seed)
    n = sum(replicates)
    base = np.exp(rng.uniform(np.log(5), np.log(5000), n_features))
    disp = (0.01 + 1.0 / base) * np.exp(rng.normal(0, 0.3, n_features))
    depth = rng.uniform(0.6, 1.6, n)
    change = np.where(rng.random(n_features) < 0.125, rng.normal(0, 1.5, n_features), 0.0)
    condition = np.repeat([0, 1], replicates)
    mu = base[None, :] * depth[:, None] * np.exp(change[None, :] * condition[:, None])
    size = 1.0 / disp
    counts = rng.negative_binomial(size[None, :], size[None, :] / (size[None, :] + mu))
    for _ in range(n_outliers):
        counts[rng.integers(n), rng.integers(n_features)] *= 20
    return counts, condition


def converged_minimize(fun, x0, jac=None, method=None, bounds=None, **kwargs):
    """scipy's `minimize` as pydeseq2 calls it (L-BFGS-B with bounds and a gradient), solved
    to its minimum: in one dimension (the dispersions), the minimum over the bounds (a grid,
    then brentq on the gradient); in more (the trend, the GLM's fallback), L-BFGS-B at its
    defaults, then scipy's `root` (hybr) of the gradient from there, kept when it lies within
    the bounds, lowers the loss and the gradient."""
    result = scipy.optimize.minimize(fun, x0, jac=jac, method=method, bounds=bounds, **kwargs)
    x0 = np.asarray(x0, dtype=float)
    lower = np.array([b[0] for b in bounds] * len(x0))[: len(x0)]
    upper = np.array([b[1] for b in bounds] * len(x0))[: len(x0)]
    if len(x0) == 1:
        # the loss on 1,000 log-spaced points over the bounds, then, about the best of them,
        # brentq on the gradient where it changes sign (bounded Brent on the loss where it
        # does not: next to a bound, where pydeseq2's gradient is lost to cancellation)
        loss = lambda x: float(fun(np.array([x])))  # noqa: E731
        slope = lambda x: float(jac(np.array([x]))[0])  # noqa: E731
        grid = np.linspace(lower[0], upper[0], 1000)
        values = np.array([loss(x) for x in grid])
        best = int(np.argmin(values))
        left, right = grid[max(best - 1, 0)], grid[min(best + 1, len(grid) - 1)]
        x = grid[best]
        if best not in (0, len(grid) - 1) and slope(left) < 0 < slope(right):
            x = scipy.optimize.brentq(slope, left, right, xtol=1e-300, rtol=8.9e-16)
        elif left < right:
            bounded = scipy.optimize.minimize_scalar(
                loss, bounds=(left, right), method="bounded", options={"xatol": 1e-12}
            )
            if bounded.fun < values[best]:
                x = bounded.x
        result.x = np.array([x])
        result.fun = loss(x)
        result.success = True
        return result
    polished = scipy.optimize.root(jac, result.x, method="hybr", tol=1e-13)
    if (
        np.max(np.abs(jac(polished.x))) < np.max(np.abs(jac(result.x)))
        and np.all(polished.x >= lower)
        and np.all(polished.x <= upper)
        and fun(polished.x) <= result.fun
    ):
        result.x, result.fun, result.success = polished.x, fun(polished.x), True
    return result


def run(counts, condition, converge):
    minimize = converged_minimize if converge else scipy.optimize.minimize
    utils.minimize = minimize
    default_inference.minimize = minimize
    samples = [f"{'AB'[c]}{k}" for c, k in zip(condition, range(len(condition)))]
    frame = pd.DataFrame(counts, index=samples, columns=[f"f{i}" for i in range(counts.shape[1])])
    meta = pd.DataFrame({"condition": ["AB"[c] for c in condition]}, index=samples)
    inference = DefaultInference(n_cpus=1)
    dds = DeseqDataSet(
        counts=frame, metadata=meta, design="~condition", quiet=True, inference=inference
    )
    dds.deseq2()
    stats = DeseqStats(
        dds,
        contrast=["condition", "B", "A"],
        independent_filter=False,
        quiet=True,
        inference=inference,
    )
    stats.summary()
    return dds, stats.results_df


def relative(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    keep = np.isfinite(a) & np.isfinite(b)
    r = np.abs(a[keep] - b[keep]) / np.maximum(np.abs(b[keep]), 1e-300)
    return {q: float(np.quantile(r, q)) for q in (0.5, 0.9, 0.99, 1.0)} | {
        "within_1e-6": float(np.mean(r <= 1e-6))
    }


def main():
    os.makedirs(root, exist_ok=True)
    for case, (replicates, n_features, n_outliers) in CASES.items():
        counts, condition = simulate(20261130, replicates, n_features, n_outliers)
        dds, res = run(counts, condition, converge=True)
        default_dds, default_res = run(counts, condition, converge=False)
        names = []
        for c in (0, 1):
            names += [f"{'AB'[c]}{k + 1}" for k in range(replicates[c])]
        var = dds.var
        with gzip.GzipFile(os.path.join(root, f"{case}.tsv.gz"), "wb", mtime=0) as raw:
            lines = ["\t".join(names + ["genewise", "map", "outlier", "log2FoldChange",
                                        "lfcSE", "pvalue", "padj"])]
            for i in range(n_features):
                values = [str(int(v)) for v in counts[:, i]]
                values += [f"{v:.9g}" for v in (var["genewise_dispersions"].iloc[i],
                                                  var["MAP_dispersions"].iloc[i])]
                values.append(str(int(bool(var["_outlier_genes"].iloc[i]))))
                values += [f"{v:.9g}" for v in res.iloc[i][
                    ["log2FoldChange", "lfcSE", "pvalue", "padj"]]]
                lines.append("\t".join(values))
            raw.write(("\n".join(lines) + "\n").encode())
        trend = dds.uns["trend_coeffs"]
        summary = {
            "pydeseq2": pydeseq2.__version__,
            "size_factors": [float(v) for v in dds.obs["size_factors"]],
            "trend": {"a0": float(trend["a0"]), "a1": float(trend["a1"])},
            "squared_log_residual": float(dds.uns["_squared_logres"]),
            "prior_variance": float(dds.uns["prior_disp_var"]),
            "lfc_converged": int(var["_LFC_converged"].sum()),
            "default_tolerances_against_converged": {
                "trend": [float(default_dds.uns["trend_coeffs"]["a0"]),
                          float(default_dds.uns["trend_coeffs"]["a1"])],
                "genewise_dispersions": relative(default_dds.var["genewise_dispersions"],
                                                 var["genewise_dispersions"]),
                "dispersions": relative(default_dds.var["dispersions"], var["dispersions"]),
                "log2FoldChange": relative(default_res["log2FoldChange"], res["log2FoldChange"]),
                "pvalue": relative(default_res["pvalue"], res["pvalue"]),
                "calls_at_q0.05": {
                    "converged": int((res["padj"] < 0.05).sum()),
                    "default": int((default_res["padj"] < 0.05).sum()),
                    "both": int(((res["padj"] < 0.05) & (default_res["padj"] < 0.05)).sum()),
                },
            },
            "cooks_outliers": int(res["pvalue"].isna().sum()),
        }
        with open(os.path.join(root, f"{case}.json"), "w") as f:
            json.dump(summary, f, indent=1)
            f.write("\n")
        print(case, json.dumps(summary["default_tolerances_against_converged"]))


if __name__ == "__main__":
    main()
