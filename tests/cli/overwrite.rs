//! Issue 26, outputs that would destroy inputs and temporaries that could be hijacked:
//!
//! - every command whose output is one of its inputs (the same path, a symbolic or hard link to
//!   it, the file of an `.mcool::/resolutions/N` URI, another spelling of the path) refuses in one
//!   line with exit 2 and leaves the input byte for byte as it was; two outputs of one command on
//!   one path are refused the same way;
//! - with symbolic links planted at the temporary names the next process would use (another
//!   user's attack in a shared folder), every writer (text, gzip text, .cool, .mcool, .hic, PNG,
//!   SVG) leaves the link's target untouched and writes a regular file at its output;
//! - a link planted at the lock file of `balance --store` is refused.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::{data, run_err, run_ok};

/// Copy fixture `name` into `dir` as `as_name`; return its path.
fn copy(name: &str, dir: &Path, as_name: &str) -> PathBuf {
    let path = dir.join(as_name);
    std::fs::copy(data(name), &path).unwrap();
    path
}

fn text(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// Run `args`, require a one-line refusal naming `needle`, and that every file of `kept` is
/// byte for byte what it was.
fn refused(args: &[&str], needle: &str, kept: &[&Path]) {
    let before: Vec<Vec<u8>> = kept.iter().map(|p| std::fs::read(p).unwrap()).collect();
    let message = run_err(args);
    assert!(message.contains(needle), "{args:?}: {message}");
    assert!(message.contains("nothing was written"), "{message}");
    for (path, bytes) in kept.iter().zip(before) {
        assert!(
            std::fs::read(path).unwrap() == bytes,
            "{args:?} changed {}",
            path.display()
        );
    }
}

const IS_INPUT: &str = "is the input";
const SAME_FILE: &str = "is the same file as the input";
const TWO_OUTPUTS: &str = "is named for two outputs";

#[test]
fn matrix_writers_refuse_to_overwrite_their_input() {
    let dir = tempfile::tempdir().unwrap();
    let same = copy("yeast.10kb.cool", dir.path(), "same.cool");
    let other = copy("CN.mm9.10000kb.cool", dir.path(), "other.cool");
    let s = text(&same);
    // The report's case: normalize in place.
    refused(&["normalize", s, s], IS_INPUT, &[&same]);
    refused(&["convert", s, s], IS_INPUT, &[&same]);
    refused(&["merge", s, text(&other), "-o", s], IS_INPUT, &[&same]);
    refused(&["balance", s, "-o", s], IS_INPUT, &[&same]);
    // Links and other spellings of the path.
    let soft = dir.path().join("soft.cool");
    std::os::unix::fs::symlink(&same, &soft).unwrap();
    let hard = dir.path().join("hard.cool");
    std::fs::hard_link(&same, &hard).unwrap();
    refused(&["normalize", s, text(&soft)], SAME_FILE, &[&same]);
    refused(&["normalize", s, text(&hard)], SAME_FILE, &[&same]);
    let dotted = dir.path().join(".").join("same.cool");
    refused(&["convert", s, text(&dotted)], IS_INPUT, &[&same]);
    // The file of an .mcool URI, given or made by zoomify's default output name.
    let mcool = copy("cooler_test_file.mcool", dir.path(), "dm6.mcool");
    let level = format!("{}::/resolutions/100000", mcool.display());
    refused(&["convert", &level, text(&mcool)], IS_INPUT, &[&mcool]);
    refused(&["zoomify", &level], IS_INPUT, &[&mcool]);
    refused(&["normalize", &level, text(&mcool)], IS_INPUT, &[&mcool]);
    // A .hic input.
    let hic = copy("hic_test_file.hic", dir.path(), "dm6.hic");
    refused(&["convert", text(&hic), text(&hic)], IS_INPUT, &[&hic]);
    // Validation: the repair and the report.
    refused(&["validate", s, "--repair", s], IS_INPUT, &[&same]);
    refused(&["validate", s, "-o", s], IS_INPUT, &[&same]);
    // Text outputs of the analyses, and auxiliary inputs (a bin table, a view).
    refused(&["dump", s, "-o", s], IS_INPUT, &[&same]);
    refused(&["info", text(&other), s, "-o", s], IS_INPUT, &[&same]);
    refused(&["expected", s, "-o", s], IS_INPUT, &[&same]);
    refused(&["tads", s, "--boundaries", s], IS_INPUT, &[&same]);
    let bins = dir.path().join("bins.bed");
    std::fs::write(&bins, b"chrI\t0\t230218\n").unwrap();
    refused(
        &["expected", s, "--view", text(&bins), "-o", text(&bins)],
        IS_INPUT,
        &[&bins],
    );
    let bg2 = copy(
        "hg19.GM12878-MboI.matrix.2000kb.bg2.gz",
        dir.path(),
        "m.bg2.gz",
    );
    let bed = copy("hg19.bins.2000kb.bed.gz", dir.path(), "bins.bed.gz");
    refused(
        &["convert", text(&bg2), "--bins", text(&bed), text(&bed)],
        IS_INPUT,
        &[&bg2, &bed],
    );
}

#[test]
fn analyses_with_prefixes_refuse_an_output_that_is_their_track() {
    let dir = tempfile::tempdir().unwrap();
    let mcool = copy("cooler_test_file.mcool", dir.path(), "dm6.mcool");
    let level = format!("{}::/resolutions/100000", mcool.display());
    let prefix = dir.path().join("p");
    // A phasing track that is the vecs table this run would write.
    let vecs = dir.path().join("p.cis.vecs.tsv");
    run_ok(&["compartments", &level, "-o", text(&prefix)]);
    let track = format!("{}:E1", vecs.display());
    refused(
        &[
            "compartments",
            &level,
            "--phasing-track",
            &track,
            "-o",
            text(&prefix),
        ],
        IS_INPUT,
        &[&vecs, &mcool],
    );
    // A saddle track named like one of the saddle's own outputs.
    let saddle_track = dir.path().join("s.saddle.tsv");
    std::fs::copy(&vecs, &saddle_track).unwrap();
    let track = format!("{}:E1", saddle_track.display());
    let saddle_prefix = dir.path().join("s");
    refused(
        &[
            "saddle",
            &level,
            "--track",
            &track,
            "-o",
            text(&saddle_prefix),
        ],
        IS_INPUT,
        &[&saddle_track],
    );
    // Score and plot read tables too.
    let truth = dir.path().join("truth.bed");
    std::fs::write(&truth, b"chr2L\t0\t100000\tA\n").unwrap();
    refused(
        &[
            "score",
            "compartments",
            "--truth",
            text(&truth),
            text(&vecs),
            "-o",
            text(&vecs),
        ],
        IS_INPUT,
        &[&vecs],
    );
    refused(
        &[
            "score",
            "boundaries",
            "--truth",
            text(&truth),
            text(&truth),
            "-o",
            text(&truth),
        ],
        IS_INPUT,
        &[&truth],
    );
    refused(
        &[
            "plot",
            "map",
            &level,
            "-r",
            "chr2L",
            "--to",
            "png",
            "-o",
            text(&mcool),
        ],
        IS_INPUT,
        &[&mcool],
    );
    refused(
        &[
            "plot",
            "expected",
            &level,
            "--to",
            "svg",
            "-o",
            text(&mcool),
        ],
        IS_INPUT,
        &[&mcool],
    );
    let saddle_table = dir.path().join("t.saddle.tsv");
    std::fs::write(&saddle_table, b"i\tj\tsum\tcount\n").unwrap();
    refused(
        &[
            "plot",
            "saddle",
            text(&saddle_table),
            "--to",
            "svg",
            "-o",
            text(&saddle_table),
        ],
        IS_INPUT,
        &[&saddle_table],
    );
}

#[test]
fn protein_commands_refuse_to_overwrite_their_input() {
    let dir = tempfile::tempdir().unwrap();
    let pdb = copy("protein/1guuA/1guuA.pdb.gz", dir.path(), "1guuA.pdb.gz");
    let rr = copy("protein/1guuA/1guuA.contact.rr", dir.path(), "1guuA.rr");
    refused(
        &["contacts", text(&pdb), "-o", text(&pdb)],
        IS_INPUT,
        &[&pdb],
    );
    refused(
        &[
            "score",
            "contacts",
            "--structure",
            text(&pdb),
            text(&rr),
            "-o",
            text(&rr),
        ],
        IS_INPUT,
        &[&rr],
    );
    refused(
        &[
            "score",
            "contacts",
            "--structure",
            text(&pdb),
            text(&rr),
            "--curve",
            text(&pdb),
        ],
        IS_INPUT,
        &[&pdb],
    );
    refused(
        &["score", "overlap", text(&rr), text(&rr), "-o", text(&rr)],
        IS_INPUT,
        &[&rr],
    );
    refused(
        &[
            "plot",
            "contacts",
            "--structure",
            text(&pdb),
            text(&rr),
            "--to",
            "png",
            "-o",
            text(&rr),
        ],
        IS_INPUT,
        &[&rr],
    );
}

#[test]
fn two_outputs_on_one_path_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.cool");
    let bed = dir.path().join("x.bed");
    let spelled = dir.path().join(".").join("x.bed");
    let message = run_err(&[
        "simulate",
        "blocks",
        "-o",
        text(&out),
        "--truth-domains",
        text(&bed),
        "--truth-boundaries",
        text(&spelled),
    ]);
    assert!(message.contains(TWO_OUTPUTS), "{message}");
    assert!(!out.exists() && !bed.exists());
    // An input of simulate polymer (--ctcf BED) as one of its truths.
    let ctcf = dir.path().join("ctcf.bed");
    std::fs::write(&ctcf, b"chr1\t10000\t11000\t.\t0\t+\n").unwrap();
    refused(
        &[
            "simulate",
            "polymer",
            "-o",
            text(&out),
            "--chains",
            "50",
            "--extrusion",
            "--ctcf",
            text(&ctcf),
            "--truth-boundaries",
            text(&ctcf),
        ],
        IS_INPUT,
        &[&ctcf],
    );
    let cool = copy("yeast.10kb.cool", dir.path(), "y.cool");
    let track = dir.path().join("t.tsv");
    let message = run_err(&[
        "tads",
        text(&cool),
        "-o",
        text(&track),
        "--boundaries",
        text(&track),
    ]);
    assert!(message.contains(TWO_OUTPUTS), "{message}");
}

/// The last PID the kernel handed out (Linux), or `None` where it cannot be read.
fn last_pid() -> Option<u32> {
    std::fs::read_to_string("/proc/sys/kernel/ns_last_pid")
        .ok()?
        .trim()
        .parse()
        .ok()
}

/// PIDs past the last one, and sequence numbers, at which links are planted.
const PLANTED_PIDS: u32 = 400;
const PLANTED_SEQUENCES: u32 = 4;

/// Run `args` with links to a victim file (half of them dangling, towards files that must not
/// appear) planted at every temporary name `.OUT.PID-SEQ.tmp` the next processes would use, as
/// an attacker sharing the folder would; retried until the child's PID fell among the planted
/// ones. Check that the victim is untouched, nothing appeared at the dangling targets, and `out`
/// is a regular file; return `None` where PIDs cannot be predicted (no `/proc`).
fn run_with_planted_links(dir: &Path, out: &Path, args: &[&str]) -> Option<()> {
    let victim = dir.join("victim.txt");
    std::fs::write(&victim, b"precious").unwrap();
    let name = out.file_name().unwrap().to_string_lossy().into_owned();
    for _ in 0..20 {
        let first = last_pid()? + 1;
        let mut planted = Vec::new();
        for pid in first..first + PLANTED_PIDS {
            for sequence in 0..PLANTED_SEQUENCES {
                let link = dir.join(format!(".{name}.{pid}-{sequence}.tmp"));
                let target = if (pid + sequence) % 2 == 0 {
                    victim.clone()
                } else {
                    dir.join(format!("dangling-{pid}-{sequence}"))
                };
                std::os::unix::fs::symlink(&target, &link).unwrap();
                planted.push(link);
            }
        }
        let child = Command::new(env!("CARGO_BIN_EXE_contactmap"))
            .args(args)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let pid = child.id();
        let output = child.wait_with_output().unwrap();
        for link in planted {
            std::fs::remove_file(link).unwrap();
        }
        assert!(
            output.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&output.stderr)
        );
        assert_eq!(std::fs::read(&victim).unwrap(), b"precious", "{args:?}");
        let left: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.starts_with("dangling") || n.ends_with(".tmp"))
            .collect();
        assert!(left.is_empty(), "{args:?} left {left:?}");
        let kind = out.symlink_metadata().unwrap().file_type();
        assert!(kind.is_file(), "{args:?}: {} is not a file", out.display());
        assert!(out.metadata().unwrap().len() > 0);
        if (first..first + PLANTED_PIDS).contains(&pid) {
            return Some(());
        }
        std::fs::remove_file(out).unwrap();
    }
    panic!("the child's PID never fell among the planted ones");
}

#[test]
fn planted_links_at_temporary_names_are_never_followed() {
    if last_pid().is_none() {
        eprintln!("skipped: /proc/sys/kernel/ns_last_pid cannot be read here");
        return;
    }
    let cool = data("CN.mm9.10000kb.cool");
    let cases: &[(&str, &[&str])] = &[
        ("out.tsv", &["dump", &cool, "-o", "OUT"]),
        ("out.tsv.gz", &["dump", &cool, "-o", "OUT"]),
        ("out.bg2", &["convert", &cool, "OUT"]),
        ("out.cool", &["convert", &cool, "OUT"]),
        ("out.mcool", &["convert", &cool, "OUT"]),
        ("out.hic", &["convert", &cool, "OUT"]),
        (
            "out.png",
            &["plot", "map", &cool, "-r", "chr1", "-o", "OUT"],
        ),
        (
            "out.svg",
            &["plot", "map", &cool, "-r", "chr1", "-o", "OUT"],
        ),
    ];
    for (name, template) in cases {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join(name);
        let args: Vec<&str> = template
            .iter()
            .map(|a| if *a == "OUT" { text(&out) } else { a })
            .collect();
        run_with_planted_links(dir.path(), &out, &args).unwrap();
        if name.ends_with("cool") || name.ends_with(".hic") {
            let uri = if name.ends_with(".mcool") {
                format!("{}::/resolutions/10000000", out.display())
            } else {
                text(&out).to_string()
            };
            run_ok(&["info", &uri]);
        }
    }
}

#[test]
fn balance_store_refuses_a_planted_lock_link() {
    let dir = tempfile::tempdir().unwrap();
    let cool = copy("CN.mm9.10000kb.cool", dir.path(), "m.cool");
    let victim = dir.path().join("victim");
    std::os::unix::fs::symlink(&victim, dir.path().join(".m.cool.lock")).unwrap();
    let message = run_err(&["balance", text(&cool), "--store", "--force"]);
    assert!(message.contains("symbolic link"), "{message}");
    assert!(!victim.exists());
}
