#!/usr/bin/env python3
"""The P(s) figure of cooltools' "contacts vs distance" notebook, for comparison by eye with
`contactmap plot expected`.

usage: ps_matplotlib.py URI [URI ...] OUT.png [--raw]

For each cooler URI: cooltools.expected_cis (whole chromosomes, no smoothing, ignore_diags=2),
logbin_expected + combine_binned_expected, then log-log P(s) (upper panel) and the local slope
(lower panel) against the mean separation of each log bin, as the notebook draws them.
Needs cooler, cooltools and matplotlib (see docs/peers.md).
"""
import os
import sys

import cooler
import cooltools
import cooltools.api.expected as ce
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(argv):
    raw = "--raw" in argv
    args = [a for a in argv if a != "--raw"]
    if len(args) < 2:
        sys.exit(__doc__)
    uris, out = args[:-1], args[-1]
    fig, axs = plt.subplots(
        figsize=(6, 6), nrows=2, gridspec_kw={"height_ratios": [2.2, 1]}, sharex=True
    )
    column = "count.avg" if raw else "balanced.avg"
    for uri in uris:
        clr = cooler.Cooler(uri)
        cvd = cooltools.expected_cis(
            clr,
            smooth=False,
            aggregate_smoothed=False,
            clr_weight_name=None if raw else "weight",
            ignore_diags=2,
            nproc=1,
        )
        lb_cvd, lb_slopes, _ = ce.logbin_expected(cvd, summary_name=column.replace(".avg", ".sum"))
        agg, slopes = ce.combine_binned_expected(
            lb_cvd, binned_exp_slope=lb_slopes, Pc_name=column
        )
        agg["s_bp"] = agg["dist.avg"] * clr.binsize
        slopes["s_bp"] = slopes["dist.avg"] * clr.binsize
        label = os.path.basename(uri.replace("::/resolutions/", " @"))
        axs[0].loglog(agg["s_bp"], agg[column], "-", label=label)
        axs[1].semilogx(slopes["s_bp"], slopes["slope"], "-")
    axs[0].set(ylabel="P(s), " + ("raw counts" if raw else "balanced"))
    axs[0].legend()
    axs[1].set(xlabel="separation, bp", ylabel="slope")
    fig.tight_layout()
    fig.savefig(out, dpi=100)


if __name__ == "__main__":
    main(sys.argv[1:])
