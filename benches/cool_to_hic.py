"""Write a .hic (v9, by hictk's writer) holding the same pixels as a .cool, for side-by-side
read timings of .hic readers.  Usage: python benches/cool_to_hic.py IN.cool OUT.hic [RES,RES...]
(resolutions default to the cooler's own; coarser ones must be multiples of it)."""
import sys

import cooler
import hictkpy

src, out = sys.argv[1], sys.argv[2]
clr = cooler.Cooler(src)
resolutions = [int(r) for r in sys.argv[3].split(",")] if len(sys.argv) > 3 else [clr.binsize]
writer = hictkpy.hic.FileWriter(out, clr.chromsizes.to_dict(), resolutions, n_threads=2,
                                skip_all_vs_all_matrix=True)
step = 5_000_000
for lo in range(0, clr.info["nnz"], step):
    writer.add_pixels(clr.pixels()[lo:lo + step][["bin1_id", "bin2_id", "count"]])
writer.finalize()
print(out, resolutions)
