//! `contactmap plot`: figures as PNG or SVG. `plot map` draws a contact-map heatmap (square or
//! 45-degree, with overlays and tracks); `plot expected` P(s) curves with their slopes and power
//! laws; `plot contacts` a protein contact map with the predictions coloured true / false
//! positive and the precision curve; `plot saddle` a compartment saddle; `plot pileup` the
//! pileups of `contactmap pileup`, as plotpup draws them; `plot hicrep` the SCCs of
//! `contactmap hicrep` as a clustered heatmap; `plot polymer-stats` the tables of
//! `contactmap polymer-stats`. The options every figure shares (output, format, size, dpi,
//! title) are in `figure`.

mod contacts;
mod diff;
mod expected;
mod figure;
mod hicrep;
mod map;
mod pileup;
mod polymer;
mod saddle;

use clap::{Args, Subcommand};

use contactmap::error::Result;

/// Arguments of `contactmap plot`.
#[derive(Debug, Args)]
pub struct PlotArgs {
    /// What to draw.
    #[command(subcommand)]
    pub command: PlotCommand,
}

/// The figures.
#[derive(Debug, Subcommand)]
pub enum PlotCommand {
    /// Heatmap of a region or a pair of regions: balanced (default), raw or observed/expected,
    /// log colour scale, square or 45-degree (--triangle), with domains, boundaries, loops and
    /// tracks.
    Map(Box<map::MapArgs>),
    /// P(s) on log-log axes with its local slope: several samples overlaid, fitted power laws
    /// with their exponents.
    Expected(Box<expected::ExpectedPlotArgs>),
    /// Protein contact map: the true contacts of a structure in grey, the top-L predicted
    /// pairs coloured true / false positive (ConKit's `plot cmap`), a second prediction in the
    /// lower triangle, and the precision-vs-list-size curve.
    Contacts(Box<contacts::ContactsArgs>),
    /// Saddle plot of `contactmap saddle`'s table: mean observed/expected by pair of track
    /// classes (cooltools' saddleplot).
    Saddle(Box<saddle::SaddlePlotArgs>),
    /// The pileups of `contactmap pileup` as plotpup draws them: a heatmap per group, log colour
    /// scale centred at 1, the centre score in a corner.
    Pileup(Box<pileup::PileupPlotArgs>),
    /// The SCC table of `contactmap hicrep` as a clustered heatmap (samples ordered by
    /// average-linkage clustering, the tree above, the SCCs in the cells).
    Hicrep(Box<hicrep::HicrepPlotArgs>),
    /// The tables of `contactmap polymer-stats`: P(s), <R^2(s)> and <Rg^2(s)> on log-log axes
    /// with their local slopes, several ensembles overlaid; or Rg^2 over the conformations.
    PolymerStats(Box<polymer::PolymerStatsPlotArgs>),
    /// The MA or volcano plot of a `contactmap diff` table (loops, boundaries, compartments):
    /// each feature's change against its level or its p-value, coloured by its call.
    Diff(Box<diff::DiffPlotArgs>),
}

/// Run `contactmap plot`.
pub fn run(args: &PlotArgs) -> Result<()> {
    match &args.command {
        PlotCommand::Map(args) => map::run(args),
        PlotCommand::Expected(args) => expected::run(args),
        PlotCommand::Contacts(args) => contacts::run(args),
        PlotCommand::Saddle(args) => saddle::run(args),
        PlotCommand::Pileup(args) => pileup::run(args),
        PlotCommand::Hicrep(args) => hicrep::run(args),
        PlotCommand::PolymerStats(args) => polymer::run(args),
        PlotCommand::Diff(args) => diff::run(args),
    }
}
