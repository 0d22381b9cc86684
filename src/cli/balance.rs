//! `contactmap balance`. Being written.

use clap::Args;

use crate::error::{Error, Result};

/// Arguments of `contactmap balance`.
#[derive(Debug, Args)]
pub struct BalanceArgs {
    /// Matrix URI.
    pub uri: String,
}

/// Run `contactmap balance`.
pub fn run(args: &BalanceArgs) -> Result<()> {
    Err(Error::Invalid(format!("{}: not available yet", args.uri)))
}
