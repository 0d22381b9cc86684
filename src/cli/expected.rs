//! `contactmap expected`. Being written.

use clap::Args;

use crate::error::{Error, Result};

/// Arguments of `contactmap expected`.
#[derive(Debug, Args)]
pub struct ExpectedArgs {
    /// Matrix URI.
    pub uri: String,
}

/// Run `contactmap expected`.
pub fn run(args: &ExpectedArgs) -> Result<()> {
    Err(Error::Invalid(format!("{}: not available yet", args.uri)))
}
