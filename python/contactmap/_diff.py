"""Differences between conditions with replicates (``contactmap diff``)."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any, Sequence

from . import _native
from ._file import _pandas, _uri_of

if TYPE_CHECKING:
    import pandas


def diff_loops(
    a: Sequence[Any],
    b: Sequence[Any],
    loops: str | os.PathLike[str] | None = None,
    *,
    half_width: int = 1,
    alpha: float = 0.05,
    cooks_filter: bool = True,
) -> pandas.DataFrame:
    """Loops whose contacts changed between conditions A (``a``: a map per replicate, paths,
    ``contactmap.File`` or ``cooler.Cooler``) and B (``b``), as ``contactmap diff loops``: each
    loop's raw counts in its (2 half_width + 1)^2 pixels, normalised by the smoothed expected at
    its distance, tested with DESeq2's model (pydeseq2 0.5.4's statistics), B against A.

    ``loops``: a BEDPE; ``None`` calls dots on each condition's summed replicates and pools them.
    Returns one row per loop with the columns of ``PREFIX.loops.bedpe``: ``chrom1 start1 end1
    chrom2 start2 end2 baseMean log2FoldChange lfc_low lfc_high lfcSE pvalue qvalue mean_A mean_B
    direction count_A1 ...``.
    """
    pd = _pandas()
    first = [_uri_of(m, "a") for m in a]
    second = [_uri_of(m, "b") for m in b]
    path = None if loops is None else os.fspath(loops)
    columns = _native.diff_loops(first, second, path, half_width, alpha, cooks_filter)
    return pd.DataFrame(dict(columns))
