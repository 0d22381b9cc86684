"""Write a .hic with hictk's own writer (hictkpy.hic.FileWriter), for side-by-side timings with
`contactmap convert IN.cool OUT.hic`.  usage: python scripts/hictk_write_hic.py IN.cool OUT.hic RES,RES,... [threads]"""
import sys, cooler, hictkpy
src, out = sys.argv[1], sys.argv[2]
res = [int(r) for r in sys.argv[3].split(",")]
threads = int(sys.argv[4]) if len(sys.argv) > 4 else 2
clr = cooler.Cooler(src)
w = hictkpy.hic.FileWriter(out, clr.chromsizes.to_dict(), res, n_threads=threads, tmpdir="/tmp")
step = 5_000_000
for lo in range(0, clr.info["nnz"], step):
    w.add_pixels(clr.pixels()[lo:lo + step][["bin1_id", "bin2_id", "count"]])
w.finalize()
