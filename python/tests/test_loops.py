"""Dots and pileups from Python against cooltools 0.7.1 `dots` (data/reference/dots) and
coolpuppy 1.1.0 `pileup` (data/reference/pileup, scripts/pileup_reference.py: the cases below are
that script's calls, argument for argument), and against the command line on the same input."""

from __future__ import annotations

import gzip
import subprocess
from typing import Any

import numpy as np
import pandas as pd
import pytest

import contactmap as cm

from helpers import DATA, REF, assert_columns_close, binary, cli_table

SIM = str(DATA / "sim_extrusion.5kb.cool")
YEAST = str(DATA / "yeast.10kb.cool")


@pytest.mark.parametrize(
    "cool, prefix", [(YEAST, "yeast_10kb"), (SIM, "sim_extrusion_5kb")]
)
def test_dots_equal_cooltools(cool: str, prefix: str) -> None:
    expected = cm.expected_cis(cool)
    dots = cm.dots(cool, expected)
    reference = pd.read_csv(REF / "dots" / f"{prefix}.dots.tsv.gz", sep="\t")
    assert list(dots.columns) == list(reference.columns)
    assert_columns_close(dots, reference, 1e-8, f"{prefix} dots")
    enriched = cm.dots(cool, expected, clustering_radius=None)
    reference = pd.read_csv(REF / "dots" / f"{prefix}.enriched.tsv.gz", sep="\t")
    assert list(enriched.columns) == list(reference.columns)
    assert_columns_close(enriched, reference, 1e-8, f"{prefix} enriched pixels")
    # the command line on the same input: the same table, to the last digit
    assert_columns_close(dots, cli_table("dots", cool), 0.0, f"{prefix} dots vs the CLI")


def test_dots_refuse_what_they_cannot_do() -> None:
    expected = cm.expected_cis(YEAST)
    with pytest.raises(ValueError, match="kernels: custom kernel"):
        cm.dots(YEAST, expected, kernels={"donut": np.ones((3, 3))})
    with pytest.raises(ValueError, match="give both"):
        cm.dots(YEAST, expected, w=5)
    with pytest.raises(cm.ContactmapError, match="n_lambda_bins"):
        cm.dots(YEAST, expected, n_lambda_bins=10)


def reference_cases() -> dict[str, list[dict[str, Any]]]:
    """The pileups of scripts/pileup_reference.py: per case, per group (all last), its header
    fields (n, control_n, group) and grid."""
    cases: dict[str, list[dict[str, Any]]] = {}
    with gzip.open(REF / "pileup" / "pileups.tsv.gz", "rt") as f:
        case: list[dict[str, Any]] = []
        for line in f:
            if line.startswith("## "):
                case = cases.setdefault(line[3:].strip(), [])
            elif line.startswith("# "):
                fields = dict(item.split("=", 1) for item in line[2:].split())
                case.append({**fields, "grid": []})
            else:
                case[-1]["grid"].append([float(v) for v in line.split("\t")])
    return cases


def bed(name: str, names: tuple[str, ...] = ("chrom", "start", "end")) -> pd.DataFrame:
    return pd.read_csv(REF / "pileup" / name, sep="\t", header=None, names=list(names))


def pileup_cases() -> dict[str, tuple[str, Any, dict[str, Any]]]:
    """The script's coolpuppy calls: case -> (map, features, arguments)."""
    loops = pd.read_csv(DATA / "sim_extrusion.truth_loops.bedpe", sep="\t")
    anchors = bed("anchors.bed")
    stranded = bed("anchors.stranded.bed", ("chrom", "start", "end", "name", "score", "strand"))
    grouped = bed("anchors.grouped.bed", ("chrom", "start", "end", "name"))
    grouped_loops = pd.read_csv(REF / "pileup" / "loops.grouped.bedpe", sep="\t")
    yeast_anchors = bed("yeast_anchors.bed")
    trans_pairs = pd.read_csv(
        REF / "pileup" / "yeast_trans.bedpe",
        sep="\t",
        header=None,
        names=["chrom1", "start1", "end1", "chrom2", "start2", "end2"],
    )
    exp = cm.expected_cis(SIM)
    yeast_exp = cm.expected_cis(YEAST)
    return {
        "bedpe_oe": (SIM, loops, dict(features_format="bedpe", expected_df=exp, flank=20000)),
        "bed_raw": (SIM, anchors, dict(clr_weight_name=None, flank=30000, maxdist=400000)),
        "bed_local_oe": (SIM, anchors, dict(local=True, expected_df=exp, flank=50000)),
        "bed_shifts": (SIM, anchors, dict(nshifts=5, seed=7, flank=30000)),
        "bedpe_rescale_shifts": (
            SIM,
            loops,
            dict(rescale=True, rescale_flank=2, rescale_size=11, nshifts=2, seed=3),
        ),
        "bed_by_distance_oe": (
            SIM,
            anchors,
            dict(expected_df=exp, flank=20000, mindist=100000, by_distance=True),
        ),
        "bed_by_strand_flip_oe": (
            SIM,
            stranded,
            dict(
                expected_df=exp,
                flank=20000,
                mindist=100000,
                by_strand=True,
                flip_negative_strand=True,
            ),
        ),
        "bed_groupby_oe": (
            SIM,
            grouped,
            dict(expected_df=exp, flank=20000, mindist=100000, groupby=["name1", "name2"]),
        ),
        "bedpe_groupby_shifts": (
            SIM,
            grouped_loops,
            dict(nshifts=3, seed=9, flank=20000, groupby=["class"]),
        ),
        "yeast_local_rescale_oe": (
            YEAST,
            bed("yeast_domains.bed"),
            dict(local=True, rescale=True, rescale_flank=1, rescale_size=21, expected_df=yeast_exp),
        ),
        "yeast_trans_oe": (
            YEAST,
            yeast_anchors,
            dict(trans=True, expected_df=cm.expected_trans(YEAST), flank=30000),
        ),
        "yeast_trans_bedpe_raw": (
            YEAST,
            trans_pairs,
            dict(trans=True, clr_weight_name=None, flank=20000, mindist=0),
        ),
        "bed_covnorm": (SIM, anchors, dict(clr_weight_name=None, coverage_norm=True, flank=30000)),
    }


CASES = pileup_cases()
REFERENCE = reference_cases()


def _dot_list(width: int, rows: list[tuple[int, int, int, str]]) -> pd.DataFrame:
    """Dots on chr1 of one width: (start1, start2, count, note) each."""
    return pd.DataFrame(
        {
            "chrom1": ["chr1"] * len(rows),
            "start1": [r[0] for r in rows],
            "end1": [r[0] + width for r in rows],
            "chrom2": ["chr1"] * len(rows),
            "start2": [r[1] for r in rows],
            "end2": [r[1] + width for r in rows],
            "count": [r[2] for r in rows],
            "note": [r[3] for r in rows],
        }
    )


def test_merge_dots_keeps_what_hiccups_keeps_as_the_command_line(tmp_path: Any) -> None:
    """HiCCUPS' rule worked by hand (as tests/cli/dots.rs), and the same table as
    `contactmap dots-merge` writes from files."""
    lists = {
        5_000: _dot_list(
            5_000,
            [
                (1_000_000, 1_500_000, 40, "confirmed"),  # a 10 kb call 20 kb away
                (2_000_000, 2_600_000, 30, "unconfirmed"),  # nothing near: dropped
                (3_000_000, 3_105_000, 20, "near-diagonal"),
                (4_000_000, 4_800_000, 101, "strong"),
                (5_000_000, 5_900_000, 100, "not-strong"),  # 100 is not above 100
            ],
        ),
        10_000: _dot_list(
            10_000,
            [
                (1_020_000, 1_500_000, 50, "at-5kb"),  # confirms the first 5 kb call
                (6_000_000, 6_500_000, 60, "only-10kb"),
            ],
        ),
        25_000: _dot_list(
            25_000,
            [
                (6_050_000, 6_500_000, 70, "near-kept"),  # 50 kb from a kept call
                (8_000_000, 8_500_000, 80, "only-25kb"),
            ],
        ),
    }
    merged = cm.merge_dots(lists)
    assert list(merged.columns) == [*lists[5_000].columns, "resolution"]
    assert [f"{n} {r}" for n, r in zip(merged["note"], merged["resolution"])] == [
        "confirmed 5000",
        "near-diagonal 5000",
        "strong 5000",
        "only-10kb 10000",
        "only-25kb 25000",
    ]
    paths = []
    for resolution, frame in lists.items():
        path = tmp_path / f"d{resolution}.bedpe"
        frame.to_csv(path, sep="\t", index=False)
        paths.append(f"{path}@{resolution}")
    pd.testing.assert_frame_equal(merged, cli_table("dots-merge", *paths))
    # the thresholds are the command's options
    assert "not-strong" in set(cm.merge_dots(lists, strong=99)["note"])
    # a resolution the rule does not define: the library's error, naming the list
    with pytest.raises(cm.ContactmapError, match="dots at 7000 bp: calls at 7000 bp"):
        cm.merge_dots({7_000: lists[5_000]})


@pytest.mark.parametrize("case", sorted(CASES))
def test_pileups_equal_coolpuppy(case: str) -> None:
    cool, features, arguments = CASES[case]
    ours = cm.pileup(cool, features, **arguments)
    reference = REFERENCE[case]
    assert len(ours) == len(reference), case
    by_label = {row["group"]: row for _, row in ours.iterrows()}
    for group in reference:
        label = group.get("group", "all")
        assert label in by_label, f"{case}: no group {label} (have {list(by_label)})"
        row = by_label[label]
        assert row["n"] == int(group["n"]), f"{case} {label}: n"
        if "control_n" in group:
            assert row["control_n"] == int(group["control_n"]), f"{case} {label}: control_n"
        want = np.array(group["grid"])
        assert row["data"].shape == want.shape
        np.testing.assert_allclose(
            row["data"], want, rtol=1e-12, atol=0, equal_nan=True, err_msg=f"{case} {label}"
        )
    assert ours["group"].iloc[-1] == "all"


def test_pileup_equals_the_command_line_and_says_what_it_left_out(tmp_path: Any) -> None:
    anchors = bed("anchors.bed")
    ours = cm.pileup(SIM, anchors, expected_df=cm.expected_cis(SIM), flank=20000, maxdist=300000)
    path = tmp_path / "anchors.bed"
    anchors.to_csv(path, sep="\t", header=False, index=False)
    prefix = str(tmp_path / "pup")
    subprocess.run(
        [binary(), "pileup", SIM, str(path), "--flank", "20k", "--maxdist", "300k", "-o", prefix],
        check=True,
        capture_output=True,
    )
    grid = np.loadtxt(f"{prefix}.pileup.tsv", delimiter="\t")
    np.testing.assert_array_equal(ours["data"].iloc[-1], grid)
    skipped = ours.attrs["skipped"]
    assert skipped["distance"] > 0 and skipped["min_dist_bp"] == 2 * 20000 + 2 * 5000
    # the per-pixel counts: every snippet has a value off the left-out diagonals
    assert ours["num"].iloc[-1].max() == ours["n"].iloc[-1]


def test_pileup_refuses_bad_features() -> None:
    with pytest.raises(ValueError, match="features: .* neither BED"):
        cm.pileup(SIM, pd.DataFrame({"a": [1]}))
    bad = pd.DataFrame({"chrom": ["chr1"], "start": ["x"], "end": [10]})
    with pytest.raises(cm.ContactmapError, match="features \\(BED\\).*start 'x'"):
        cm.pileup(SIM, bad)
    with pytest.raises(ValueError, match="by_window: True is not supported"):
        cm.pileup(SIM, bed("anchors.bed"), by_window=True)
