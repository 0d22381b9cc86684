#!/usr/bin/env python3
"""Reference pictures of a contact map made the way cooltools' notebooks make them (cooler +
cooltools + matplotlib), to set beside `contactmap plot map` by eye (docs/plots.md).

    python scripts/figures/map_matplotlib.py URI CHROM OUTDIR [WINDOW_BP] [DEPTH_BP]

Writes OUTDIR/mpl_square.png (balanced map, cooltools' `fall` colour map on a log scale, limits the
minimum and maximum positive value as contactmap's default percentiles 0,100) and
OUTDIR/mpl_triangle.png (the 45-degree view of cooltools' insulation notebook: the map rotated
with pcolormesh, cut at DEPTH_BP, the log2 insulation score computed by cooltools under it and its
boundaries as dots). Needs cooler, cooltools and matplotlib (a venv: see docs/peers.md).
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.cm  # noqa: E402

# cooltools 0.7.1 registers its colour maps through matplotlib.cm.register_cmap, which
# matplotlib >= 3.9 removed: give it the registry's equivalent so `fall` is cooltools' own.
if not hasattr(matplotlib.cm, "register_cmap"):
    matplotlib.cm.register_cmap = lambda name, cmap: matplotlib.colormaps.register(
        cmap, name=name, force=True
    )
import cooler  # noqa: E402
import cooltools  # noqa: E402
import cooltools.lib.plotting  # noqa: E402,F401  (registers `fall`)
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import LogNorm  # noqa: E402


def mb_ticks(ax, axis="x"):
    formatter = matplotlib.ticker.FuncFormatter(lambda v, _: f"{v / 1e6:g}")
    (ax.xaxis if axis == "x" else ax.yaxis).set_major_formatter(formatter)


def rotated_mesh(n, start, bin_size):
    """Corner coordinates of an n x n matrix turned 45 degrees: x the genomic midpoint of
    (i, j), y their distance, both in bp (so the y axis reads as the separation s)."""
    i, j = np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij")
    x = start + (i + j) / 2 * bin_size
    y = (j - i) * bin_size
    return x, y


def main():
    uri, chrom, outdir = sys.argv[1:4]
    window = int(sys.argv[4]) if len(sys.argv) > 4 else 500_000
    depth = int(sys.argv[5]) if len(sys.argv) > 5 else 3_000_000
    clr = cooler.Cooler(uri)
    bin_size = clr.binsize
    data = clr.matrix(balance=True).fetch(chrom)
    positive = data[np.isfinite(data) & (data > 0)]
    norm = LogNorm(vmin=positive.min(), vmax=positive.max())
    length = clr.chromsizes[chrom]

    fig, ax = plt.subplots(figsize=(6, 5))
    im = ax.matshow(data, cmap="fall", norm=norm, extent=(0, length, length, 0))
    ax.xaxis.set_ticks_position("bottom")
    mb_ticks(ax, "x")
    mb_ticks(ax, "y")
    ax.set_xlabel(f"{chrom} (Mb)")
    ax.set_ylabel(f"{chrom} (Mb)")
    fig.colorbar(im, ax=ax, label="balanced contacts")
    fig.savefig(f"{outdir}/mpl_square.png", dpi=100, bbox_inches="tight")

    table = cooltools.insulation(clr, [window], verbose=False)
    table = table[table["chrom"] == chrom]
    fig, (ax, track) = plt.subplots(
        2, 1, figsize=(8, 4.5), sharex=True, gridspec_kw={"height_ratios": [3, 1]}
    )
    x, y = rotated_mesh(len(data), 0, bin_size)
    masked = np.ma.masked_invalid(data)
    im = ax.pcolormesh(x, y, masked, cmap="fall", norm=norm)
    ax.set_ylim(0, depth)
    ax.set_ylabel("distance (Mb)")
    mb_ticks(ax, "y")
    fig.colorbar(im, ax=[ax, track], label="balanced contacts", fraction=0.03)
    mid = (table["start"] + table["end"]) / 2
    column = f"log2_insulation_score_{window}"
    track.plot(mid, table[column], lw=1)
    boundaries = table[table[f"is_boundary_{window}"]]
    track.scatter(
        (boundaries["start"] + boundaries["end"]) / 2, boundaries[column], s=8, c="tab:green"
    )
    track.set_ylabel(column.replace("_score", ""), fontsize=7)
    track.set_xlabel(f"{chrom} (Mb)")
    track.set_xlim(0, length)
    mb_ticks(track, "x")
    fig.savefig(f"{outdir}/mpl_triangle.png", dpi=100, bbox_inches="tight")


if __name__ == "__main__":
    main()
