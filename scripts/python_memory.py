"""Peak memory of a pixel query from Python (issue 31: no copy of the pixel columns between Rust
and numpy): the rise of the process's peak RSS while chr1's stored pixels of a balanced cooler
are fetched, against the size of the columns returned.

usage: python scripts/python_memory.py BIG_BALANCED.cool pixels|df
"""
import resource, sys, time, numpy as np, contactmap as cm
path, mode = sys.argv[1], sys.argv[2]
f = cm.File(path)
import pandas
rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
t = time.perf_counter()
if mode == 'pixels':
    b1, b2, c, bal = f._native.fetch_pixels(f._native.region_bins('chr1'), f._native.region_bins('chr1'), 'weight')
    size = (b1.nbytes + b2.nbytes + c.nbytes + bal.nbytes) / 2**20
    n = len(b1)
elif mode == 'df':
    df = f.fetch('chr1', normalization='weight').to_df()
    size = df.memory_usage(index=False).sum() / 2**20
    n = len(df)
elapsed = time.perf_counter() - t
rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
print(f'{mode}: {n} pixels, columns {size:.0f} MB, peak RSS rise {rss - rss0:.0f} MB, {elapsed:.2f} s')
