"""contactmap compartments against cooltools 0.7.1 eigs_cis on every balanced real map given,
with and without a phasing track (log10 of 1 + each bin's coverage), and eigs_trans: the largest
differences. Vectors are compared exactly when phased, up to each region's sign otherwise.
usage: python scripts/check_compartments_peers.py CONTACTMAP URI [URI ...]
(needs cooler and cooltools; writes into a temporary folder). cooltools' eigs_trans draws its
fake cis values from the C library's random(): only the first call in a process starts from the
default seed, so each map's trans comparison runs in a process of its own."""
import os
import subprocess
import sys
import tempfile

import cooler
import cooltools
import numpy as np
import pandas as pd

cm, uris = sys.argv[1], sys.argv[2:]
if len(uris) > 1:
    # one process per map (see above)
    print("map\tanalysis\tmax |dE| (up to sign unless phased)\tmax |E|\tmax rel d(eigenvalue)")
    for uri in uris:
        out = subprocess.run([sys.executable, __file__, cm, uri], check=True, capture_output=True,
                             text=True).stdout
        print("".join(out.splitlines(True)[1:]), end="")
    sys.exit(0)
work = tempfile.mkdtemp()


def compare(ours_prefix, vals, vecs, signed, by_region):
    a = pd.read_csv(ours_prefix + ".vecs.tsv", sep="\t")
    la = pd.read_csv(ours_prefix + ".lam.txt", sep="\t")
    worst, scale = 0.0, 0.0
    groups = a.chrom.unique() if by_region else [None]
    for col in [c for c in a.columns if c.startswith("E")]:
        for chrom in groups:
            pick = (a.chrom == chrom) if chrom is not None else np.ones(len(a), bool)
            x, y = a[pick][col].values, vecs[col].values[pick.values if chrom is not None else pick]
            assert np.array_equal(np.isnan(x), np.isnan(y)), (col, chrom)
            if np.isnan(x).all():
                continue
            scale = max(scale, np.nanmax(np.abs(y)))
            d = np.nanmax(np.abs(x - y))
            worst = max(worst, d if signed else min(d, np.nanmax(np.abs(x + y))))
    cols = [c for c in la.columns if c.startswith("eigval")]
    theirs = vals[cols].values.astype(float)
    ok = np.isfinite(theirs)
    rel = np.max(np.abs(la[cols].values[ok] - theirs[ok]) / np.abs(theirs[ok])) if ok.any() else 0.0
    return worst, scale, rel


print("map\tanalysis\tmax |dE| (up to sign unless phased)\tmax |E|\tmax rel d(eigenvalue)")
for k, uri in enumerate(uris):
    clr = cooler.Cooler(uri)
    bins = clr.bins()[["chrom", "start", "end"]][:]
    pix = clr.pixels()[:]
    cov = np.bincount(pix.bin1_id, weights=pix["count"], minlength=len(bins))
    cov += np.bincount(pix.bin2_id, weights=pix["count"], minlength=len(bins))
    track = bins.copy()
    track["track"] = np.log10(1.0 + cov)
    track_path = os.path.join(work, f"track{k}.tsv")
    track.to_csv(track_path, sep="\t", index=False)
    for phased in (False, True):
        vals, vecs = cooltools.eigs_cis(clr, phasing_track=track if phased else None, n_eigs=3)
        prefix = os.path.join(work, f"m{k}{phased}")
        args = [cm, "compartments", uri, "-o", prefix]
        if phased:
            args += ["--phasing-track", track_path + ":track"]
        subprocess.run(args, check=True, stderr=subprocess.DEVNULL)
        w, s, r = compare(prefix + ".cis", vals, vecs, phased, True)
        print(f"{uri}\teigs_cis{' phased' if phased else ''}\t{w:.2g}\t{s:.3g}\t{r:.2g}")
    if len(clr.chromnames) > 1:
        vals, vecs = cooltools.eigs_trans(clr, n_eigs=3)
        prefix = os.path.join(work, f"t{k}")
        subprocess.run([cm, "compartments", uri, "--trans", "-o", prefix], check=True,
                       stderr=subprocess.DEVNULL)
        w, s, r = compare(prefix + ".trans", vals, vecs, False, False)
        print(f"{uri}\teigs_trans\t{w:.2g}\t{s:.3g}\t{r:.2g}")
