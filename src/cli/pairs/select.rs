//! `contactmap pairs select`: the pairs that meet a condition
//! ([`contactmap::pairs::select`]).

use std::path::PathBuf;

use clap::Args;

use super::shared::{Compression, command_line, open_output, refuse_overwrites};
use contactmap::error::{Error, Result};
use contactmap::io::pairs::{PairColumns, PairRecord, open_pairs};
use contactmap::pairs::select::{ColumnType, Selection};

/// Arguments of `contactmap pairs select`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
The condition is written as in pairtools select (Python syntax), in a language of its own that
covers what is written there:
  A or B, A and B, not A              conditions
  X == Y, !=, <, <=, >, >=            comparisons, chained (0 < pos1 < 1000)
  X in (\"UU\", \"UR\"), X not in [...]   membership
  X + Y, -, *, /, //, %, abs(X)       arithmetic
  csv_match(X, \"a,b\")                 X is one of the comma-separated values
  wildcard_match(X, \"chr*\")           a shell pattern over the whole of X
Values are the header's column names (chrom1, pos1, pair_type, mapq1, ...), COLS[i] (field i,
0-based), strings in quotes, numbers, True and False. pos1, pos2 and pairtools' integer extra
columns (mapq1, dist_to_51, ...) are numbers, other columns text; --type-cast changes a
column's type. Comparing text with a number is an error when the condition is read, and so is a
field that is not a number in a numeric column (with its line).

Not supported: arbitrary Python, regex_match, --startup-code.

Examples:
  contactmap pairs select \\
      '(pair_type == \"UU\") or (pair_type == \"UR\") or (pair_type == \"RU\")' \\
      sample.pairs.gz -o sample.unique.pairs.gz
  contactmap pairs select 'chrom1 != chrom2 and mapq1 >= 30 and mapq2 >= 30' \\
      in.pairs.gz --output-rest rest.pairs.gz -o trans.pairs.gz")]
pub struct SelectArgs {
    /// The condition.
    pub condition: String,
    /// Pairs file (plain, gzip or BGZF; `-`: standard input).
    #[arg(default_value = "-")]
    pub input: PathBuf,
    /// Output of the selected pairs (`.gz`: BGZF); standard output when not given.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    #[command(flatten)]
    pub compression: Compression,
    /// Output of the pairs not selected.
    #[arg(long, value_name = "FILE")]
    pub output_rest: Option<PathBuf>,
    /// A column's type: COLUMN int|float|str (repeatable).
    #[arg(short = 't', long, num_args = 2, value_names = ["COLUMN", "TYPE"], action = clap::ArgAction::Append)]
    pub type_cast: Vec<String>,
}

/// Run `contactmap pairs select`.
pub fn run(args: &SelectArgs) -> Result<()> {
    refuse_overwrites(
        &[&args.input],
        &[args.output.as_ref(), args.output_rest.as_ref()],
    )?;
    let mut types = Vec::new();
    for pair in args.type_cast.chunks(2) {
        let kind = match pair[1].as_str() {
            "int" => ColumnType::Integer,
            "float" => ColumnType::Float,
            "str" => ColumnType::Text,
            other => {
                return Err(Error::Argument(format!(
                    "--type-cast {} {other}: the type is one of int, float, str",
                    pair[0]
                )));
            }
        };
        types.push((pair[0].clone(), kind));
    }
    let mut reader = open_pairs(&args.input)?;
    let names = reader.header().columns();
    let columns = PairColumns::of(reader.header(), reader.path())?;
    // The columns come from the file's header: an error names the file.
    let selection = Selection::parse_with_types(&args.condition, &names, &types)
        .map_err(|e| Error::Argument(format!("{}: {e}", reader.path())))?;
    let mut header = reader.header().clone();
    header.push_program("contactmap_pairs_select", &command_line());
    let mut output = open_output(args.output.as_deref(), &header, args.compression)?;
    let mut rest = match &args.output_rest {
        Some(path) => Some(open_output(Some(path), &header, args.compression)?),
        None => None,
    };
    let mut record = PairRecord::default();
    while reader.read_record(&mut record)? {
        columns.check(&reader, &record)?;
        let selected = selection
            .matches(&record)
            .map_err(|message| reader.error(record.number(), message))?;
        let target = if selected {
            Some(&mut output)
        } else {
            rest.as_mut()
        };
        if let Some(target) = target {
            target.write_all(record.line())?;
            target.write_all(b"\n")?;
        }
    }
    if let Some(rest) = rest {
        rest.finish()?;
    }
    output.finish()
}
