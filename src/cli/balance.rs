//! `contactmap balance`: ICE as `cooler balance`, VC, VC_SQRT, KR and SCALE as Juicer; weights to a TSV
//! or stored into the cooler.

use std::path::PathBuf;

use clap::{Args, ValueEnum};

use crate::cli::args::InputArgs;
use crate::cli::input::open_for_analysis;
use crate::cli::output::{Output, is_stdout, print_json, refuse_overwrites, store_lock, uri_file};
use contactmap::balance::store::{Balanced, balance_reader, weights_table};
use contactmap::balance::{BalanceParams, Method, Scope};
use contactmap::error::{Error, Result};
use contactmap::export::cooler::store_balanced;
use contactmap::genome::BinTable;
use contactmap::io::cool::store::check_target;
use contactmap::io::{self, default_memory_budget, parse_memory_size};
use contactmap::matrix::Weights;

/// Balancing methods, for `--method`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum MethodArg {
    /// iterative correction, exactly as cooler 0.11 `cooler balance`
    Ice,
    /// vanilla coverage (1 / row sum), scaled as Juicer
    Vc,
    /// square root of vanilla coverage (1 / sqrt(row sum)), scaled as Juicer
    VcSqrt,
    /// Knight-Ruiz, as Juicer
    Kr,
    /// SCALE, Juicer's default normalisation (matrix balancing with row filtering)
    Scale,
}

impl From<MethodArg> for Method {
    fn from(arg: MethodArg) -> Self {
        match arg {
            MethodArg::Ice => Method::Ice,
            MethodArg::Vc => Method::Vc,
            MethodArg::VcSqrt => Method::VcSqrt,
            MethodArg::Kr => Method::Kr,
            MethodArg::Scale => Method::Scale,
        }
    }
}

/// Arguments of `contactmap balance`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
ICE (default) follows cooler 0.11 `cooler balance` step by step, with its defaults: pixels on the
first --ignore-diags diagonals left out, bins masked by --min-nnz, --min-count, the MAD-max filter
and --blacklist, then iterations until the variance of the nonzero marginals is below --tol; the
weights are rescaled so that balanced rows sum to 1, as cooler does.

VC, VC-SQRT and KR follow Juicer: no filter (the filter options still apply when given), the
diagonal included, the divisive vector scaled so that the balanced matrix sums to the raw one;
KR uses Juicer's tolerance 1e-6 and its rules for dropping rows that cannot be balanced. SCALE
(Juicer's default normalisation) iterates a row / column scaling from the square root of the VC
vector, with Juicer's tolerance 5e-4 on the vector and 5 times it on the balanced row sums, leaving
out the rows with the fewest nonzero pixels when an attempt stalls (100 iterations per attempt,
300 in all); as Juicer, the last vector is kept even when it did not converge. Juicer's own KR /
VC / VC_SQRT / SCALE vectors (the columns hic2cool writes) are per chromosome: use --cis-only to
reproduce them (without it, Juicer's GW_ vectors).

Weights are multiplicative (balanced = count * w1 * w2), NaN for masked bins. Without --store they
are printed as a table `chrom start end NAME` with a header line (NaN as `nan`, full precision)
to standard output or -o FILE, and a summary (`# converged=... scale=... var=...`) goes to
standard error. With --store the column bins/NAME is written into the cooler with cooler's
attributes (converged, scale, var, tol, min_nnz, min_count, mad_max, ignore_diags, cis_only,
divisive_weights); an existing column is replaced only with --force. The new column is written
under a temporary name and swapped in, so a failure leaves the file as it was. While storing, the
file is locked (an advisory lock on .NAME.lock beside it): a second --store on the same file
refuses at once (exit code 2, file untouched). Columns named KR, VC or VC_SQRT are stored
divisive (cooler divides by those names).

Counts must be finite and >= 0: a negative, NaN or infinite count in the file stops the command
(exit code 2) naming the file and the first such pixel.

When the balancing does not converge within --max-iters, a WARNING line goes to standard error
and the summary says converged=false; the table is still written (exit code 0), as cooler's
default does. --store, however, refuses to store unconverged weights (exit code 2, the file is
left as it was) unless --store-unconverged is given (then converged=false is stored with them).
A chromosome with no contacts left after filtering gets NaN weights and counts as converged, as in
cooler.

The pixels are copied into memory (16 bytes each) when they fit --max-memory, otherwise every
iteration streams them from the file (slower, same weights).

Examples:
  contactmap balance data/CN.mm9.10000kb.cool -o weights.tsv
  contactmap balance data/cooler_test_file.mcool::/resolutions/100000 \\
      --cis-only
  contactmap balance copy.cool --store --force --name weight
  contactmap balance data/cooler_test_file.mcool::/resolutions/100000 \\
      --method kr --cis-only
  contactmap balance data/cooler_test_file.mcool::/resolutions/100000 \\
      --method scale --cis-only
  contactmap balance big.cool --blacklist gaps.bed --max-memory 2G -o w.tsv.gz")]
pub struct BalanceArgs {
    /// Matrix URI: file.cool, file.mcool::/resolutions/N; .hic and text tables too, without --store.
    pub uri: String,
    /// Balancing method.
    #[arg(long, value_enum, default_value_t = MethodArg::Ice)]
    pub method: MethodArg,
    /// Leave out the first N diagonals (0: none, 1: the main diagonal, 2: also +-1). Default 2 for
    /// ICE (cooler), 0 for VC / KR (Juicer).
    #[arg(long, value_name = "N")]
    pub ignore_diags: Option<u64>,
    /// Leave out pixels closer than this many bp (the larger of this, in diagonals, and
    /// --ignore-diags is used; fixed bins only).
    #[arg(long, value_name = "BP")]
    pub ignore_dist: Option<u64>,
    /// MAD-max filter: mask bins whose log marginal is more than N median absolute deviations
    /// below the median (0: off). Default 5 for ICE, 0 for VC / KR.
    #[arg(long, value_name = "N")]
    pub mad_max: Option<f64>,
    /// Mask bins with fewer nonzero pixels than N. Default 10 for ICE, 0 for VC / KR.
    #[arg(long, value_name = "N")]
    pub min_nnz: Option<u64>,
    /// Mask bins whose marginal count is below N (default 0: off).
    #[arg(long, value_name = "N")]
    pub min_count: Option<f64>,
    /// Mask the bins overlapping the regions of this BED file (chrom start end).
    #[arg(long, value_name = "BED")]
    pub blacklist: Option<PathBuf>,
    /// Convergence tolerance: variance of the marginals (ICE, default 1e-5), residual (KR,
    /// default 1e-6) or change of the vector (SCALE, default 5e-4).
    #[arg(long)]
    pub tol: Option<f64>,
    /// Iteration limit (ICE iterations; KR Newton iterations per try; SCALE iterations per
    /// attempt). Default 200 (SCALE: 100).
    #[arg(long, value_name = "N")]
    pub max_iters: Option<usize>,
    /// Balance each chromosome on its intra-chromosomal pixels only.
    #[arg(long, conflicts_with = "trans_only")]
    pub cis_only: bool,
    /// Balance on the inter-chromosomal pixels only.
    #[arg(long)]
    pub trans_only: bool,
    /// Name of the weight column.
    #[arg(long, default_value = "weight")]
    pub name: String,
    /// Store the weights into the cooler as bins/NAME instead of printing them.
    #[arg(long, conflicts_with = "out")]
    pub store: bool,
    /// With --store: replace an existing column.
    #[arg(short, long)]
    pub force: bool,
    /// With --store: store the weights even when the balancing did not converge (with
    /// converged=false).
    #[arg(long, requires = "store")]
    pub store_unconverged: bool,
    /// Write the table to FILE (gzip if it ends in .gz) instead of standard output.
    #[arg(short, long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Print the summary (method, convergence, iterations, masked bins, scale, variance; per
    /// chromosome for per-chromosome methods) as JSON on standard output instead of the `#`
    /// lines on standard error (with --store or -o FILE: standard output holds the table
    /// otherwise).
    #[arg(long)]
    pub json: bool,
    /// Memory for the in-memory copy of the pixels, e.g. 8G, 512M (default: half of the RAM);
    /// larger matrices are streamed from the file on every iteration.
    #[arg(long, value_name = "SIZE")]
    pub max_memory: Option<String>,
    /// Options for text inputs.
    #[command(flatten)]
    pub input: InputArgs,
}

/// Run `contactmap balance`.
pub fn run(args: &BalanceArgs) -> Result<()> {
    // --store writes into the level --resolution names
    let uri = args.input.uri_at_resolution(&args.uri)?;
    let mut inputs = vec![uri_file(&uri)];
    inputs.extend(args.blacklist.as_deref());
    inputs.extend(args.input.files());
    refuse_overwrites(&inputs, &[args.out.as_deref()])?;
    if args.json && !args.store && is_stdout(args.out.as_deref()) {
        return Err(Error::Argument(
            "--json prints the summary on standard output, where the weights table goes without --store or -o FILE: give one of them".into(),
        ));
    }
    let budget = match &args.max_memory {
        Some(text) => parse_memory_size(text)?,
        None => default_memory_budget(),
    };
    // With --store, the file is locked from the check of the column to the end of the store, so
    // that a second `balance --store` on it refuses at once instead of overwriting the column the
    // first one reports as stored.
    let _lock = if args.store {
        let lock = store_lock(&uri, "; write a table with -o instead")?;
        check_target(&uri, &args.name, args.force)?;
        Some(lock)
    } else {
        None
    };
    // The reader (and the pixels borrowing it) is closed before --store opens the file to write.
    let (
        Balanced {
            result,
            disconnected,
        },
        bins,
        params_used,
        reader_warnings,
    ) = {
        let reader = open_for_analysis(&uri, &args.input)?;
        let params = params(args, reader.bins())?;
        let balanced = balance_reader(reader.as_ref(), &params, budget)?;
        (balanced, reader.bins().clone(), params, reader.warnings())
    };
    if !result.converged {
        let message = format!(
            "{}: {} balancing did not converge within {} iterations ({})",
            uri,
            params_used.method.name(),
            params_used.max_iters,
            result.unconverged_detail(&bins, params_used.tol)
        );
        let advice = if disconnected {
            "the map has no trans (inter-chromosomal) contacts, so genome-wide balancing cannot \
             converge: balance each chromosome with --cis-only"
        } else {
            "raise --max-iters or --tol"
        };
        if args.store && !args.store_unconverged {
            return Err(Error::Argument(format!(
                "{message}; nothing stored: {advice}, or pass --store-unconverged"
            )));
        }
        let what = if args.store { "storing" } else { "writing" };
        eprintln!(
            "contactmap: WARNING: {message}; {what} the unconverged weights anyway ({advice})"
        );
    }
    if args.store {
        store_balanced(&uri, &args.name, &params_used, &result, args.force)?;
    } else {
        let weights = Weights {
            name: args.name.clone(),
            values: result.weights.clone(),
            provenance: None,
        };
        let mut out = Output::open(args.out.as_deref())?;
        weights_table(&bins, &weights, |bytes| out.write_all(bytes))?;
        out.finish()?;
    }
    if args.json {
        print_json(&result.report_json(&uri, &params_used, &bins))?;
    } else {
        eprint!("{}", result.report_text(&params_used, &bins));
    }
    super::warnings::print_reader_warnings(reader_warnings);
    Ok(())
}

/// Check the options and build the library's parameters, with the method's defaults.
fn params(args: &BalanceArgs, bins: &BinTable) -> Result<BalanceParams> {
    let method: Method = args.method.into();
    let mut params = BalanceParams::for_method(method);
    params.scope = if args.cis_only {
        Scope::Cis
    } else if args.trans_only {
        Scope::Trans
    } else {
        Scope::GenomeWide
    };
    if let Some(n) = args.ignore_diags {
        params.ignore_diags = n;
    }
    if let Some(bp) = args.ignore_dist {
        let Some(resolution) = bins.resolution() else {
            return Err(Error::Argument(
                "--ignore-dist needs fixed-size bins; use --ignore-diags".into(),
            ));
        };
        params.ignore_diags = params.ignore_diags.max(bp.div_ceil(resolution));
    }
    if let Some(m) = args.mad_max {
        if !(m.is_finite() && m >= 0.0) {
            return Err(Error::Argument(format!(
                "--mad-max must be a non-negative number (got {m})"
            )));
        }
        params.mad_max = m;
    }
    if let Some(n) = args.min_nnz {
        params.min_nnz = n;
    }
    if let Some(c) = args.min_count {
        params.min_count = c;
    }
    if let Some(tol) = args.tol {
        if !(tol.is_finite() && tol > 0.0) {
            return Err(Error::Argument(format!(
                "--tol must be a positive number (got {tol})"
            )));
        }
        params.tol = tol;
    }
    if let Some(n) = args.max_iters {
        if n == 0 {
            return Err(Error::Argument("--max-iters must be at least 1".into()));
        }
        params.max_iters = n;
    }
    if let Some(path) = &args.blacklist {
        params.blacklist = io::bed::read_bin_mask(path, bins)?;
    }
    Ok(params)
}
