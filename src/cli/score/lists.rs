//! The list options `score contacts` and `score overlap` share.

use clap::Args;

use crate::cli::protein::RoundingArg;
use contactmap::error::Result;
use contactmap::score::lists::{LabelledSize, NamedRange, parse_list_size, parse_range};

/// Separation ranges, list sizes and their rounding, shared by `score contacts` and
/// `score overlap`.
#[derive(Debug, Args)]
pub struct ListArgs {
    /// Separation ranges: short, medium, long, all, MIN-MAX or MIN+ (comma separated).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "short,medium,long,all",
        value_name = "RANGES"
    )]
    pub ranges: Vec<String>,
    /// List sizes: L/10, L/5, L/2, L, 0.3L, a count N, or NC (comma separated).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "L/10,L/5,L/2,L",
        value_name = "SIZES"
    )]
    pub top: Vec<String>,
    /// Rounding of L * fraction.
    #[arg(long, value_enum, default_value = "floor")]
    pub rounding: RoundingArg,
}

impl ListArgs {
    /// The parsed ranges and list sizes.
    pub fn parse(&self) -> Result<(Vec<NamedRange>, Vec<LabelledSize>)> {
        let ranges = self
            .ranges
            .iter()
            .map(|token| parse_range(token))
            .collect::<Result<_>>()?;
        let sizes = self
            .top
            .iter()
            .map(|token| parse_list_size(token))
            .collect::<Result<_>>()?;
        Ok((ranges, sizes))
    }
}
