"""The Python API against independent references: cooler / cooltools outputs in data/reference/
(made by the peer tools, see data/README.md) and the contactmap command line on the same input.

Tolerances: the references keep 10 significant digits (1e-8 relative), `cooler dump` 6 (1e-5);
the command line writes floats in full (shortest round trip), so it is compared exactly.
"""

from __future__ import annotations

import gzip
import io
import os
import shutil
import signal
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import contactmap as cm

from helpers import DATA, DM6, GM12878, MM9, REF, ROOT, YEAST, assert_columns_close, binary, cli_table

# ---------------------------------------------------------------------------------------------
# File


def test_file_metadata_equals_cooler():
    f = cm.File(MM9)
    bins_ref = pd.read_csv(REF / "CN.mm9.10000kb.bins.tsv", sep="\t")
    bins = f.bins()
    assert list(bins.columns[:3]) == ["chrom", "start", "end"]
    assert_columns_close(bins, bins_ref, 1e-5, "mm9 bins")  # cooler dump: 6 digits
    assert f.resolution() == 10_000_000
    chroms = f.chromosomes()
    assert list(chroms) == list(dict.fromkeys(bins_ref["chrom"]))
    assert chroms["chr1"] == 197195432
    assert "weight" in f.avail_normalizations()
    assert f.attributes()["bin-size"] == 10_000_000
    assert f.format().startswith("cool")


def test_fetch_box_equals_cooler_dump():
    # `cooler dump --join -b -r chr2L:1,000,000-3,000,000 -r2 chr2L:2,000,000-5,000,000`
    ref = pd.read_csv(REF / "dm6_100kb.chr2L_box.balanced.join.tsv", sep="\t")
    f = cm.File(DM6)
    sel = f.fetch("chr2L:1,000,000-3,000,000", "chr2L:2,000,000-5,000,000", normalization="weight")
    df = sel.to_df(join=True)
    assert list(df.columns) == list(ref.columns)
    assert_columns_close(df, ref, 1e-5, "dm6 box")
    assert sel.nnz() == len(ref)
    assert sel.sum() == pytest.approx(ref["balanced"].sum(), rel=1e-5)
    # the same pixels by bin id, raw
    raw = f.fetch("chr2L:1,000,000-3,000,000", "chr2L:2,000,000-5,000,000").to_df()
    assert list(raw.columns) == ["bin1_id", "bin2_id", "count"]
    np.testing.assert_array_equal(raw["count"].to_numpy(), ref["count"].to_numpy())


def test_dense_matrix_is_the_symmetric_matrix_of_the_pixels():
    f = cm.File(DM6)
    chrom = "chr3R"
    w = f.weights("weight")
    first, end = f._native.region_bins(chrom)
    pixels = f.fetch(chrom).to_df()
    naive = np.zeros((end - first, end - first))
    i = pixels["bin1_id"].to_numpy() - first
    j = pixels["bin2_id"].to_numpy() - first
    naive[i, j] = pixels["count"].to_numpy()
    naive[j, i] = pixels["count"].to_numpy()
    dense = f.fetch(chrom).to_numpy()
    np.testing.assert_array_equal(dense, naive)
    # balanced as cooler's matrix(balance=True): count * outer(w, w), NaN rows for masked bins
    balanced = f.fetch(chrom, normalization="weight").to_numpy()
    want = naive * np.outer(w[first:end], w[first:end])
    assert np.array_equal(np.isnan(balanced), np.isnan(want))
    np.testing.assert_array_equal(balanced[~np.isnan(want)], want[~np.isnan(want)])
    # a rectangle across the diagonal: rows from both triangles
    rect = f.fetch(f"{chrom}:0-3,000,000", f"{chrom}:1,000,000-6,000,000").to_numpy()
    r0, r1 = f._native.region_bins(f"{chrom}:0-3,000,000")
    c0, c1 = f._native.region_bins(f"{chrom}:1,000,000-6,000,000")
    np.testing.assert_array_equal(rect, naive[r0 - first : r1 - first, c0 - first : c1 - first])


def test_sparse_outputs_hold_the_pixels():
    pytest.importorskip("scipy")
    f = cm.File(YEAST)
    sel = f.fetch("chrII", normalization="weight")
    coo, csr = sel.to_coo(), sel.to_csr()
    df = sel.to_df()
    assert coo.nnz == len(df) == sel.nnz()
    dense = sel.to_numpy()
    upper = np.triu(np.nan_to_num(dense))
    np.testing.assert_allclose(np.nan_to_num(csr.toarray()), upper, rtol=1e-15)


def test_multires_file_lists_and_opens_resolutions():
    m = cm.MultiResFile(DATA / "cooler_test_file.mcool")
    assert m.resolutions() == [100000, 1000000]
    assert m[1000000].resolution() == 1000000
    h = cm.MultiResFile(DATA / "CN.mm9.multires.hic")
    assert h.resolutions() == [10000000, 20000000, 50000000]
    assert h[20000000].nbins() > 0
    with pytest.raises(ValueError, match="resolution: .* no resolution 5"):
        m[5]
    with pytest.raises(cm.ContactmapError, match="not a multi-resolution file"):
        cm.MultiResFile(YEAST)


def test_file_takes_the_resolution_apart_as_hictkpy():
    levels = ((DATA / "cooler_test_file.mcool", 100000), (DATA / "CN.mm9.multires.hic", 20000000))
    for path, level in levels:
        by_option = cm.File(path, resolution=level)
        by_uri = cm.File(f"{path}::/resolutions/{level}")
        assert by_option.uri() == by_uri.uri()
        assert by_option.resolution() == level
        np.testing.assert_array_equal(by_option.fetch().to_numpy(), by_uri.fetch().to_numpy())
    assert cm.File(MM9, resolution=10000000).resolution() == 10000000
    with pytest.raises(cm.ContactmapError, match="has no resolution 5000: it has 100000, 1000000"):
        cm.File(DATA / "cooler_test_file.mcool", resolution=5000)
    with pytest.raises(cm.ContactmapError, match="holds one resolution, 10000000 bp"):
        cm.File(MM9, resolution=5000)
    with pytest.raises(ValueError, match="resolution"):
        cm.File(MM9, resolution=0)


# ---------------------------------------------------------------------------------------------
# Analyses against cooltools


def test_expected_cis_equals_cooltools():
    for key, uri in [("dm6_100kb", DM6), ("mm9_CN_10Mb", MM9)]:
        ref = pd.read_csv(REF / "numerics" / f"{key}.expected_cis.balanced_storedweight.tsv.gz", sep="\t")
        ours = cm.expected_cis(uri, ignore_diags=2)
        assert list(ours.columns) == list(ref.columns), key
        assert_columns_close(ours, ref, 1e-8, f"{key} expected balanced")
        raw_ref = pd.read_csv(REF / "numerics" / f"{key}.expected_cis.raw.tsv.gz", sep="\t")
        raw = cm.expected_cis(cm.File(uri), clr_weight_name=None)
        assert_columns_close(raw, raw_ref, 1e-8, f"{key} expected raw")


def test_insulation_equals_cooltools():
    ref = pd.read_csv(REF / "tads" / "yeast_10kb.insulation.Li.tsv.gz", sep="\t")
    ours = cm.insulation(YEAST, [30000, 50000, 100000], threshold="Li", min_frac_valid_pixels=0.66)
    assert list(ours.columns) == list(ref.columns)
    assert_columns_close(ours, ref, 1e-8, "yeast insulation")


def test_directionality_equals_cooltools():
    for key, uri, window in [("yeast_10kb", YEAST, 50000), ("dm6_100kb", DM6, 500000)]:
        ref = pd.read_csv(REF / "tads" / f"{key}.directionality_{window}.tsv.gz", sep="\t")
        ours = cm.directionality(uri, window_bp=window, balance="weight", min_dist_bad_bin=2)
        assert list(ours.columns) == list(ref.columns), key
        assert_columns_close(ours, ref, 1e-8, f"{key} directionality")


def test_expected_trans_equals_the_command_line_and_naive_sums():
    ours = cm.expected_trans(MM9)
    cli = cli_table("expected", MM9, "--trans")
    assert list(ours.columns) == list(cli.columns)
    assert_columns_close(ours, cli, 0, "expected_trans vs CLI")
    # one block summed by hand from the pixels: chr1 x chr2, both weights finite
    f = cm.File(MM9)
    w = f.weights("weight")
    a0, a1 = f._native.region_bins("chr1")
    b0, b1 = f._native.region_bins("chr2")
    block = f.fetch("chr1", "chr2").to_numpy()
    ok = np.outer(~np.isnan(w[a0:a1]), ~np.isnan(w[b0:b1]))
    row = ours[(ours.region1 == "chr1") & (ours.region2 == "chr2")].iloc[0]
    assert row["n_valid"] == ok.sum()
    assert row["count.sum"] == pytest.approx(block[ok].sum(), rel=1e-12)
    balanced = block * np.outer(w[a0:a1], w[b0:b1])
    assert row["balanced.sum"] == pytest.approx(balanced[ok].sum(), rel=1e-12)


def test_eigs_cis_equals_cooltools():
    # cooltools 0.7.1 eigs_cis on dm6, phased by the track it was given (masked where the
    # weight is NaN, as the library test does)
    comp = REF / "compartments"
    f = cm.File(DM6)
    w = f.weights("weight")
    track = pd.read_csv(comp / "dm6_100kb.phasing.tsv.gz", sep="\t")
    assert len(track) == len(w)
    track.loc[np.isnan(w), "track"] = np.nan
    eigvals, eigvecs = cm.eigs_cis(f, phasing_track=track, n_eigs=3)
    vals = pd.read_csv(comp / "dm6_100kb.eigs_cis_phased.vals.tsv.gz", sep="\t")
    vecs = pd.read_csv(comp / "dm6_100kb.eigs_cis_phased.vecs.tsv.gz", sep="\t")
    assert list(eigvals.columns) == list(vals.columns)
    assert_columns_close(eigvals, vals, 1e-8, "dm6 eigenvalues")
    assert list(eigvecs.columns[:3]) == ["chrom", "start", "end"] and "weight" in eigvecs.columns
    assert_columns_close(eigvecs[["E1", "E2", "E3"]], vecs, 1e-8, "dm6 eigenvectors")


def test_eigs_trans_equals_cooltools():
    comp = REF / "compartments"
    vals = pd.read_csv(comp / "mm9_10Mb.eigs_trans.vals.tsv.gz", sep="\t")
    vecs = pd.read_csv(comp / "mm9_10Mb.eigs_trans.vecs.tsv.gz", sep="\t")
    eigvals, eigvecs = cm.eigs_trans(MM9)
    assert_columns_close(eigvals, vals, 1e-8, "mm9 trans eigenvalues")
    for column in ["E1", "E2", "E3"]:
        # without a phasing track the signs are arbitrary, in cooltools too
        ours, theirs = eigvecs[column].to_numpy(), vecs[column].to_numpy()
        assert np.array_equal(np.isnan(ours), np.isnan(theirs)), column
        ok = ~np.isnan(theirs)
        sign = np.sign(np.dot(ours[ok], theirs[ok]))
        np.testing.assert_allclose(sign * ours[ok], theirs[ok], rtol=1e-8, atol=1e-12)


def test_saddles_equal_cooltools():
    comp = REF / "compartments"

    def assert_saddle(S, C, name):
        ref = pd.read_csv(comp / name, sep="\t")
        n = S.shape[0]
        assert len(ref) == n * n, name
        i, j = ref["i"].to_numpy(), ref["j"].to_numpy()
        np.testing.assert_array_equal(C[i, j], ref["count"].to_numpy(), err_msg=name)
        want = ref["sum"].to_numpy()
        ok = ~np.isnan(want)
        np.testing.assert_allclose(S[i, j][ok], want[ok], rtol=1e-8, err_msg=name)

    # cis: dm6 with cooltools' own phased E1 as the track (masked where the weight is NaN)
    f = cm.File(DM6)
    w = f.weights("weight")
    e1 = pd.read_csv(comp / "dm6_100kb.eigs_cis_phased.vecs.tsv.gz", sep="\t")["E1"].to_numpy()
    e1 = np.where(np.isnan(w), np.nan, e1)
    bins = f.bins()[["chrom", "start", "end"]].assign(E1=e1)
    digitized, edges = cm.digitize(bins, 10, qrange=(0.025, 0.975))
    ref_edges = pd.read_csv(comp / "dm6_100kb.saddle_edges.tsv.gz", sep="\t")["edge"].to_numpy()
    np.testing.assert_allclose(edges, ref_edges, rtol=0, atol=1e-9)
    assert "E1.d" in digitized.columns and digitized["E1.d"].max() == 11
    exp = cm.expected_cis(f)
    S, C = cm.saddle(f, exp, bins, "cis", n_bins=10, qrange=(0.025, 0.975), min_diag=3)
    assert_saddle(S, C, "dm6_100kb.saddle.tsv.gz")
    strength = pd.read_csv(comp / "dm6_100kb.saddle_strength.tsv.gz", sep="\t")["strength"]
    # cooltools' entry k = 0 is a placeholder 0
    np.testing.assert_allclose(cm.saddle_strength(S, C)[1:], strength.to_numpy()[1:], rtol=1e-8)
    # trim_outliers: cooltools' arrays without the outer classes
    St, Ct = cm.saddle(f, exp, bins, "cis", n_bins=10, qrange=(0.025, 0.975), trim_outliers=True)
    assert St.shape == (10, 10)
    np.testing.assert_array_equal(Ct, C[1:-1, 1:-1])
    np.testing.assert_array_equal(St, S[1:-1, 1:-1])
    # trans: mm9 with cooltools' trans E1
    g = cm.File(MM9)
    w = g.weights("weight")
    e1 = pd.read_csv(comp / "mm9_10Mb.eigs_trans.vecs.tsv.gz", sep="\t")["E1"].to_numpy()
    e1 = np.where(np.isnan(w), np.nan, e1)
    S, C = cm.saddle(g, cm.expected_trans(g), e1, "trans", n_bins=10, qrange=(0.025, 0.975))
    assert_saddle(S, C, "mm9_10Mb.saddle_trans.tsv.gz")


def test_ice_equals_cooler_balance():
    for key, uri in [("mm9_CN_10Mb", MM9), ("gm12878_2Mb", GM12878)]:
        for mode, cis_only in [("gw", False), ("cis", True)]:
            ref = pd.read_csv(REF / "numerics" / f"{key}.ice_{mode}.weights.tsv.gz", sep="\t")
            weights, info = cm.balance(uri, cis_only=cis_only)
            want = ref["weight"].to_numpy()
            assert np.array_equal(np.isnan(weights), np.isnan(want)), key
            ok = ~np.isnan(want)
            # cooler's own tolerance leaves the last digits to the iteration order
            np.testing.assert_allclose(weights[ok], want[ok], rtol=1e-6)
            assert info["converged"] and info["n_masked"] == int((~ok).sum())


# ---------------------------------------------------------------------------------------------
# The same answers as the command line


def test_expected_and_insulation_equal_the_command_line():
    ours = cm.expected_cis(YEAST)
    cli = cli_table("expected", YEAST)
    assert_columns_close(ours, cli, 0, "expected vs CLI")
    ours = cm.insulation(YEAST, 50000)
    cli = cli_table("tads", YEAST, "--method", "insulation", "--window", "50000", "-o", "-")
    assert_columns_close(ours, cli, 0, "insulation vs CLI")


# ---------------------------------------------------------------------------------------------
# Beside cooler and h5py in one process


def test_equals_cooler_in_the_same_process_and_takes_its_cooler_objects(tmp_path):
    cooler = pytest.importorskip("cooler")
    h5py = pytest.importorskip("h5py")
    clr = cooler.Cooler(DM6)
    f = cm.File(clr)  # a cooler.Cooler: its uri
    assert f.uri() == clr.uri
    for r1, r2 in [
        ("chr2L", None),
        ("chr2L:1,000,000-3,000,000", "chr2L:2,000,000-5,000,000"),
        ("chr3R:0-4,000,000", "chrX"),
        ("chrX", "chr3R:0-4,000,000"),
    ]:
        for balance, norm in [(True, "weight"), (False, None)]:
            theirs = clr.matrix(balance=balance).fetch(r1, r2)
            ours = f.fetch(r1, r2, normalization=norm).to_numpy()
            assert np.array_equal(ours, theirs, equal_nan=True), (r1, r2, balance)
    # a file that h5py (cooler's library) holds open, for writing too: contactmap opens files
    # without HDF5 file locking, so both work (the two libhdf5 copies live side by side)
    path = tmp_path / "copy.cool"
    shutil.copy(YEAST, path)
    with h5py.File(path, "r+") as h:
        assert "pixels" in h
        g = cm.File(path)
        assert g.fetch("chrI").nnz() == cm.File(YEAST).fetch("chrI").nnz()
    g = cm.File(path)
    with h5py.File(path, "r+") as h:
        h.attrs["touched"] = 1
    assert cooler.Cooler(str(path)).info["nnz"] == g.fetch().nnz()


# ---------------------------------------------------------------------------------------------
# Errors, threads


def test_errors_are_python_exceptions_with_the_cli_message():
    with pytest.raises(FileNotFoundError, match="no-such.cool"):
        cm.File(DATA / "no-such.cool")
    f = cm.File(YEAST)
    with pytest.raises(cm.ContactmapError, match="no chromosome 'chrZZ'"):
        f.fetch("chrZZ")
    with pytest.raises(ValueError, match="no weight column 'KR'"):
        f.fetch("chrI", normalization="KR").to_numpy()
    with pytest.raises(cm.ContactmapError, match="method 'nope'"):
        cm.balance(f, method="nope")
    with pytest.raises(cm.ContactmapError):
        cm.File(DATA / "README.md")
    with pytest.raises(TypeError, match="expected a path"):
        cm.File(42)


def test_errors_come_as_the_exception_class_of_their_kind(tmp_path):
    # a parameter: ContactmapError, a ValueError, and not a FormatError
    f = cm.File(YEAST)
    with pytest.raises(cm.ContactmapError, match="method 'nope'") as bad:
        cm.balance(f, method="nope")
    assert isinstance(bad.value, ValueError) and not isinstance(bad.value, cm.FormatError)
    # a corrupt file (a cooler cut after 4 kB): FormatError, naming the file
    truncated = tmp_path / "truncated.cool"
    truncated.write_bytes(Path(YEAST).read_bytes()[:4096])
    with pytest.raises(cm.FormatError, match="truncated.cool: not a readable HDF5 file"):
        cm.File(truncated)
    # a structure with a bad line (a letter in a coordinate): FormatError naming file and line
    with gzip.open(DATA / "protein" / "1aapA" / "1aapA.pdb.gz", "rt") as pdb:
        lines = pdb.read().splitlines(keepends=True)
    at = next(i for i, line in enumerate(lines) if line.startswith("ATOM"))
    lines[at] = lines[at][:30] + "   xx.xxx" + lines[at][39:]
    bad = tmp_path / "bad.pdb"
    bad.write_text("".join(lines))
    with pytest.raises(cm.FormatError, match=f"bad.pdb:{at + 1}: x"):
        cm.read_structure(bad)
    # what the operating system refuses: its OSError subclass, not a ContactmapError
    with pytest.raises(FileNotFoundError, match="no-such.cool") as missing:
        cm.File(tmp_path / "no-such.cool")
    assert not isinstance(missing.value, cm.ContactmapError)
    with pytest.raises(IsADirectoryError):
        cm.File(tmp_path)


def test_a_call_releases_the_gil():
    # While one thread runs contactmap, another runs Python: its ticks land inside the call.
    f = cm.File(GM12878)
    calls: list[tuple[float, float]] = []
    ticks: list[float] = []
    done = threading.Event()

    def work() -> None:
        for _ in range(5):
            t0 = time.perf_counter()
            cm.balance(f)
            calls.append((t0, time.perf_counter()))
        done.set()

    def tick() -> None:
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.0005)

    threads = [threading.Thread(target=work), threading.Thread(target=tick)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    inside = sum(any(a < t < b for a, b in calls) for t in ticks)
    assert inside > 0, f"no Python tick during {len(calls)} calls: the GIL was held"


def test_ctrl_c_stops_a_long_call():
    # ICE to a tolerance it never reaches (the variance stays near 1e-28): minutes of work,
    # stopped by SIGINT as Ctrl-C sends it; the library runs normally afterwards.
    # Python's own Ctrl-C handler is installed for the test: a process started in the
    # background by a non-interactive shell (`make test &`, nohup) inherits SIGINT ignored,
    # and there Ctrl-C rightly interrupts nothing (this test hung so).
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        f = cm.File(GM12878)
        timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
        t0 = time.perf_counter()
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            cm.balance(f, tol=1e-300, max_iters=10**9)
        assert time.perf_counter() - t0 < 10
    finally:
        signal.signal(signal.SIGINT, previous)
    weights, info = cm.balance(f)
    assert info["converged"] and np.isfinite(weights).sum() > 0


def test_the_worked_examples_of_the_docs_run(monkeypatch):
    # docs/python.md's worked example and the README's, as written (paths relative to the clone)
    monkeypatch.chdir(ROOT)
    for doc in (ROOT / "docs" / "python.md", ROOT / "README.md"):
        text = doc.read_text()
        blocks = text.split("```python\n")[1:]
        assert blocks, f"{doc}: no python example"
        for block in blocks:
            code = block.split("```", 1)[0]
            namespace: dict = {}
            exec(compile(code, str(doc), "exec"), namespace)
            assert "cm" in namespace
