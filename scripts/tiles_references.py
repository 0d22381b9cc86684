#!/usr/bin/env python3
"""clodius 0.22.2's answers for the maps in data/, which the `tiles` room's tests compare with.

Run with a Python that has clodius 0.22.2 (it needs Python >= 3.12):
    /root/.pyenv/versions/3.12.1/bin/python -m venv /tmp/clodius_venv
    /tmp/clodius_venv/bin/pip install clodius==0.22.2
    /tmp/clodius_venv/bin/python scripts/tiles_references.py

Writes, for each map:
- data/tiles/<map>.tileset_info.json: `clodius.tiles.cooler.tileset_info` of the map, its
  `transforms` sorted by value (clodius lists them in Python's set order, which varies);
- data/tiles/<map>.tiles.json.gz: for every zoom level, every transform the level stores (and
  `default`), the tiles along the diagonal, the ones beside it on either side, trans tiles and
  one past the genome's end, each asked of `clodius.tiles.cooler.tiles` alone: the decoded
  array's dtype, CRC-32 of its bytes (as decoded from base64), NaN count, min / max, or null
  when clodius gives no tile.

It also writes data/tiles/square.mcool (seed 20261130), a map made here for what the maps in
data/ lack: square storage (both triangles stored), real-valued counts, masked (NaN-weight) bins
in every level, counts beyond float16's range in one corner (so those tiles are float32),
chromosome lengths that are not multiples of the resolution, a divisive `KR` column.
"""

import base64
import gzip
import io
import json
import os
import warnings
import zlib

import clodius
import clodius.tiles.bedfile as hgb
import clodius.tiles.bedpe as hgbp
import clodius.tiles.bigwig as hgbw
import clodius.tiles.cooler as hgc
import cooler
import h5py
import numpy as np
import pandas as pd
from repack_hdf5 import repack

MAPS = ["cooler_test_file.mcool", "toy.symm.upper.2.mcool", "square.mcool"]
TRANSFORMS = ["weight", "KR", "VC", "VC_SQRT"]

root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data")
out = os.path.join(root, "tiles")


def make_square(path):
    """Three chromosomes, resolutions 1 and 2 kb, both triangles stored.

    At 1 and 2 kb the bins before 512 kb are never masked, so the tiles there have no NaN and
    the choice of float16 rests on their values alone: at 1 kb tile (0, 0) peaks at 65490 and
    tile (1, 1) at 65480 (clodius compares them with float16's largest value after rounding
    them to float16: 65490 rounds to 65504, which is not below it, so that tile is float32;
    65480 rounds to 65472, so that one is float16); at 2 kb the first bins' counts are beyond
    float16's range.
    """
    rng = np.random.default_rng(20261130)
    chromsizes = pd.Series({"chrA": 520_500, "chrB": 29_999, "chrC": 20_001})
    made = path + ".made"
    if os.path.exists(made):
        os.remove(made)
    for res in (1000, 2000):
        bins = cooler.binnify(chromsizes, res)
        n = len(bins)
        i, j = np.triu_indices(n)
        keep = rng.random(len(i)) < np.exp(-np.abs(i - j) / 2.0)
        i, j = i[keep], j[keep]
        count = np.round(rng.gamma(2.0, 5.0, len(i)) * 100.0 / (1 + np.abs(i - j)), 1)
        weight = rng.uniform(0.5, 1.5, n)
        kr = rng.uniform(0.5, 1.5, n)
        first = np.asarray(bins["start"] < 512_000) & np.asarray(bins["chrom"] == "chrA")
        weight[(rng.random(n) < 0.05) & ~first] = np.nan
        kr[rng.random(n) < 0.05] = np.nan
        if res == 1000:
            for b, peak in ((3, 65490.0), (300, 65480.0)):
                count[(i == b) & (j == b)] = peak / weight[b] ** 2
        elif res == 2000:
            count[(i < 8) & (j < 8)] *= 1e4  # beyond float16 (max 65504)
        both = np.concatenate([i, j[i != j]]), np.concatenate([j, i[i != j]])
        values = np.concatenate([count, count[i != j]])
        order = np.lexsort((both[1], both[0]))
        pixels = pd.DataFrame(
            {"bin1_id": both[0][order], "bin2_id": both[1][order], "count": values[order]}
        )
        bins = bins.assign(weight=weight, KR=kr)
        cooler.create_cooler(
            f"{made}::/resolutions/{res}",
            bins,
            pixels,
            dtypes={"count": np.float64},
            symmetric_upper=False,
            triucheck=False,
            mode="a",
            h5opts={"compression": "gzip", "compression_opts": 9, "shuffle": True},
        )
    repack(made, path)
    os.remove(made)


def make_bed(path, chromsizes):
    """250 intervals on cooler_test_file's genome (dm6), six BED columns (a real-valued score),
    seed 20261130; a few wider than a chromosome's tenth, so coarse tiles hold many."""
    rng = np.random.default_rng(20261130)
    names, lengths = zip(*chromsizes)
    with gz_text(path) as f:
        for k in range(250):
            c = int(rng.integers(len(names)))
            width = int(rng.choice([20_000, 200_000, 2_000_000]))
            start = int(rng.integers(0, max(1, lengths[c] - width)))
            end = min(lengths[c], start + width)
            score = round(float(rng.uniform(0, 10)), 3)
            f.write(f"{names[c]}\t{start}\t{end}\tfeature{k}\t{score}\t{'+-'[k % 2]}\n")


def bed_references(path, chromsizes):
    """clodius' bedfile tileset_info and, for every zoom level, the first, a middle and the
    last tile that hold at most 1,024 records (clodius samples larger ones at random): each
    tile's record uids, and each record once (xStart, xEnd, chrOffset, fields; not `importance`,
    random in clodius)."""
    series = pd.Series({name: length for name, length in chromsizes})
    info = hgb.tileset_info(path, series)
    records, tiles = {}, {}
    for z in range(info["max_zoom"] + 1):
        for x in sorted({0, 2**z // 3, 2**z - 1}):
            ((_, answer),) = hgb.tiles(path, [f"a.{z}.{x}"], series, None)
            if len(answer) > 1024:
                continue
            tiles[f"{z}.{x}"] = sorted(int(r["uid"]) for r in answer)
            for r in answer:
                records[int(r["uid"])] = {
                    "xStart": int(r["xStart"]),
                    "xEnd": int(r["xEnd"]),
                    "chrOffset": int(r["chrOffset"]),
                    "fields": [v.item() if hasattr(v, "item") else v for v in r["fields"]],
                }
    answers = {"records": records, "tiles": tiles}
    return info, answers


def make_bedgraph(path, chromsizes):
    """A bedGraph on cooler_test_file's genome (seed 20261130): per chromosome, intervals of 1 to
    40 kb with gaps between some, values of mixed sign and scale (a chromosome's values near
    70,000 in one stretch, beyond float16's range), chrM left without data."""
    rng = np.random.default_rng(20261130)
    with gz_text(path) as f:
        for name, length in chromsizes:
            if name == "chrM":
                continue
            pos = int(rng.integers(0, 5000))
            while pos < length:
                width = int(rng.integers(10_000, 200_000))
                end = min(length, pos + width)
                value = float(rng.normal(0, 2))
                if name == "chr4":
                    value = 70_000 + value
                f.write(f"{name}\t{pos}\t{end}\t{value:.6g}\n")
                pos = end + (int(rng.integers(0, 20_000)) if rng.random() < 0.3 else 0)


def bedgraph_references(path, chromsizes):
    """clodius' bigwig tiles of a bigWig holding the bedGraph (pyBigWig, no zoom levels, so that
    pybigtools summarises the intervals themselves): tileset_info with the map's chromosomes,
    and for every zoom level the first, a middle and the last tile and the one holding chr4's
    start, in each aggregation mode."""
    import pyBigWig

    bw_path = path.removesuffix(".gz") + ".bw"
    bw = pyBigWig.open(bw_path, "w")
    bw.addHeader([(n, int(l)) for n, l in chromsizes], maxZooms=0)
    rows = [line.split("\t") for line in gzip.open(path, "rt")]
    bw.addEntries(
        [r[0] for r in rows],
        [int(r[1]) for r in rows],
        ends=[int(r[2]) for r in rows],
        values=[float(r[3]) for r in rows],
    )
    bw.close()
    info = hgbw.tileset_info(bw_path, chromsizes)
    chr4 = sum(l for n, l in chromsizes[: [n for n, _ in chromsizes].index("chr4")])
    answers = {}
    for z in range(info["max_zoom"] + 1):
        span = info["max_width"] // 2**z
        for x in sorted({0, 2**z // 3, 2**z - 1, chr4 // span}):
            for mode in ("mean", "min", "max", "sum"):
                tile_id = f"a.{z}.{x}" if mode == "mean" else f"a.{z}.{x}.{mode}"
                ((_, tile),) = hgbw.tiles(bw_path, [tile_id], chromsizes=chromsizes)
                digest = decode(tile)
                digest["length"] = len(base64.b64decode(tile["dense"])) // (
                    2 if tile["dtype"] == "float16" else 4
                )
                answers[tile_id[2:]] = digest
    os.remove(bw_path)
    return info, answers


def make_bedpe(path, chromsizes):
    """150 anchor pairs (dots) on cooler_test_file's genome, seed 20261130: mostly cis within
    2 Mb, some trans; a header line; a score column."""
    rng = np.random.default_rng(20261130)
    names, lengths = zip(*chromsizes)
    with gz_text(path) as f:
        f.write("chrom1\tstart1\tend1\tchrom2\tstart2\tend2\tscore\n")
        for k in range(150):
            a = int(rng.integers(len(names) - 1))
            b = a if rng.random() < 0.8 else int(rng.integers(len(names) - 1))
            s1 = int(rng.integers(0, lengths[a] - 10_000))
            s2 = min(lengths[b] - 10_000, s1 + int(rng.integers(20_000, 2_000_000))) if a == b \
                else int(rng.integers(0, lengths[b] - 10_000))
            score = round(float(rng.uniform(0, 1)), 4)
            f.write(f"{names[a]}\t{s1}\t{s1 + 10_000}\t{names[b]}\t{s2}\t{s2 + 10_000}\t{score}\n")


def bedpe_references(path, chromsizes):
    """clodius' bedpe tileset_info and, for every zoom level, 2D tiles on the diagonal (first,
    middle, last) and beside it, and 1D tiles (first, middle, last) that hold at most 512 records
    (clodius samples larger ones at random): each tile's record uids, each record once."""
    series = pd.Series({name: length for name, length in chromsizes})
    info = hgbp.tileset_info(path, series)
    records, tiles = {}, {}
    for z in range(info["max_zoom"] + 1):
        for x in sorted({0, 2**z // 3, 2**z - 1}):
            ids = [f"{z}.{x}.{x}", f"{z}.{x}"] + ([f"{z}.{x}.{x + 1}"] if x + 1 < 2**z else [])
            for tile_id in ids:
                ((_, answer),) = hgbp.tiles(path, [f"a.{tile_id}"], series)
                if len(answer) > 512:
                    continue
                tiles[tile_id] = sorted(int(r["uid"]) for r in answer)
                for r in answer:
                    records[int(r["uid"])] = {
                        k: int(r[k]) for k in ("xStart", "xEnd", "yStart", "yEnd", "xChrOffset", "yChrOffset")
                    } | {"fields": [v.item() if hasattr(v, "item") else v for v in r["fields"]]}
    return info, {"records": records, "tiles": tiles}


def decode(tile):
    raw = base64.b64decode(tile["dense"])
    array = np.frombuffer(raw, dtype=tile["dtype"])
    return {
        "dtype": tile["dtype"],
        "crc32": zlib.crc32(raw),
        "n_nan": int(np.isnan(array).sum()),
        "min_value": wire(tile["min_value"]),
        "max_value": wire(tile["max_value"]),
    }


def wire(value):
    """min_value / max_value as the server sends them: clodius writes "NaN" for a tile of NaN
    alone and a bare Infinity (not JSON; a browser's JSON.parse refuses it) for a tile holding
    an infinite value (a zero in a divisive column); contactmap writes "Infinity" then."""
    if isinstance(value, float) and np.isinf(value):
        return "Infinity" if value > 0 else "-Infinity"
    return value


def tile_ids(info, zoom, transforms):
    """The tiles asked of each level: diagonal, beside it, trans, past the end."""
    resolution = sorted(info["resolutions"], reverse=True)[zoom]
    length = info["max_pos"][0]
    n = -(-length // (resolution * 256))
    positions = set()
    for x in range(n):
        positions |= {(x, x), (x, x + 1), (x + 1, x)}
    # the first chromosome against the last (a trans tile where there are several)
    last_start = length - info["chromsizes"][-1][1]
    positions.add((0, last_start // (resolution * 256)))
    positions.add((n, n))
    ids = []
    for t in ["default"] + transforms:
        for x, y in sorted(positions):
            base = f"a.{zoom}.{x}.{y}"
            ids.append(base if t == "default" else f"{base}.{t}")
    return ids


def gz_text(path):
    """A gzip'd text file written without a time stamp (a rerun writes the same bytes)."""
    return io.TextIOWrapper(gzip.GzipFile(path, "wb", mtime=0), encoding="utf-8")


def write_json(path, value):
    """JSON, sorted keys; gzip'd (without a time stamp, so a rerun writes the same bytes) when
    the name ends in .gz."""
    text = json.dumps(value, sort_keys=True) + "\n"
    if path.endswith(".gz"):
        with open(path, "wb") as f:
            f.write(gzip.compress(text.encode(), mtime=0))
    else:
        with open(path, "w") as f:
            f.write(text)


def main():
    # numpy's overflow warnings where clodius casts (its float16 test, infinities to float32)
    warnings.simplefilter("ignore", RuntimeWarning)
    warnings.simplefilter("ignore", UserWarning)
    assert clodius.__version__ == "0.22.2", clodius.__version__
    os.makedirs(out, exist_ok=True)
    make_square(os.path.join(out, "square.mcool"))
    for name in MAPS:
        path = os.path.join(out if name == "square.mcool" else root, name)
        info = dict(hgc.tileset_info(path))
        info["transforms"] = sorted(info["transforms"], key=lambda t: t["value"])
        with open(os.path.join(out, name + ".tileset_info.json"), "w") as f:
            json.dump(info, f, indent=1, sort_keys=True)
            f.write("\n")
        answers = {}
        for zoom, resolution in enumerate(sorted(info["resolutions"], reverse=True)):
            columns = cooler.Cooler(f"{path}::/resolutions/{resolution}").bins().columns
            for tile_id in tile_ids(info, zoom, [t for t in TRANSFORMS if t in columns]):
                tiles = hgc.tiles(path, [tile_id])
                answers[tile_id[2:]] = decode(tiles[0][1]) if tiles else None
        write_json(os.path.join(out, name + ".tiles.json.gz"), answers)
        print(name, len(answers), "tiles")
    chromsizes = hgc.tileset_info(os.path.join(root, MAPS[0]))["chromsizes"]
    tracks = [
        ("domains.bed", make_bed, bed_references),
        ("dots.bedpe", make_bedpe, bedpe_references),
        ("track.bedgraph", make_bedgraph, bedgraph_references),
    ]
    for name, make, references in tracks:
        path = os.path.join(out, name + ".gz")
        make(path, chromsizes)
        info, answers = references(path, chromsizes)
        write_json(os.path.join(out, name + ".tileset_info.json"), info)
        write_json(os.path.join(out, name + ".tiles.json.gz"), answers)
        print(name, len(answers.get("tiles", answers)), "tiles")

main()
