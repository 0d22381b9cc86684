"""Type stubs of the native module (Rust, pyo3): the library's functions, converted."""

from typing import Any, TypedDict, final

import numpy as np
import numpy.typing as npt

__all__ = [
    "ContactmapError",
    "FormatError",
    "NativeFile",
    "NativeTileset",
    "balance",
    "balance_store",
    "contact_frequencies",
    "convert",
    "create_cooler",
    "diff_boundaries",
    "diff_compartments",
    "diff_loops",
    "diff_regions",
    "digitize",
    "directionality",
    "dots",
    "eigs_cis",
    "eigs_trans",
    "expected_cis",
    "expected_trans",
    "insulation",
    "merge",
    "merge_dots",
    "pileup",
    "polymer_map",
    "polymer_stats",
    "read_structure",
    "resolutions",
    "saddle",
    "saddle_strength",
    "score_contacts",
    "simulate_polymer",
    "zoomify",
]

class ContactmapError(ValueError):
    """An input contactmap cannot use: the command line's one-line message."""

class FormatError(ContactmapError):
    """A file or data that does not follow its format, contradicts itself, or is in a layout
    this version does not support."""

_Region = tuple[str, int, int, str | None]
_Column = tuple[str, npt.NDArray[Any]]

@final
class NativeTileset:
    def __new__(cls, path: str) -> NativeTileset: ...
    def tileset_info(self) -> str: ...
    def tiles(self, tile_ids: list[str]) -> str: ...

@final
class NativeFile:
    def __new__(cls, uri: str, resolution: int | None = None) -> NativeFile: ...
    def uri(self) -> str: ...
    def format(self) -> str: ...
    def chromosomes(self) -> list[tuple[str, int]]: ...
    def resolution(self) -> int | None: ...
    def bin_columns(
        self,
    ) -> tuple[npt.NDArray[np.uint32], npt.NDArray[np.uint64], npt.NDArray[np.uint64]]: ...
    def attributes_json(self) -> str: ...
    def weight_names(self) -> list[str]: ...
    def weights(self, name: str) -> npt.NDArray[np.float64]: ...
    def region_bins(self, region: str) -> tuple[int, int]: ...
    def totals(self) -> tuple[int, float]: ...
    def fetch_dense(
        self, rows: tuple[int, int], cols: tuple[int, int], weight_name: str | None = None
    ) -> npt.NDArray[np.float64]: ...
    def fetch_pixels(
        self, rows: tuple[int, int], cols: tuple[int, int], weight_name: str | None = None
    ) -> tuple[
        npt.NDArray[np.int64],
        npt.NDArray[np.int64],
        npt.NDArray[np.float64],
        npt.NDArray[np.float64] | None,
    ]: ...

def expected_cis(
    file: NativeFile,
    view: list[_Region] | None,
    weight_name: str | None,
    ignore_diags: int = 2,
    smooth: bool = True,
    aggregate_smoothed: bool = True,
    smooth_sigma: float = 0.1,
) -> tuple[list[str], list[str], list[_Column]]: ...
def expected_trans(
    file: NativeFile, view: list[_Region] | None, weight_name: str | None
) -> tuple[list[str], list[str], list[_Column]]: ...
def directionality(
    file: NativeFile,
    window_bp: int,
    view: list[_Region] | None,
    weight_name: str | None,
    ignore_diags: int | None = None,
    min_dist_bad_bin: int = 2,
) -> tuple[
    npt.NDArray[np.uint64],
    npt.NDArray[np.bool_],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
]: ...
def insulation(
    file: NativeFile,
    window_bp: list[int],
    view: list[_Region] | None,
    weight_name: str | None,
    ignore_diags: int | None = None,
    min_frac_valid_pixels: float = 0.66,
    min_dist_bad_bin: int = 0,
    threshold: str = "Li",
    append_raw_scores: bool = False,
) -> tuple[
    npt.NDArray[np.uint64],
    npt.NDArray[np.uint32],
    npt.NDArray[np.bool_],
    list[str],
    list[_Column],
]: ...
def eigs_cis(
    file: NativeFile,
    view: list[_Region] | None,
    weight_name: str,
    phasing_track: list[float] | None = None,
    n_eigs: int = 3,
    ignore_diags: int | None = None,
    clip_percentile: float = 99.9,
    sort_metric: str | None = None,
) -> tuple[
    list[tuple[str, str, int, int, int, int, list[float], list[list[float]]]], list[str]
]: ...
def eigs_trans(
    file: NativeFile,
    weight_name: str,
    phasing_track: list[float] | None = None,
    n_eigs: int = 3,
    perc_top: float = 99.95,
    perc_bottom: float = 1.0,
    sort_metric: str | None = None,
) -> tuple[list[float], list[list[float]], list[str]]: ...
def digitize(
    track: list[float],
    n_bins: int,
    qrange: tuple[float, float] | None = None,
    vrange: tuple[float, float] | None = None,
) -> tuple[npt.NDArray[np.int32], npt.NDArray[np.float64]]: ...
def saddle(
    file: NativeFile,
    track: list[float],
    expected: list[list[float]],
    weight_name: str,
    view: list[_Region] | None,
    trans: bool = False,
    n_bins: int = 50,
    qrange: tuple[float, float] | None = None,
    vrange: tuple[float, float] | None = None,
    min_diag: int = 3,
    max_diag: int | None = None,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64], int]: ...
def saddle_strength(
    sum: list[float], count: list[float], n: int
) -> npt.NDArray[np.float64]: ...
class _BalanceOptions(TypedDict):
    """The options of balance() and balance_store(), by name (None: the method's default)."""

    method: str
    cis_only: bool
    ignore_diags: int | None
    mad_max: float | None
    min_nnz: int | None
    min_count: float | None
    tol: float | None
    max_iters: int | None
    rescale_marginals: bool | None

def balance(
    file: NativeFile, options: _BalanceOptions
) -> tuple[npt.NDArray[np.float64], dict[str, Any]]: ...
def balance_store(
    uri: str, name: str, overwrite: bool, store_unconverged: bool, options: _BalanceOptions
) -> tuple[npt.NDArray[np.float64], dict[str, Any]]: ...
def resolutions(path: str) -> list[int]: ...
def diff_loops(
    first: list[str],
    second: list[str],
    loops: str | None = None,
    half_width: int = 1,
    alpha: float = 0.05,
    cooks_filter: bool = True,
) -> list[tuple[str, Any]]: ...
def diff_boundaries(
    first: list[str],
    second: list[str],
    window_bp: int | None = None,
    threshold: str = "li",
    ignore_diags: int = 2,
    match_bins: int = 2,
    alpha: float = 0.05,
    weight_name: str = "weight",
) -> str: ...
def diff_compartments(
    first: list[str],
    second: list[str],
    track: list[float] | None = None,
    ignore_diags: int = 2,
    clip_percentile: float = 99.9,
    alpha: float = 0.05,
    weight_name: str = "weight",
) -> tuple[str, str]: ...
def diff_regions(
    reference: str,
    query: str,
    pairs: str | None = None,
    window_bp: int | None = None,
    step_bp: int | None = None,
    raw: bool = False,
    weight_name: str = "weight",
    min_bins: int = 20,
    mappability_cutoff: float = 0.1,
    relative_window: float = 1.0,
    absolute_window: int | None = None,
) -> str: ...
def dots(
    file: NativeFile,
    view: list[_Region] | None,
    weight_name: str,
    expected: list[list[float]],
    w: int | None = None,
    p: int | None = None,
    max_separation_bp: int = 10_000_000,
    max_nans_tolerated: int = 1,
    n_lambda_bins: int = 40,
    fdr: float = 0.1,
    clustering_radius_bp: float | None = ...,
    cluster_filtering: bool = True,
) -> tuple[list[str], list[str], list[_Column]]: ...

def merge_dots(
    lists: list[tuple[str, int, list[str], list[list[str]]]],
    near_diagonal_bp: int,
    strong_count: float,
) -> str: ...

_PileupGroup = tuple[
    str,
    str | None,
    tuple[int, int | None] | None,
    list[str],
    npt.NDArray[np.float64],
    npt.NDArray[np.uint64],
    int,
    int | None,
]

def pileup(
    file: NativeFile,
    bedpe: bool,
    header: list[str] | None,
    rows: list[list[str]],
    view: list[_Region] | None,
    weight_name: str | None,
    expected: list[list[float]] | None,
    local: bool = False,
    flank_bp: int = 100_000,
    min_dist_bp: float | None = None,
    max_dist_bp: float | None = None,
    ignore_diags: int = 2,
    rescale: tuple[float, int] | None = None,
    shifts: tuple[int, int, int, int] | None = None,
    by_distance: list[int] | None = None,
    by_strand: bool = False,
    flip_negative_strand: bool = False,
    groupby: list[str] = ...,
    trans: bool = False,
    coverage_norm: str | None = None,
) -> tuple[list[_PileupGroup], dict[str, Any]]: ...
def convert(
    input: str,
    output: str,
    resolutions: list[str] | None = None,
    assembly: str | None = None,
    normalizations: list[str] | None = None,
    compression_level: int = 6,
) -> list[str]: ...
def zoomify(
    input: str,
    output: str,
    resolutions: list[str],
    balance: bool = False,
    assembly: str | None = None,
) -> tuple[list[int], list[str]]: ...
def merge(
    inputs: list[str],
    output: str,
    resolutions: list[str] | None = None,
    assembly: str | None = None,
) -> list[str]: ...
def create_cooler(
    path: str,
    chroms: list[tuple[str, int]],
    bin_chrom: npt.NDArray[np.int64],
    bin_start: npt.NDArray[np.int64],
    bin_end: npt.NDArray[np.int64],
    weights: list[tuple[str, list[float]]],
    bin1: npt.NDArray[np.int64],
    bin2: npt.NDArray[np.int64],
    count: npt.NDArray[np.float64],
    integer: bool,
    assembly: str | None = None,
) -> None: ...
def read_structure(
    structure: str,
    chain: str | None = None,
    atom: str = "cb",
    cutoff: float = 8.0,
    le: bool = False,
    fasta: str | None = None,
    register: str = "auto",
) -> tuple[
    str, npt.NDArray[np.int32], npt.NDArray[np.float64], npt.NDArray[np.bool_], str | None
]: ...
def score_contacts(
    structure: str,
    predictions: list[str],
    chain: str | None = None,
    fasta: str | None = None,
    format: str | None = None,
    atom: str = "cb",
    cutoff: float = 8.0,
    le: bool = False,
    register: str = "auto",
    ranges: list[str] | None = None,
    top: list[str] | None = None,
    min_sep: int | None = None,
    length: str | None = None,
    rounding: str = "floor",
    keep_unobserved: bool = False,
) -> tuple[list[_Column], list[str], list[tuple[str, str]]]: ...
def contact_frequencies(
    trajectories: list[str],
    topology: str,
    definition: str = "cb",
    cutoff: float = 8.0,
    stride: int = 1,
    periodic: bool = True,
    min_sep: int = 3,
) -> tuple[
    list[str],
    list[str],
    list[str],
    list[str],
    list[str],
    npt.NDArray[np.uint64],
    npt.NDArray[np.uint64],
    npt.NDArray[np.uint32],
    int,
]: ...
def polymer_map(
    trajectories: list[str],
    contact_radius: float,
    monomers_per_bin: int = 1,
    chains: list[int] | None = None,
) -> tuple[
    tuple[npt.NDArray[np.int64], npt.NDArray[np.int64], npt.NDArray[np.int64]],
    list[int],
    int,
    int,
]: ...
def polymer_stats(
    trajectories: list[str],
    contact_radius: float = 1.1,
) -> tuple[
    tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]],
    tuple[npt.NDArray[np.uint64], npt.NDArray[np.float64], npt.NDArray[np.float64]],
    tuple[list[str], npt.NDArray[np.float64]],
]: ...
def simulate_polymer(
    options: dict[str, Any],
    device: str = "auto",
    threads: int | None = None,
    output: str | None = None,
) -> tuple[
    list[tuple[str, int]],
    tuple[npt.NDArray[np.uint32], npt.NDArray[np.uint64], npt.NDArray[np.uint64]],
    tuple[npt.NDArray[np.int64], npt.NDArray[np.int64], npt.NDArray[np.int64]],
    npt.NDArray[np.float64] | None,
    npt.NDArray[np.float64],
    tuple[str, str, str | None, str | None],
    tuple[str, str | None, str],
]: ...
