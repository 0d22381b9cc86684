#!/usr/bin/env python3
"""Run HiCExplorer 2.2.1.1's hicPlotMatrix (the last release on PyPI) with matplotlib >= 3.9,
which removed matplotlib.cm.get_cmap: the one shim it needs. Arguments are hicPlotMatrix's.

    pip install --no-deps hicexplorer hicmatrix && pip install intervaltree unidecode pyBigWig future
    python scripts/figures/hicplotmatrix.py --matrix big.cool --region chr1:0-50000000 --log1p --outFileName hpm.png
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.cm  # noqa: E402

if not hasattr(matplotlib.cm, "get_cmap"):

    def get_cmap(name=None, lut=None):
        cmap = matplotlib.colormaps[name or matplotlib.rcParams["image.cmap"]]
        return cmap if lut is None else cmap.resampled(lut)

    matplotlib.cm.get_cmap = get_cmap

from hicexplorer.hicPlotMatrix import main  # noqa: E402

main(sys.argv[1:])
