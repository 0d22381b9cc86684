//! Command-line interface: argument structs (clap derive) and one module per subcommand, each with
//! one `run` function that parses, checks, calls the library and writes the result.

pub mod args;
pub mod balance;
pub mod compartments;
pub mod contacts;
pub mod convert;
pub mod coverage;
pub mod diff;
pub mod dots;
pub mod dump;
pub mod expected;
pub mod hicrep;
pub mod info;
pub mod input;
pub mod matrix_output;
pub mod merge;
pub mod normalize;
pub mod output;
pub mod pairs;
pub mod pileup;
pub mod plot;
pub mod polymer_map;
pub mod polymer_stats;
pub mod progress;
pub mod protein;
pub mod saddle;
pub mod sample;
pub mod score;
pub mod serve;
pub mod shell;
pub mod simulate;
pub mod status;
pub mod tads;
pub mod validate;
pub mod virtual4c;
pub mod warnings;
pub mod zoomify;

use clap::{Parser, Subcommand};

use contactmap::error::Result;
use status::Status;

/// Contact maps: inspect, dump, convert, zoomify and merge Hi-C maps (.cool, .mcool, .hic, text,
/// pairs), balance them (ICE, VC, KR, SCALE), distance-decay expected and its power law, observed /
/// expected maps, TADs, pictures; protein contact predictions scored against structures;
/// simulated maps (block maps, polymer ensembles) with a known truth.
///
/// Matrices are named by URI: `file.cool`, `file.mcool::/resolutions/10000`, `file.hic` (or
/// `file.hic::/resolutions/10000` when it has several resolutions), or a text table
/// (BG2 / COO pixels, pairs, dense; gzip allowed; `-` for standard input).
#[derive(Debug, Parser)]
#[command(name = "contactmap", version, propagate_version = true)]
pub struct Cli {
    /// The subcommand.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Describe a matrix: format, bins, chromosomes, pixels (nnz), count sum, weight columns.
    Info(info::InfoArgs),
    /// Print pixels (or the bin / chromosome table) as text, like `cooler dump`.
    Dump(dump::DumpArgs),
    /// Convert between formats: .hic / .cool / text / pairs -> .cool, .mcool, .hic or text.
    Convert(convert::ConvertArgs),
    /// Balance a matrix (ICE as cooler, VC, VC_SQRT, KR, SCALE): weights to a TSV or stored
    /// with --store.
    Balance(balance::BalanceArgs),
    /// Sum maps on the same bins (replicates, simulation replicas) into a .cool, .mcool or .hic.
    Merge(merge::MergeArgs),
    /// Multi-resolution .mcool (or .hic) from a cooler, as cooler zoomify (optionally balanced per
    /// level).
    Zoomify(zoomify::ZoomifyArgs),
    /// Distance-decay expected P(s) as cooltools expected-cis / expected-trans, log-binned P(s),
    /// power-law exponents.
    Expected(expected::ExpectedArgs),
    /// Observed / expected maps (o/e, log2 o/e, z-score) as a .cool or a text table.
    Normalize(normalize::NormalizeArgs),
    /// TAD boundaries and domains: insulation (as cooltools), directionality + HMM, TopDom,
    /// Armatus.
    Tads(tads::TadsArgs),
    /// A/B compartment eigenvectors (E1..En and eigenvalues) as cooltools eigs-cis / eigs-trans,
    /// oriented by a phasing track or the GC content of a genome FASTA.
    Compartments(compartments::CompartmentsArgs),
    /// The cis saddle of a compartment track (sums, counts, strength), as cooltools saddle.
    Saddle(saddle::SaddleArgs),
    /// Loops (dots) as cooltools' dot caller: locally adjusted expected of four kernels, FDR
    /// per lambda bin, BIRCH clustering, HiCCUPS filter.
    Dots(dots::DotsArgs),
    /// Dot calls at 5, 10 and 25 kb merged into one list as Juicer's HiCCUPS merges them.
    DotsMerge(dots::DotsMergeArgs),
    /// Read pairs from the aligner's BAM to deduplicated pairs, as pairtools: `pairs parse`
    /// (SAM / BAM to pairs), `pairs sort`, `pairs dedup`, `pairs stats`, `pairs select`, `pairs
    /// merge`; each reads `-` and writes standard output, for pipes.
    Pairs(pairs::PairsArgs),
    /// Aggregate maps at features (loops, TADs, peaks) as coolpuppy, with coolpuppy's and Juicer
    /// APA's scores.
    Pileup(pileup::PileupArgs),
    /// What changed between two conditions with replicates: `diff loops` (each loop's counts,
    /// DESeq2's model with the expected at its distance, q-values), `diff boundaries`
    /// (contacts across against the flanks: gained, lost, shifted), `diff compartments`
    /// (E1 per bin: A->B, B->A switches), `diff regions` (CHESS's structural similarity).
    Diff(diff::DiffArgs),
    /// HiCRep's stratum-adjusted correlation (SCC) of replicates or samples, per chromosome and
    /// genome-wide, as hicrep 0.2.6 (h trained as hicreppy with --h auto).
    Hicrep(hicrep::HicrepArgs),
    /// Downsample contacts to a count or a fraction (seeded), as cooltools random-sample.
    Sample(sample::SampleArgs),
    /// Cis and total coverage per bin (raw or balanced), as cooltools coverage.
    Coverage(coverage::CoverageArgs),
    /// A viewpoint's contacts with the whole genome (virtual 4C), as cooltools virtual4c.
    Virtual4c(virtual4c::Virtual4cArgs),
    /// Simulated maps with a known truth: `simulate blocks` (block-structured map with TADs),
    /// `simulate polymer` (bead-spring polymer ensembles with loop extrusion, CPU or GPU).
    Simulate(simulate::SimulateArgs),
    /// The contact map of 3D conformations (polychrom HDF5 trajectories, `simulate polymer
    /// --conformations` tables, XYZ), as polychrom's binnedContactMap counts it.
    PolymerMap(polymer_map::PolymerMapArgs),
    /// P(s), <R^2(s)>, <Rg^2(s)> and each conformation's Rg^2 of 3D conformations, as polychrom's
    /// polymer_analyses computes them.
    PolymerStats(polymer_stats::PolymerStatsArgs),
    /// Score calls against a truth: `score boundaries` (TAD boundaries and domains), `score
    /// compartments` (eigenvectors against A/B truth), `score loops` (dot calls against true
    /// loops), `score contacts` (protein residue-contact predictions against a structure), `score
    /// overlap` (two contact predictions).
    Score(score::ScoreArgs),
    /// True residue contacts of a protein structure (PDB / mmCIF) as CASP RR, or its residue
    /// distance matrix.
    Contacts(contacts::ContactsArgs),
    /// Check a .cool / .mcool / .hic file end to end (exit 0 valid, 1 invalid, 2 unreadable);
    /// `--repair OUT` writes a corrected copy of a cooler.
    Validate(validate::ValidateArgs),
    /// Figures as PNG or SVG: `plot map` (contact-map heatmaps, square or 45-degree, with
    /// domains, loops and tracks), `plot expected` (P(s) and power laws), `plot saddle` (saddle
    /// plots), `plot contacts` (protein contact maps), `plot pileup` (pileups, as plotpup),
    /// `plot hicrep` (SCCs as a clustered heatmap), `plot polymer-stats` (P(s), R^2(s) of 3D
    /// conformations), `plot diff` (MA and volcano plots of `diff` tables); `plot map
    /// --compare` draws two samples.
    Plot(plot::PlotArgs),
    /// A HiGlass tile server for .mcool / .cool / .hic maps (higlass-server's API, tiles as
    /// clodius computes them) with the viewer page: `serve a.mcool`, then open the URL it prints.
    Serve(serve::ServeArgs),
    /// Shell completion script (bash, zsh, fish) on standard output.
    Completions(shell::CompletionsArgs),
    /// Man pages, one per command, into a folder (`make man`).
    Man(shell::ManArgs),
}

/// The width help is written at: the terminal's (or `COLUMNS`) between 80 and 100 columns, 100
/// without either. Never below 80, so that the examples of every `--help` (at most 78 columns,
/// continued with `\` past that) are never wrapped inside a command and can be pasted; a
/// narrower terminal folds the long lines itself without breaking them.
fn help_width() -> usize {
    #[cfg(unix)]
    let terminal = rustix::termios::tcgetwinsize(std::io::stdout())
        .ok()
        .map(|size| usize::from(size.ws_col))
        .filter(|&w| w > 0);
    #[cfg(not(unix))]
    let terminal: Option<usize> = None;
    terminal
        .or_else(|| std::env::var("COLUMNS").ok()?.trim().parse().ok())
        .unwrap_or(100)
        .clamp(80, 100)
}

/// The command-line definition: [`Cli`]'s, with every option that takes one value accepting a
/// value that starts with `-` (`--vmin -2`, `--window -50k`), so that a negative number reaches
/// the option's own check ("--window must be positive") instead of being read as an unknown
/// flag; help written at the terminal's width, kept between 80 and 100 columns.
pub fn command() -> clap::Command {
    fn hyphen_values(command: clap::Command) -> clap::Command {
        command
            .mut_args(|arg| {
                let one_value = matches!(
                    arg.get_action(),
                    clap::ArgAction::Set | clap::ArgAction::Append
                ) && arg
                    .get_num_args()
                    .is_none_or(|range| range.max_values() == 1);
                if one_value && !arg.is_positional() {
                    arg.allow_hyphen_values(true)
                } else {
                    arg
                }
            })
            .mut_subcommands(hyphen_values)
    }
    hyphen_values(<Cli as clap::CommandFactory>::command()).term_width(help_width())
}

/// Parse a command line (the program name first) with [`command`].
pub fn parse<I, T>(args: I) -> std::result::Result<Cli, clap::Error>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let matches = command().try_get_matches_from(args)?;
    <Cli as clap::FromArgMatches>::from_arg_matches(&matches)
}

/// A command-line error in one line, as every other error is printed (after
/// `contactmap: error: `): clap's message, then the usage line and where to read more.
pub fn argument_error_line(error: &clap::Error) -> String {
    let text = error.render().to_string();
    // clap's paragraphs: the message (with its list of missing arguments or possible values),
    // tips, the usage, "For more information".
    let paragraphs: Vec<String> = text
        .split("\n\n")
        .map(|p| p.split_whitespace().collect::<Vec<_>>().join(" "))
        .filter(|p| !p.is_empty())
        .collect();
    let mut message = paragraphs
        .first()
        .map_or("bad arguments", |p| p.trim_start_matches("error: "))
        .to_string();
    // A negative number for an unsigned option: say so instead of Rust's parse error.
    let negative = matches!(
        error.get(clap::error::ContextKind::InvalidValue),
        Some(clap::error::ContextValue::String(value))
            if value.starts_with('-') && value[1..].parse::<f64>().is_ok()
    );
    if negative {
        if let Some((head, _)) = message.split_once("': ") {
            message =
                format!("{head}': a number of 0 or more is expected here, not a negative one");
        }
    }
    for tip in paragraphs.iter().filter(|p| p.starts_with("tip: ")) {
        message.push_str(&format!("; {tip}"));
    }
    let usage = text
        .lines()
        .find_map(|l| l.trim().strip_prefix("Usage: "))
        .map(str::trim);
    match usage {
        Some(usage) => {
            let command: Vec<&str> = usage
                .split_whitespace()
                .take_while(|word| !word.starts_with(['-', '[', '<']))
                .collect();
            format!(
                "{message} (usage: {usage}; see `{} --help`)",
                command.join(" ")
            )
        }
        None => message,
    }
}

/// The option that gives the library's parameter `field` (an [`contactmap::Error::Parameter`]'s
/// name) in the command line `args`: the long name of the argument with that id in the
/// subcommand `args` ran, else the field's name in kebab case (clap's own rule for a field
/// without a long name of its own).
pub fn option_name(args: &[std::ffi::OsString], field: &str) -> String {
    let mut command = command();
    let long = command
        .try_get_matches_from_mut(args)
        .ok()
        .and_then(|matches| {
            let mut command = &command;
            let mut matches = &matches;
            while let Some((name, sub)) = matches.subcommand() {
                command = command.find_subcommand(name)?;
                matches = sub;
            }
            command
                .get_arguments()
                .find(|arg| arg.get_id() == field)
                .and_then(|arg| arg.get_long())
                .map(str::to_string)
        });
    long.unwrap_or_else(|| field.replace('_', "-"))
}

/// Run a parsed command line.
pub fn run(cli: Cli) -> Result<Status> {
    match cli.command {
        Command::Info(args) => info::run(&args),
        Command::Dump(args) => dump::run(&args),
        Command::Convert(args) => convert::run(&args),
        Command::Balance(args) => balance::run(&args),
        Command::Merge(args) => merge::run(&args),
        Command::Zoomify(args) => zoomify::run(&args),
        Command::Expected(args) => expected::run(&args),
        Command::Normalize(args) => normalize::run(&args),
        Command::Tads(args) => tads::run(&args),
        Command::Compartments(args) => compartments::run(&args),
        Command::Saddle(args) => saddle::run(&args),
        Command::Dots(args) => dots::run(&args),
        Command::DotsMerge(args) => dots::run_merge(&args),
        Command::Pairs(args) => pairs::run(&args),
        Command::Pileup(args) => pileup::run(&args),
        Command::Diff(args) => diff::run(&args),
        Command::Hicrep(args) => hicrep::run(&args),
        Command::Sample(args) => sample::run(&args),
        Command::Coverage(args) => coverage::run(&args),
        Command::Virtual4c(args) => virtual4c::run(&args),
        Command::Simulate(args) => simulate::run(&args),
        Command::PolymerMap(args) => polymer_map::run(&args),
        Command::PolymerStats(args) => polymer_stats::run(&args),
        Command::Score(args) => score::run(&args),
        Command::Contacts(args) => contacts::run(&args),
        Command::Validate(args) => return validate::run(&args),
        Command::Plot(args) => plot::run(&args),
        Command::Serve(args) => serve::run(&args),
        Command::Completions(args) => shell::run_completions(&args, command()),
        Command::Man(args) => shell::run_man(&args, command()),
    }
    .map(|()| Status::Success)
}
