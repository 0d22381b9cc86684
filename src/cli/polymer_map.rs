//! `contactmap polymer-map`: the contact map of a set of 3D conformations (polychrom trajectories,
//! `simulate polymer --conformations` tables, XYZ), as polychrom's `binnedContactMap` counts it
//! ([`contactmap::conformations`], [`contactmap::io::trajectory`]).

use std::path::{Path, PathBuf};

use clap::Args;

use crate::cli::output::{check_cool_output, refuse_overwrites};
use crate::cli::progress::spinner;
use crate::cli::warnings::Warnings;
use contactmap::conformations::{MapParams, chains_of_lengths, contact_map};
use contactmap::error::{Error, Result};
use contactmap::io::InMemory;
use contactmap::io::cool::{CoolWriteOptions, write_cool};
use contactmap::io::trajectory::open_trajectories;

/// Arguments of `contactmap polymer-map`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Two beads i < j of a conformation are in contact when they are at most --contact-radius apart
(scipy's KDTree.query_pairs, which polychrom's calculate_contacts calls); each contact adds one to
its pair of bins, summed over every conformation of every input. Beads are binned per chain as
polychrom's binnedContactMap bins them: each chain cut into bins of --monomers-per-bin beads from
its start (the last bin of a chain may be shorter); with --monomers-per-bin 1 the map is polychrom's
monomerResolutionContactMap. polychrom returns the dense matrix triangle + triangle.T, whose
diagonal is twice the contacts within a bin: the .cool stores each contact once.

Inputs (one or more, read in order; the format is detected):
  polychrom HDF5         a trajectory folder (its blocks_X-Y.h5 files), one blocks file, or one
                         block as polychrom's URI blocks_1-50.h5::42 (the dataset pos, N x 3)
  conformations table    `simulate polymer --conformations` TSV: replica sample chain bead x y z
  XYZ                    frames of N, a comment, N lines 'name x y z' (.xyz, .xyz.gz)
  DCD, XTC               CHARMM / NAMD / OpenMM and GROMACS frames (.dcd, .xtc): every atom a
                         bead (Angstrom for DCD, nm for XTC: --contact-radius in those units)
  multi-model PDB/mmCIF  every MODEL, all its atoms in file order (Angstrom)

Every conformation must have as many beads as the first. Conformations stream: a chunk is read,
its contacts found on every core, and the next chunk read. The output has one chromosome per chain
(chr1..chrK, --monomer-bp bp per bead) and is written under a temporary name.

Examples:
  contactmap polymer-map traj/ --contact-radius 5 --monomers-per-bin 10 \\
      -o map.cool
  contactmap polymer-map run1/ run2/ --contact-radius 2 --chains 4000,4000 \\
      -o pair.cool
  contactmap polymer-map sim.tsv.gz --contact-radius 1.5 -o sim.cool")]
pub struct PolymerMapArgs {
    /// Trajectories: polychrom folders, blocks files or URIs; conformations tables; XYZ, DCD,
    /// XTC, multi-model PDB / mmCIF files.
    #[arg(value_name = "TRAJ", required = true)]
    pub inputs: Vec<String>,
    /// Beads at most this far apart are in contact (the positions' units; polychrom's cutoff).
    #[arg(long, value_name = "R")]
    pub contact_radius: f64,
    /// Beads per bin (polychrom's binSize); 1: monomer resolution.
    #[arg(long, default_value_t = 1, value_name = "N")]
    pub monomers_per_bin: usize,
    /// Beads of each chain, in order (default: one chain of every bead).
    #[arg(long, value_delimiter = ',', value_name = "N,...")]
    pub chains: Option<Vec<usize>>,
    /// Base pairs per bead, for the map's coordinates.
    #[arg(long, default_value_t = 1000, value_name = "BP")]
    pub monomer_bp: u64,
    /// The output .cool.
    #[arg(short, long, value_name = "OUT.cool")]
    pub out: PathBuf,
}

/// Run `contactmap polymer-map`.
pub fn run(args: &PolymerMapArgs) -> Result<()> {
    let inputs: Vec<&Path> = args
        .inputs
        .iter()
        .map(|i| Path::new(i.split("::").next().unwrap_or(i)))
        .collect();
    refuse_overwrites(&inputs, &[Some(&args.out)])?;
    check_cool_output("polymer-map", &args.out)?;
    if args.monomer_bp == 0 {
        return Err(Error::Argument("--monomer-bp must be at least 1".into()));
    }
    let chains = args.chains.as_deref().map(chains_of_lengths);
    let params = MapParams {
        contact_radius: args.contact_radius,
        monomers_per_bin: args.monomers_per_bin,
        chains,
    };
    let bar = spinner("conformations");
    let map = contact_map(open_trajectories(&args.inputs)?, &params, &|done| {
        bar.set_position(done as u64)
    })?;
    bar.finish_and_clear();
    let reader = InMemory::new("polymer-map".into(), map.matrix(args.monomer_bp)?);
    write_cool(&reader, &args.out, &CoolWriteOptions::default())?;
    eprintln!(
        "polymer-map: {} conformations of {} beads, {} bins, {} contacts counted",
        map.n_conformations,
        map.n_beads,
        map.bins.n_bins(),
        map.pixels.iter().map(|p| p.2).sum::<u64>()
    );
    let chained: usize = args.chains.iter().flatten().sum();
    if args.chains.is_some() && chained < map.n_beads {
        let mut notes = Warnings::new();
        notes.push(format!(
            "--chains covers beads 1-{chained} of {}: the last {} belong to no chain and are \
             left out of the map",
            map.n_beads,
            map.n_beads - chained
        ));
        notes.print();
    }
    Ok(())
}
