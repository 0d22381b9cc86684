"""Peer check for contactmap (see scripts/check_peers.sh)."""
import glob, json, os, subprocess, sys, tempfile

import cooler
import hictkpy
import numpy as np

data_dir, binary = sys.argv[1], sys.argv[2]
failures = 0


def ours(*args):
    out = subprocess.run([binary, *args], capture_output=True, text=True)
    if out.returncode != 0:
        raise RuntimeError(out.stderr.strip())
    return out.stdout


def peer_pixels(uri):
    """(bin1, bin2, count) as the peer tool reads them."""
    if ".hic" in uri:
        path, res = uri.split("::/resolutions/")
        df = hictkpy.File(path, int(res)).fetch().to_df()
        return df["bin1_id"].to_numpy(), df["bin2_id"].to_numpy(), df["count"].to_numpy()
    px = cooler.Cooler(uri).pixels()[:]
    # float64: numpy sums float32 counts in float32, which is not the sum (cooler may store float32)
    counts = px["count"].to_numpy()
    counts = counts.astype(np.float64) if counts.dtype.kind == "f" else counts
    return px["bin1_id"].to_numpy(), px["bin2_id"].to_numpy(), counts


def peer_nbins(uri):
    if ".hic" in uri:
        path, res = uri.split("::/resolutions/")
        return hictkpy.File(path, int(res)).nbins()
    return cooler.Cooler(uri).info["nbins"]


def report(ok, what):
    global failures
    failures += 0 if ok else 1
    print(f"{'ok  ' if ok else 'FAIL'}  {what}", flush=True)


uris = []
for path in sorted(glob.glob(f"{data_dir}/**/*", recursive=True)):
    if path.endswith(".cool"):
        uris.append(path)
    elif path.endswith(".mcool"):
        uris += [f"{path}::{g}" for g in cooler.fileops.list_coolers(path)]
    elif path.endswith(".hic"):
        uris += [f"{path}::/resolutions/{r}" for r in hictkpy.MultiResFile(path).resolutions()]

print(f"{'':6}{'uri':<90} {'nbins':>8} {'nnz':>10} {'sum':>14}")
with tempfile.TemporaryDirectory() as tmp:
    for uri in uris:
        name = os.path.relpath(uri, data_dir)
        try:
            b1, b2, counts = peer_pixels(uri)
            nbins = peer_nbins(uri)
            info = json.loads(ours("info", "--json", uri))
            same = ((info["nbins"], info["nnz"]) == (nbins, len(counts))
                    and np.isclose(info["sum"], counts.sum(), rtol=1e-12, atol=0))
            report(same, f"{name:<90} {nbins:>8} {len(counts):>10} {counts.sum():>14}  info"
                   + ("" if same else f"  ours: {info['nbins']} {info['nnz']} {info['sum']}"))
            out = os.path.join(tmp, "out.cool")
            ours("convert", uri, out)
            c = cooler.Cooler(out)
            px = c.pixels()[:]
            same = (np.array_equal(px["bin1_id"], b1) and np.array_equal(px["bin2_id"], b2)
                    and np.array_equal(px["count"], counts) and c.info["nbins"] == nbins)
            report(same, f"{name:<90} cooler opens our .cool: pixels identical")
            if ".hic" not in uri:
                src = cooler.Cooler(uri)
                sb, ob = src.bins()[:], c.bins()[:]
                same = ob[["chrom", "start", "end"]].astype(str).equals(sb[["chrom", "start", "end"]].astype(str))
                divisive = {n.split("'")[1] for n in info.get("notes", []) if "is divisive" in n}
                for col in sb.columns.drop(["chrom", "start", "end"]):
                    if col in divisive or sb[col].dtype.kind != "f":
                        continue  # divisive columns are compared through balancing below
                    same &= np.allclose(ob[col], sb[col], equal_nan=True, rtol=0, atol=0)
                for col in [w for w in sb.columns if w == "weight" or w in divisive]:
                    region = src.chromnames[0]
                    # the source as Juicer / hic2cool mean it (divisive), ours as cooler reads it
                    a = src.matrix(balance=col, divisive_weights=col in divisive).fetch(region)
                    b = c.matrix(balance=col).fetch(region)
                    same &= np.allclose(a, b, equal_nan=True, rtol=1e-12)
                report(same, f"{name:<90} cooler: bins and balanced matrices equal the source")
            if info.get("bin-type") == "fixed" and nbins > 4:
                base = info["bin-size"]
                mc = os.path.join(tmp, "out.mcool")
                ours("convert", uri, mc, "--resolutions", f"{base},{2 * base},{10 * base}")
                levels = cooler.fileops.list_coolers(mc)
                fine = cooler.Cooler(f"{mc}::/resolutions/{2 * base}")
                coarse = cooler.Cooler(f"{mc}::/resolutions/{10 * base}")
                same = (len(levels) == 3
                        and np.isclose(fine.pixels()[:]["count"].sum(), counts.sum(), rtol=1e-12, atol=0)
                        and coarse.info["nnz"] == len(coarse.pixels()[:]))
                # independent check of one level: cooler's own coarsening of our base level
                ref = os.path.join(tmp, "ref.cool")
                cooler.coarsen_cooler(f"{mc}::/resolutions/{base}", ref, 10, chunksize=10_000_000)
                rp, op = cooler.Cooler(ref).pixels()[:], coarse.pixels()[:]
                same &= (np.array_equal(rp["bin1_id"], op["bin1_id"])
                         and np.array_equal(rp["bin2_id"], op["bin2_id"])
                         and np.allclose(rp["count"], op["count"], rtol=1e-12, atol=0))
                report(same, f"{name:<90} cooler opens our .mcool; 10x level equals cooler.coarsen_cooler")
        except Exception as e:  # a failure of either tool on this file
            report(False, f"{name}: {type(e).__name__}: {e}")

print(f"\n{len(uris)} matrices, {failures} failures")
sys.exit(1 if failures else 0)
