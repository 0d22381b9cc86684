//! The fuzz harness: the formats, their seed fixtures and the commands that read them; running a
//! mutant through the binary as a child process and classifying the outcome.
//!
//! Shared by the CI test (`tests/fuzz.rs`) and the campaign driver (`examples/fuzz_campaign.rs`),
//! which include this file (and `mutate.rs`, as the sibling module `mutate`) with `#[path = ...]`.
//! See `docs/reliability.md`.

use std::collections::BTreeMap;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use rand::Rng;

use super::mutate::{self, Kind};

/// A run longer than this is a hang.
pub const HANG: Duration = Duration::from_secs(10);

/// The deadline of each libhdf5 metadata read in the runs (`CONTACTMAP_HDF5_TIMEOUT`, seconds):
/// 2 s unless the environment sets it. The mutants are small files, whose reads take
/// milliseconds; a libhdf5 loop on a corrupt heap (F-MCOOL-1) then costs each run 2 s instead of
/// the binary's default 5 s.
fn hdf5_timeout() -> String {
    std::env::var("CONTACTMAP_HDF5_TIMEOUT").unwrap_or_else(|_| "2".into())
}

/// The formats, in the order of the summary table.
pub const FORMATS: [&str; 20] = [
    "cool",
    "mcool",
    "hic",
    "hic-small",
    "bg2",
    "coo",
    "pairs",
    "bed",
    "pdb",
    "mmcif",
    "rr",
    "matrix",
    "npz",
    "npy",
    "h5",
    "xtc",
    "dcd",
    "bam",
    "sam",
    "4dn-pairs",
];

/// A fixture to mutate and the commands that read a mutant of it.
#[derive(Clone, Debug)]
pub struct Seed {
    /// The seed's bytes (decompressed and shortened for text tables).
    pub bytes: Vec<u8>,
    /// Where it came from (for the report).
    pub origin: String,
    /// The mutant's file name (its extension matters to the format detection).
    pub file_name: String,
    /// Argument lists; `{P}` is the mutant's path, `{O}` an output path next to it.
    pub commands: Vec<Vec<String>>,
}

/// One format of the campaign.
#[derive(Clone, Debug)]
pub struct Format {
    /// Short name (`hic`, `pdb` ...).
    pub name: &'static str,
    /// How its seeds are mutated.
    pub kind: Kind,
    /// Its seeds, drawn uniformly per mutant.
    pub seeds: Vec<Seed>,
    /// Other input files of the commands that an error may name instead of the mutant (a BED
    /// mutant that drops a chromosome makes the BG2 table that uses it wrong).
    pub companions: Vec<String>,
    /// The deadline of each libhdf5 metadata read in its runs, seconds (`CONTACTMAP_HDF5_TIMEOUT`
    /// of the children; [`hdf5_timeout`]'s unless a replay sets another).
    pub hdf5_timeout: String,
}

/// The outcome of one command on one mutant.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Class {
    /// Exit 0.
    Ok,
    /// Exit 2 with one `contactmap: error:` line naming the file.
    CleanError,
    /// `validate` found the file invalid: exit 1, its report on standard output, nothing on
    /// standard error.
    Invalid,
    /// A Rust panic (exit 101 or "panicked at").
    Panic,
    /// Killed by a signal (abort, segfault ...), or exit 134 / 139.
    Signal,
    /// Still running after [`HANG`].
    Hang,
    /// Another exit code.
    OtherExit,
    /// Exit 2, but not exactly one error line naming the file (warnings before it, several
    /// lines, no file name, no `contactmap: error:` prefix).
    BadMessage,
    /// Failed, but left a file (an output or a temporary) behind.
    LeftBehind,
}

impl Class {
    /// All classes, in table order.
    pub const ALL: [Class; 9] = [
        Class::Ok,
        Class::CleanError,
        Class::Invalid,
        Class::Panic,
        Class::Signal,
        Class::Hang,
        Class::OtherExit,
        Class::BadMessage,
        Class::LeftBehind,
    ];

    /// Short name for tables and folder names.
    pub fn name(self) -> &'static str {
        match self {
            Class::Ok => "ok",
            Class::CleanError => "clean-error",
            Class::Invalid => "invalid",
            Class::Panic => "panic",
            Class::Signal => "signal",
            Class::Hang => "hang",
            Class::OtherExit => "other-exit",
            Class::BadMessage => "bad-message",
            Class::LeftBehind => "left-behind",
        }
    }

    /// Whether this outcome is a failure of the campaign.
    pub fn is_failure(self) -> bool {
        !matches!(self, Class::Ok | Class::CleanError | Class::Invalid)
    }
}

/// One command run on a mutant.
#[derive(Clone, Debug)]
pub struct Run {
    /// The arguments (paths included).
    pub args: Vec<String>,
    /// The outcome.
    pub class: Class,
    /// Exit code or signal, in words.
    pub status: String,
    /// Its standard error (the first 4 KiB).
    pub stderr: String,
    /// Why the outcome is a failure (empty when it is not).
    pub why: String,
    /// Wall time.
    pub elapsed: Duration,
}

/// A mutant and its runs.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// Index in the campaign (with the seed and the format, reproduces the mutant).
    pub index: u64,
    /// The seed fixture it came from.
    pub origin: String,
    /// The mutant's file name.
    pub file_name: String,
    /// Where the mutant lay during the runs (a scratch folder, removed since).
    pub path: String,
    /// The mutations applied.
    pub mutations: Vec<String>,
    /// The mutant's bytes, kept only when a run failed.
    pub bytes: Option<Vec<u8>>,
    /// The runs.
    pub runs: Vec<Run>,
}

impl Outcome {
    /// Whether any run failed.
    pub fn failed(&self) -> bool {
        self.runs.iter().any(|r| r.class.is_failure())
    }
}

/// Path of a fixture under `data/`.
pub fn data(name: &str) -> String {
    let path: PathBuf = [env!("CARGO_MANIFEST_DIR"), "data", name].iter().collect();
    path.to_string_lossy().into_owned()
}

/// A gzip fixture's first `max_lines` lines.
fn gunzip_head(name: &str, max_lines: usize) -> Vec<u8> {
    let mut text = Vec::new();
    flate2::read::MultiGzDecoder::new(std::fs::File::open(data(name)).expect("fixture"))
        .read_to_end(&mut text)
        .expect("gzip fixture");
    let end = text
        .iter()
        .enumerate()
        .filter(|&(_, &b)| b == b'\n')
        .nth(max_lines.saturating_sub(1))
        .map_or(text.len(), |(k, _)| k + 1);
    text.truncate(end);
    text
}

/// The first `max_records` records of a BAM (with its header) as SAM text, by noodles.
fn bam_as_sam(path: &str, max_records: usize) -> Vec<u8> {
    use noodles::sam::alignment::io::Write as _;
    let mut reader = noodles::bam::io::Reader::new(std::fs::File::open(path).expect("fixture"));
    let header = reader.read_header().expect("BAM header");
    let mut writer = noodles::sam::io::Writer::new(Vec::new());
    writer.write_header(&header).expect("SAM in memory");
    for record in reader.records().take(max_records) {
        let record = record.expect("BAM record");
        writer
            .write_alignment_record(&header, &record)
            .expect("SAM in memory");
    }
    writer.into_inner()
}

fn strings(args: &[&str]) -> Vec<String> {
    args.iter().map(|s| s.to_string()).collect()
}

/// A fixture's bytes as a seed, decompressed when the fixture is stored gzip-compressed (`.gz`).
fn raw_seed(name: &str, file_name: &str, commands: Vec<Vec<String>>) -> Seed {
    Seed {
        bytes: if name.ends_with(".gz") {
            gunzip_head(name, usize::MAX)
        } else {
            std::fs::read(data(name)).expect("fixture")
        },
        origin: format!("data/{name}"),
        file_name: file_name.into(),
        commands,
    }
}

/// Build the format `name`; companion files it needs (a chrom.sizes, a BG2 table, a bin table)
/// are written into `aux`.
pub fn format(name: &str, aux: &Path) -> Format {
    let bed = data("hg19.bins.2000kb.bed.gz");
    // Every command that reads a matrix, with `options` (a text layout) after the input;
    // `validate` for the formats it checks (.cool, .mcool, .hic).
    let commands = |uri: &str, options: &[&str], validate: Option<&str>| {
        let with = |args: &[&str]| -> Vec<String> {
            let (head, tail) = args.split_at(args.len().min(2));
            strings(&[head, options, tail].concat())
        };
        let mut list = vec![
            with(&["info", uri]),
            with(&["dump", uri]),
            with(&["dump", uri, "-t", "bins"]),
            with(&["convert", uri, "{O}.cool"]),
            with(&["convert", uri, "{O}.hic"]),
            with(&["zoomify", uri, "-o", "{O}.mcool"]),
            with(&["balance", uri, "-o", "{O}.tsv"]),
            with(&["expected", uri, "--raw", "-o", "{O}.tsv"]),
            with(&["tads", uri, "--raw", "-o", "{O}.tsv"]),
            with(&["normalize", uri, "{O}.cool"]),
        ];
        if let Some(file) = validate {
            list.push(strings(&["validate", file]));
        }
        list
    };
    let matrix = |uri: &str| commands(uri, &[], Some("{P}"));
    let protein = |name: &str| data(&format!("protein/{name}"));
    // A prediction: scored, drawn, compared with itself.
    let score = |structure: &str| {
        let structure = protein(structure);
        vec![
            strings(&["score", "contacts", "--structure", &structure, "{P}"]),
            strings(&[
                "score",
                "contacts",
                "--structure",
                &structure,
                "{P}",
                "--tsv",
            ]),
            strings(&[
                "plot",
                "contacts",
                "--structure",
                &structure,
                "{P}",
                "-o",
                "{O}.svg",
            ]),
            strings(&["score", "overlap", "{P}", "{P}", "--length", "100"]),
        ]
    };
    // A structure: its contacts and distances, on its sequence, and a prediction scored and
    // drawn on it.
    let structure = |fasta: &str, prediction: Option<&str>| {
        let fasta = protein(fasta);
        let mut list = vec![
            strings(&["contacts", "{P}"]),
            strings(&["contacts", "{P}", "--matrix"]),
            strings(&["contacts", "{P}", "--fasta", &fasta]),
        ];
        if let Some(prediction) = prediction {
            let prediction = protein(prediction);
            list.push(strings(&[
                "score",
                "contacts",
                "--structure",
                "{P}",
                &prediction,
            ]));
            list.push(strings(&[
                "plot",
                "contacts",
                "--structure",
                "{P}",
                &prediction,
                "-o",
                "{O}.svg",
            ]));
        }
        list
    };
    let (kind, seeds, companions) = match name {
        "cool" => (
            Kind::Binary,
            vec![
                raw_seed("CN.mm9.10000kb.cool", "m.cool", matrix("{P}")),
                raw_seed(
                    "hg19.GM12878-MboI.matrix.2000kb.cool",
                    "m.cool",
                    matrix("{P}"),
                ),
                raw_seed(
                    "cooler_variable_bins_test_file.cool",
                    "m.cool",
                    matrix("{P}"),
                ),
            ],
            vec![],
        ),
        "mcool" => {
            let mut list = matrix("{P}::/resolutions/2");
            list[0] = strings(&["info", "{P}"]);
            (
                Kind::Binary,
                vec![raw_seed("toy.symm.upper.2.mcool", "m.mcool", list)],
                vec![],
            )
        }
        "h5" => (
            Kind::Binary,
            vec![
                raw_seed(
                    "hicexplorer/small_test_matrix.h5",
                    "m.h5",
                    commands("{P}", &[], None),
                ),
                raw_seed(
                    "hicexplorer/ICEcorrected_chr3LHet.h5",
                    "m.h5",
                    commands("{P}", &[], None),
                ),
            ],
            vec![],
        ),
        "hic" => {
            let mut multi = matrix("{P}::/resolutions/10000000");
            multi[0] = strings(&["info", "{P}"]);
            (
                Kind::Binary,
                vec![
                    raw_seed("CN.mm9.multires.hic", "m.hic", multi),
                    raw_seed("hic_test_file.hic", "m.hic", matrix("{P}")),
                ],
                vec![],
            )
        }
        // Small one-resolution .hic v8 files from hictk's writer (a few kB, so mutations reach
        // every part: header, master index, block index, blocks, footer).
        "hic-small" => (
            Kind::Binary,
            vec![
                raw_seed("hic_layouts/both_triangles.hic", "m.hic", matrix("{P}")),
                raw_seed("hic_layouts/past_end.hic", "m.hic", matrix("{P}")),
            ],
            vec![],
        ),
        "bg2" | "coo" | "bed" => {
            let bg2 = gunzip_head("hg19.GM12878-MboI.matrix.2000kb.bg2.gz", 2000);
            let text_commands = |file: &str, format: &str, bins: &str| {
                commands(file, &["--format", format, "--bins", bins], None)
            };
            match name {
                "bg2" => (
                    Kind::Text,
                    vec![Seed {
                        bytes: bg2,
                        origin: "data/hg19.GM12878-MboI.matrix.2000kb.bg2.gz, first 2,000 lines"
                            .into(),
                        file_name: "m.bg2".into(),
                        commands: text_commands("{P}", "bg2", &bed),
                    }],
                    vec![],
                ),
                "coo" => {
                    // The same pixels as `bin1 bin2 count`, numbered by the BED's line.
                    let bins = gunzip_head("hg19.bins.2000kb.bed.gz", usize::MAX);
                    let ids: BTreeMap<(String, String), usize> = String::from_utf8(bins)
                        .expect("utf-8 bins")
                        .lines()
                        .enumerate()
                        .map(|(k, l)| {
                            let f: Vec<&str> = l.split('\t').collect();
                            ((f[0].to_string(), f[1].to_string()), k)
                        })
                        .collect();
                    let coo: String = String::from_utf8(bg2)
                        .expect("utf-8 bg2")
                        .lines()
                        .map(|l| {
                            let f: Vec<&str> = l.split('\t').collect();
                            let a = ids[&(f[0].to_string(), f[1].to_string())];
                            let b = ids[&(f[3].to_string(), f[4].to_string())];
                            format!("{a}\t{b}\t{}\n", f[6])
                        })
                        .collect();
                    (
                        Kind::Text,
                        vec![Seed {
                            bytes: coo.into_bytes(),
                            origin: "data/hg19.GM12878-MboI.matrix.2000kb.bg2.gz, first 2,000 lines as COO"
                                .into(),
                            file_name: "m.coo".into(),
                            commands: text_commands("{P}", "coo", &bed),
                        }],
                        vec![],
                    )
                }
                _ => {
                    let table = aux.join("companion.bg2");
                    std::fs::write(&table, &bg2).expect("write the companion table");
                    let table = table.to_string_lossy().into_owned();
                    (
                        Kind::Text,
                        vec![Seed {
                            bytes: gunzip_head("hg19.bins.2000kb.bed.gz", usize::MAX),
                            origin: "data/hg19.bins.2000kb.bed.gz".into(),
                            file_name: "m.bed".into(),
                            // The mutant as the bins of a text table, and as every other BED
                            // input (one reader, io::bed): a view, a blacklist, boundaries,
                            // domains drawn on a map.
                            commands: {
                                let hg19 = data("hg19.GM12878-MboI.matrix.2000kb.cool");
                                let mut list = text_commands(&table, "bg2", "{P}");
                                list.push(strings(&[
                                    "expected", &hg19, "--raw", "--view", "{P}", "-o", "{O}.tsv",
                                ]));
                                list.push(strings(&[
                                    "balance",
                                    &hg19,
                                    "--blacklist",
                                    "{P}",
                                    "-o",
                                    "{O}.tsv",
                                ]));
                                list.push(strings(&[
                                    "score",
                                    "boundaries",
                                    "--truth",
                                    "{P}",
                                    "{P}",
                                ]));
                                list.push(strings(&[
                                    "plot",
                                    "map",
                                    &hg19,
                                    "--raw",
                                    "-r",
                                    "chr1",
                                    "--domains",
                                    "{P}",
                                    "-o",
                                    "{O}.svg",
                                ]));
                                list
                            },
                        }],
                        vec![table],
                    )
                }
            }
        }
        "pairs" => {
            // hg19 chrom.sizes: the end of each chromosome's last bin.
            let bins = String::from_utf8(gunzip_head("hg19.bins.2000kb.bed.gz", usize::MAX))
                .expect("utf-8 bins");
            let mut sizes: Vec<(String, String)> = Vec::new();
            for line in bins.lines() {
                let f: Vec<&str> = line.split('\t').collect();
                match sizes.last_mut() {
                    Some((chrom, end)) if chrom == f[0] => *end = f[2].to_string(),
                    _ => sizes.push((f[0].to_string(), f[2].to_string())),
                }
            }
            let path = aux.join("hg19.sizes");
            let text: String = sizes.iter().map(|(c, e)| format!("{c}\t{e}\n")).collect();
            std::fs::write(&path, text).expect("write chrom.sizes");
            let sizes = path.to_string_lossy().into_owned();
            let options = [
                "--format",
                "pairs",
                "--bin-size",
                "2000000",
                "--chrom-sizes",
                &sizes,
                "--pairs-columns",
                "1,2,4,5",
            ];
            (
                Kind::Text,
                vec![Seed {
                    bytes: gunzip_head("hg19.GM12878-MboI.pairs.subsample.sorted.txt.gz", 3000),
                    origin:
                        "data/hg19.GM12878-MboI.pairs.subsample.sorted.txt.gz, first 3,000 lines"
                            .into(),
                    file_name: "m.pairs".into(),
                    commands: commands("{P}", &options, None),
                }],
                vec![],
            )
        }
        "pdb" => (
            Kind::Text,
            vec![
                raw_seed(
                    "protein/toxd/toxd.pdb.gz",
                    "m.pdb",
                    structure("toxd/toxd.fasta", Some("toxd/toxd.mat.gz")),
                ),
                raw_seed(
                    "protein/1guuA/1guuA.pdb.gz",
                    "m.pdb",
                    structure("1guuA/1guuA.fasta", Some("1guuA/1guuA.contact.rr")),
                ),
                raw_seed(
                    "protein/1a8o/1A8O.pdb.gz",
                    "m.pdb",
                    structure("1a8o/1A8O.fasta", None),
                ),
            ],
            vec![],
        ),
        "mmcif" => (
            Kind::Text,
            vec![raw_seed(
                "protein/1a8o/1A8O.cif.gz",
                "m.cif",
                structure("1a8o/1A8O.fasta", None),
            )],
            vec![],
        ),
        "rr" => (
            Kind::Text,
            vec![
                raw_seed(
                    "protein/1aapA/1aapA.rr.gz",
                    "m.rr",
                    score("1aapA/1aapA.pdb.gz"),
                ),
                raw_seed(
                    "protein/1guuA/1guuA.contact.rr",
                    "m.rr",
                    score("1guuA/1guuA.pdb.gz"),
                ),
                raw_seed(
                    "protein/1guuA/1guuA.distance.rr",
                    "m.rr",
                    score("1guuA/1guuA.pdb.gz"),
                ),
            ],
            vec![],
        ),
        "matrix" => (
            Kind::Text,
            vec![
                raw_seed(
                    "protein/toxd/toxd.mat.gz",
                    "m.mat",
                    score("toxd/toxd.pdb.gz"),
                ),
                raw_seed(
                    "protein/1atzA/1atzA.apc.mat.gz",
                    "m.mat",
                    score("1atzA/1atzA.pdb.gz"),
                ),
            ],
            vec![],
        ),
        "npz" => (
            Kind::Zip,
            vec![raw_seed(
                "protein/1guuA/1guuA.npz",
                "m.npz",
                score("1guuA/1guuA.pdb.gz"),
            )],
            vec![],
        ),
        "npy" => (
            Kind::Binary,
            vec![
                raw_seed(
                    "protein/1guuA/1guuA.predicted.npy",
                    "m.npy",
                    score("1guuA/1guuA.pdb.gz"),
                ),
                raw_seed(
                    "protein/1guuA/1guuA.true.npy",
                    "m.npy",
                    score("1guuA/1guuA.pdb.gz"),
                ),
            ],
            vec![],
        ),
        // MD trajectories (issue 51: a corrupt frame must be refused, never read): their
        // contact frequencies on their topology, and as conformations of a polymer
        "xtc" | "dcd" => {
            let (file, topology) = match name {
                "xtc" => ("md/adk.xtc", data("md/adk.pdb.gz")),
                _ => ("md/cobrotoxin.dcd", data("md/cobrotoxin.pdb.gz")),
            };
            let trajectory = |extra: &[&str]| {
                let head = ["contacts", "--trajectory", "{P}", "--topology", &topology];
                strings(&[&head[..], extra, &["-o", "{O}.tsv"]].concat())
            };
            (
                Kind::Binary,
                vec![raw_seed(
                    file,
                    &format!("m.{name}"),
                    vec![
                        trajectory(&[]),
                        trajectory(&["--definition", "closest-heavy", "--cutoff", "4.5"]),
                        strings(&["polymer-stats", "{P}", "-o", "{O}"]),
                    ],
                )],
                vec![],
            )
        }
        "bam" | "sam" => {
            let sizes = data("pairs/sim.chrom.sizes");
            let parse = |extra: &[&str]| {
                let head = ["pairs", "parse", "{P}", "-c", &sizes];
                strings(&[&head[..], extra, &["-o", "{O}.pairs.gz"]].concat())
            };
            let commands = vec![
                parse(&[]),
                parse(&["--walks-policy", "all", "--add-pair-index"]),
                parse(&[
                    "--add-columns",
                    "mapq,cigar,mismatches,seq,dist_to_5",
                    "--output-stats",
                    "{O}.stats",
                ]),
            ];
            // The BAM held inflated (its records mutated, then deflated again), or as SAM text.
            let inflated = gunzip_head("pairs/sim.bam", usize::MAX);
            if name == "bam" {
                (
                    Kind::Bgzf,
                    vec![Seed {
                        bytes: inflated,
                        origin: "data/pairs/sim.bam (inflated; mutants deflated as BGZF)".into(),
                        file_name: "m.bam".into(),
                        commands,
                    }],
                    vec![sizes],
                )
            } else {
                (
                    Kind::Text,
                    vec![Seed {
                        bytes: bam_as_sam(&data("pairs/sim.bam"), 4000),
                        origin: "data/pairs/sim.bam as SAM".into(),
                        file_name: "m.sam".into(),
                        commands,
                    }],
                    vec![sizes],
                )
            }
        }
        "4dn-pairs" => {
            let sorted = [
                vec!["pairs", "dedup", "{P}", "-o", "{O}.nodups.pairs.gz"],
                vec![
                    "pairs",
                    "dedup",
                    "{P}",
                    "--output-stats",
                    "{O}.stats",
                    "--output-dups",
                    "{O}.dups",
                ],
                vec!["pairs", "stats", "{P}", "-o", "{O}.stats"],
                vec![
                    "pairs",
                    "sort",
                    "{P}",
                    "--memory",
                    "16K",
                    "-o",
                    "{O}.sorted.pairs.gz",
                ],
                vec![
                    "pairs",
                    "select",
                    "pair_type == \"UU\" and mapq1 >= 30",
                    "{P}",
                ],
                vec!["pairs", "merge", "{P}", "{P}", "-o", "{O}.merged.pairs"],
                vec!["convert", "{P}", "{O}.cool", "--bin-size", "10000"],
            ];
            (
                Kind::Text,
                vec![
                    Seed {
                        bytes: gunzip_head("pairs/reference/sim.5unique.sorted.pairs.gz", 1500),
                        origin:
                            "data/pairs/reference/sim.5unique.sorted.pairs.gz, first 1,500 lines"
                                .into(),
                        file_name: "m.pairs".into(),
                        commands: sorted.iter().map(|c| strings(c)).collect(),
                    },
                    Seed {
                        bytes: gunzip_head("pairs/reference/sim.5unique.full.pairs.gz", 1500),
                        origin: "data/pairs/reference/sim.5unique.full.pairs.gz, first 1,500 lines"
                            .into(),
                        file_name: "m.pairs".into(),
                        commands: sorted.iter().map(|c| strings(c)).collect(),
                    },
                ],
                vec![],
            )
        }
        other => panic!("unknown format {other}; formats: {}", FORMATS.join(", ")),
    };
    let name = FORMATS
        .iter()
        .find(|f| **f == name)
        .expect("a known format");
    Format {
        name,
        kind,
        seeds,
        companions,
        hdf5_timeout: hdf5_timeout(),
    }
}

/// Make mutant `index` of `format` (campaign seed `seed`): its seed, bytes and mutations.
pub fn make_mutant(format: &Format, seed: u64, index: u64) -> (&Seed, Vec<u8>, Vec<String>) {
    let mut rng = mutate::mutant_rng(seed, format.name, index);
    let pick = &format.seeds[rng.gen_range(0..format.seeds.len())];
    let (bytes, mutations) = mutate::mutate(&pick.bytes, format.kind, &mut rng);
    (pick, bytes, mutations)
}

/// Substitute the placeholders of a command.
fn expand(args: &[String], mutant: &str, out: &str) -> Vec<String> {
    args.iter()
        .map(|a| a.replace("{P}", mutant).replace("{O}", out))
        .collect()
}

/// Run one command with a time limit; stderr goes to `stderr_file`.
fn run_one(
    binary: &Path,
    args: &[String],
    hdf5_timeout: &str,
    stderr_file: &Path,
) -> (Option<std::process::ExitStatus>, String, Duration) {
    let start = Instant::now();
    let err = std::fs::File::create(stderr_file).expect("stderr file");
    let mut child = Command::new(binary)
        .args(args)
        .env("CONTACTMAP_HDF5_TIMEOUT", hdf5_timeout)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(err)
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start {}: {e}", binary.display()));
    let mut pause = Duration::from_millis(1);
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait for the child") {
            break Some(status);
        }
        if start.elapsed() > HANG {
            // Only this child, by its id.
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(pause);
        pause = (pause * 2).min(Duration::from_millis(20));
    };
    let elapsed = start.elapsed();
    let mut text = std::fs::read(stderr_file).unwrap_or_default();
    text.truncate(4096);
    (status, String::from_utf8_lossy(&text).into_owned(), elapsed)
}

/// Classify a finished (or killed) run.
fn classify(
    status: Option<std::process::ExitStatus>,
    stderr: &str,
    names: &[&str],
    leftovers: &[String],
    validate: bool,
) -> (Class, String, String) {
    let Some(status) = status else {
        let mut why = format!("still running after {HANG:?}");
        if !leftovers.is_empty() {
            why.push_str(&format!(
                "; once killed, left behind: {}",
                leftovers.join(", ")
            ));
        }
        return (Class::Hang, "killed".into(), why);
    };
    #[cfg(unix)]
    let signal = std::os::unix::process::ExitStatusExt::signal(&status);
    #[cfg(not(unix))]
    let signal: Option<i32> = None;
    let code = status.code();
    let words = match (code, signal) {
        (Some(c), _) => format!("exit {c}"),
        (None, Some(s)) => format!("signal {s}"),
        (None, None) => "unknown".into(),
    };
    if signal.is_some() || matches!(code, Some(134 | 139)) {
        return (Class::Signal, words, "killed by a signal / aborted".into());
    }
    if code == Some(101) || stderr.contains("panicked at") {
        return (Class::Panic, words, "panicked".into());
    }
    if code == Some(0) {
        return (Class::Ok, words, String::new());
    }
    if validate && code == Some(1) && leftovers.is_empty() {
        return if stderr.is_empty() {
            (Class::Invalid, words, String::new())
        } else {
            (
                Class::BadMessage,
                words,
                "validate: an invalid file with a message on standard error".into(),
            )
        };
    }
    if !leftovers.is_empty() {
        return (
            Class::LeftBehind,
            words,
            format!("left behind: {}", leftovers.join(", ")),
        );
    }
    if code != Some(2) {
        return (Class::OtherExit, words, "exit code other than 0 / 2".into());
    }
    let lines: Vec<&str> = stderr.lines().collect();
    let why = if lines.len() != 1 {
        format!("{} stderr lines instead of 1", lines.len())
    } else if !lines[0].starts_with("contactmap: error: ") {
        "the line does not start with `contactmap: error: `".into()
    } else if lines[0].trim_end() == "contactmap: error:" {
        "empty message".into()
    } else if !names.iter().any(|n| lines[0].contains(n)) {
        "the message does not name the file".into()
    } else {
        return (Class::CleanError, words, String::new());
    };
    (Class::BadMessage, words, why)
}

/// Run every command of mutant `index` of `format` through `binary`, in a fresh folder under
/// `scratch`.
pub fn run_mutant(
    binary: &Path,
    format: &Format,
    seed: u64,
    index: u64,
    scratch: &Path,
) -> Outcome {
    let (pick, bytes, mutations) = make_mutant(format, seed, index);
    let dir = scratch.join(format!("{}-{index}", format.name));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("mutant folder");
    let mutant = dir.join(&pick.file_name);
    std::fs::write(&mutant, &bytes).expect("write the mutant");
    let mutant_str = mutant.to_string_lossy().into_owned();
    let out = dir.join("out").to_string_lossy().into_owned();
    let stderr_file = scratch.join(format!("{}-{index}.stderr", format.name));
    let mut names: Vec<&str> = vec![&mutant_str];
    names.extend(format.companions.iter().map(String::as_str));
    let mut runs = Vec::new();
    for command in &pick.commands {
        let args = expand(command, &mutant_str, &out);
        let (status, stderr, elapsed) = run_one(binary, &args, &format.hdf5_timeout, &stderr_file);
        let mut leftovers: Vec<String> = std::fs::read_dir(&dir)
            .expect("list the mutant folder")
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| *n != pick.file_name)
            .collect();
        leftovers.sort();
        let validate = args.first().is_some_and(|a| a == "validate");
        let (class, status, why) = classify(status, &stderr, &names, &leftovers, validate);
        // Outputs of a successful run (or leftovers of a failed one) must not meet the next run.
        for name in &leftovers {
            let _ = std::fs::remove_file(dir.join(name));
        }
        runs.push(Run {
            args,
            class,
            status,
            stderr,
            why,
            elapsed,
        });
    }
    let _ = std::fs::remove_file(&stderr_file);
    let _ = std::fs::remove_dir_all(&dir);
    let mut outcome = Outcome {
        index,
        origin: pick.origin.clone(),
        file_name: pick.file_name.clone(),
        path: mutant_str.clone(),
        mutations,
        bytes: None,
        runs,
    };
    if outcome.failed() {
        outcome.bytes = Some(bytes);
    }
    outcome
}

/// Figures of one format's campaign.
#[derive(Clone, Debug, Default)]
pub struct Summary {
    /// Mutants run.
    pub mutants: u64,
    /// Mutants with at least one failing run.
    pub failing_mutants: u64,
    /// Runs per class.
    pub runs: BTreeMap<Class, u64>,
    /// Wall time.
    pub elapsed: Duration,
}

impl Summary {
    /// Total runs.
    pub fn total_runs(&self) -> u64 {
        self.runs.values().sum()
    }

    /// Runs of `class`.
    pub fn count(&self, class: Class) -> u64 {
        self.runs.get(&class).copied().unwrap_or(0)
    }
}

/// Run mutants `indices` of `format` on `jobs` threads; `on_done` sees each outcome as it ends
/// (from the worker threads). Returns the summary and the failing outcomes, by index.
pub fn campaign(
    binary: &Path,
    format: &Format,
    seed: u64,
    indices: &[u64],
    jobs: usize,
    scratch: &Path,
    on_done: &(dyn Fn(&Outcome) + Sync),
) -> (Summary, Vec<Outcome>) {
    let start = Instant::now();
    let next = AtomicU64::new(0);
    let summary = Mutex::new(Summary::default());
    let failures = Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..jobs.max(1) {
            s.spawn(|| {
                loop {
                    let k = next.fetch_add(1, Ordering::Relaxed) as usize;
                    let Some(&index) = indices.get(k) else { break };
                    let outcome = run_mutant(binary, format, seed, index, scratch);
                    on_done(&outcome);
                    {
                        let mut sum = summary.lock().expect("summary lock");
                        sum.mutants += 1;
                        for run in &outcome.runs {
                            *sum.runs.entry(run.class).or_insert(0) += 1;
                        }
                        if outcome.failed() {
                            sum.failing_mutants += 1;
                        }
                    }
                    if outcome.failed() {
                        failures.lock().expect("failures lock").push(outcome);
                    }
                }
            });
        }
    });
    let mut summary = summary.into_inner().expect("summary lock");
    summary.elapsed = start.elapsed();
    let mut failures = failures.into_inner().expect("failures lock");
    failures.sort_by_key(|o| o.index);
    (summary, failures)
}

/// A shell-quoted command line.
pub fn shell_line(binary: &Path, args: &[String]) -> String {
    let quote = |s: &str| {
        if s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_./:=,+".contains(c))
        {
            s.to_string()
        } else {
            format!("'{}'", s.replace('\'', "'\\''"))
        }
    };
    std::iter::once(binary.to_string_lossy().into_owned())
        .chain(args.iter().map(|a| quote(a)))
        .collect::<Vec<_>>()
        .join(" ")
}

/// A failing outcome in words: the mutations and each failing run's command, status and stderr.
pub fn describe(format: &Format, seed: u64, outcome: &Outcome, binary: &Path) -> String {
    let mut text = format!(
        "format {} seed {seed} mutant {} (from {}): {}\n",
        format.name,
        outcome.index,
        outcome.origin,
        outcome.mutations.join("; ")
    );
    for run in outcome.runs.iter().filter(|r| r.class.is_failure()) {
        text.push_str(&format!(
            "  {} ({}, {}, {:.1} s): {}\n    stderr: {}\n",
            run.class.name(),
            run.status,
            run.why,
            run.elapsed.as_secs_f64(),
            shell_line(binary, &run.args),
            run.stderr.trim_end().replace('\n', "\n            ")
        ));
    }
    text.push_str(&format!(
        "  reproduce: cargo run --release --example fuzz_campaign -- --format {} --seed {seed} --only {} --out DIR\n",
        format.name, outcome.index
    ));
    text
}
