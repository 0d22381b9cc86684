//! A bounded mutation-fuzzing campaign per parser, run in CI (`cargo test --test fuzz`): mutants of
//! the real fixtures in `data/` go through the `contactmap` binary as child processes; every run
//! must end with exit 0 or with exit 2 and one `contactmap: error:` line naming the file (no panic,
//! signal, hang over 10 s, other exit code, other message or file left behind). The mutation engine
//! and the runner are shared with the campaign driver `examples/fuzz_campaign.rs`; see
//! `docs/reliability.md`.
//!
//! The `known_*` tests replay the failing mutants the campaigns found, all fixed since, as
//! regression tests (a mutant is reproduced from its format, campaign seed and index: the
//! fixtures and `fuzz/mutate.rs` must stay as they are for the indices to keep their meaning).
//! A new finding is fixed, then gets its replay here under its id (docs/reliability.md lists the
//! findings).

#[allow(dead_code)]
#[path = "fuzz/harness.rs"]
mod harness;
#[allow(dead_code)]
#[path = "fuzz/mutate.rs"]
mod mutate;

use std::path::Path;

/// Mutants per format in CI, and the campaign seed (fixed, so a failure reproduces). Each mutant
/// goes through every command of its format (up to 11), so 30 mutants are more runs than the 60
/// of three commands were.
const MUTANTS: u64 = 30;
const SEED: u64 = 20_240_601;

/// Run the CI campaign of one format and fail with every failing mutant described.
fn fuzz(name: &str) {
    let indices: Vec<u64> = (0..MUTANTS).collect();
    replay(name, SEED, &indices);
}

/// Run mutants `indices` of campaign `seed` of format `name`; fail with every failing mutant
/// described.
fn replay(name: &str, seed: u64, indices: &[u64]) {
    replay_with(name, seed, indices, None);
}

/// [`replay`], the children's libhdf5 deadline `hdf5_timeout` seconds when given.
fn replay_with(name: &str, seed: u64, indices: &[u64], hdf5_timeout: Option<&str>) {
    let scratch = tempfile::tempdir().expect("scratch folder");
    let mut format = harness::format(name, scratch.path());
    if let Some(timeout) = hdf5_timeout {
        format.hdf5_timeout = timeout.to_string();
    }
    let binary = Path::new(env!("CARGO_BIN_EXE_contactmap"));
    let jobs = std::thread::available_parallelism().map_or(2, |n| n.get().min(4));
    let (summary, failures) = harness::campaign(
        binary,
        &format,
        seed,
        indices,
        jobs,
        scratch.path(),
        &|_| {},
    );
    assert_eq!(summary.mutants, indices.len() as u64);
    let report: String = failures
        .iter()
        .map(|o| harness::describe(&format, seed, o, binary))
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {} {name} mutants failed:\n{report}",
        failures.len(),
        indices.len()
    );
}

#[test]
fn fuzz_h5() {
    fuzz("h5");
}

#[test]
fn fuzz_cool() {
    fuzz("cool");
}

#[test]
fn fuzz_mcool() {
    fuzz("mcool");
}

#[test]
fn fuzz_hic() {
    fuzz("hic");
}

#[test]
fn fuzz_hic_small() {
    fuzz("hic-small");
}

#[test]
fn fuzz_bg2() {
    fuzz("bg2");
}

#[test]
fn fuzz_coo() {
    fuzz("coo");
}

#[test]
fn fuzz_bam() {
    fuzz("bam");
}

#[test]
fn fuzz_sam() {
    fuzz("sam");
}

#[test]
fn fuzz_4dn_pairs() {
    fuzz("4dn-pairs");
}

#[test]
fn fuzz_pairs() {
    fuzz("pairs");
}

#[test]
fn fuzz_bed() {
    fuzz("bed");
}

#[test]
fn fuzz_pdb() {
    fuzz("pdb");
}

#[test]
fn fuzz_mmcif() {
    fuzz("mmcif");
}

#[test]
fn fuzz_rr() {
    fuzz("rr");
}

#[test]
fn fuzz_matrix() {
    fuzz("matrix");
}

#[test]
fn fuzz_npz() {
    fuzz("npz");
}

#[test]
// F-NPY-1: fixed (docs/reliability.md).
fn fuzz_npy() {
    fuzz("npy");
}

#[test]
fn fuzz_xtc() {
    fuzz("xtc");
}

#[test]
fn fuzz_dcd() {
    fuzz("dcd");
}

// Replays of the failing mutants found by the campaigns (docs/reliability.md, findings).

#[test]
/// F-MCOOL-1, fixed: a corrupt global heap made libhdf5 loop forever; the watchdog of
/// src/io/plumbing/hdf5_guard.rs now ends each command with one line and exit 2. A 0.5 s deadline (the
/// campaigns' 2 s: each of the ~20 runs that loop spent it, 44 s of CI; these small files' reads
/// that do not loop take milliseconds).
fn known_mcool_hang() {
    replay_with("mcool", 1, &[238], Some("0.5"));
    replay_with("mcool", 2, &[1022, 1528], Some("0.5"));
}

#[test]
// F-HIC-1: fixed (docs/reliability.md).
fn known_hic_convert_message_without_file() {
    replay("hic", 1, &[129]);
    replay("hic", 2, &[442]);
}

#[test]
// F-NPY-2: fixed (docs/reliability.md).
fn known_npy_header_in_message() {
    replay("npy", 1, &[183, 296]);
}

#[test]
// F-NPY-1: fixed (docs/reliability.md).
fn known_npy_shape_overflow() {
    replay("npy", SEED, &[1, 3, 43]);
    replay("npy", 2, &[4079, 7548, 9739]);
}

#[test]
// F-HIC-2: fixed (docs/reliability.md).
fn known_hic_name_in_message() {
    replay("hic", 3, &[283]);
}

#[test]
// F-MCOOL-2: fixed (docs/reliability.md): an attribute string with invalid UTF-8 made convert
// segfault (hdf5-metno's unchecked `as_str`).
fn known_mcool_invalid_utf8_attribute() {
    replay("mcool", 5, &[2720]);
}

#[test]
// F-HIC-3: fixed (docs/reliability.md): a chromosome pair listed in the master index without a
// matrix at the open resolution gave the band planner a block grid of 0 bins, and dump, convert,
// validate ... divided by zero (found by the independent smoke fuzz on the landed main).
fn known_hic_empty_block_grid() {
    replay("hic-small", 1, &[1499]);
}

#[test]
// F-BAM-1: fixed (docs/reliability.md): a BAM record whose reference id is past the header's
// @SQ lines made `pairs parse` panic (index out of bounds in the pair order).
fn known_bam_reference_past_the_header() {
    replay("bam", 53, &[69]);
}

#[test]
// F-PAIRS-1: fixed (docs/reliability.md): a chromosome with two `#chromsize:` lines stopped
// `convert` with a message that named no file.
fn known_pairs_chromsize_twice() {
    replay("4dn-pairs", 53, &[10, 125]);
}
