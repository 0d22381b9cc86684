//! `contactmap simulate polymer`: contact maps from ensembles of a simulated bead-spring chain
//! ([`contactmap::sim::polymer`], [`contactmap::sim::ensemble`], [`contactmap::sim::extrusion`]).

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};

use crate::cli::output::{Output, check_cool_output, refuse_overwrites, write_text_file};
use crate::cli::warnings::Warnings;
use contactmap::error::{Error, Result};
use contactmap::io::InMemory;
use contactmap::io::bed::read_bed_if_file;
use contactmap::io::cool::{CoolWriteOptions, write_cool};
use contactmap::sim::ensemble::EnsembleParams;
use contactmap::sim::files::parse_type_pattern;
use contactmap::sim::gpu::{Backend, Device};
use contactmap::sim::spec::{
    BondKind, BoundarySites, ConfinementKind, RepulsionKind, SimulationSpec,
};

/// Bond models, for `--bonds`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum BondArg {
    /// harmonic, E = ((r - 1) / wiggle)^2 (polychrom)
    Harmonic,
    /// FENE, K = 30, R0 = 1.5 (Kremer-Grest; use with --repulsion wca)
    Fene,
}

/// Excluded volume, for `--repulsion`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum RepulsionArg {
    /// polychrom's polynomial repulsion (soft, --repulsion-energy kT at contact, 0 from 1.05)
    Polynomial,
    /// Weeks-Chandler-Andersen (hard, sigma 1, epsilon 1)
    Wca,
    /// none: a phantom (ideal) chain
    None,
}

/// Confinement, for `--confinement`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ConfinementArg {
    /// a soft spherical wall holding the beads at --density
    Sphere,
    /// a periodic cube at --density
    Box,
    /// free space
    None,
}

/// Where to run, for `--device`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ConformationsFormatArg {
    /// replica sample chain bead x y z (TSV)
    Tsv,
    /// polychrom's HDF5 trajectory folder (blocks_X-Y.h5)
    Polychrom,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum DeviceArg {
    /// the GPU when a hardware one is usable, else the CPU
    Auto,
    /// every CPU core
    Cpu,
    /// the GPU (any Vulkan, Metal or DX12 adapter, software drivers such as lavapipe included);
    /// an error when there is none
    Gpu,
}

/// Arguments of `contactmap simulate polymer`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Model (units: bond length 1, kT 1, bead friction 1): chains of beads joined by harmonic (or
FENE) bonds, optional angle stiffness, excluded volume between non-bonded beads (polychrom's
soft polynomial repulsion, or WCA), optional attraction between beads of the same type (block
copolymer, --types), in free space, a soft sphere or a periodic box at --density. Overdamped
Langevin (Brownian) dynamics, dt = --dt; pair forces through cell lists (O(N) per step).
--ideal removes the excluded volume (phantom chain); --saw frees the chain (good solvent, no
confinement) with a weaker repulsion (0.6 kT, radius 0.8) at which chains of a few tens of beads
already swell as self-avoiding walks (Rg ~ N^0.588; polychrom's 3 kT / 1.05 swells short chains
more, Rg ~ N^0.62 at N = 64-128): the two physics checks (docs/simulation.md).

Loop extrusion (Fudenberg et al. 2016) with --extrusion: loop-extruding factors (one per
--separation monomers) load at random, extrude both ways one monomer per 1D step (one 1D step
every --steps-per-move 3D steps), unload after --processivity / 2 steps on average, and stall at
boundary elements (--ctcf): a + element stops leftward-moving legs, a - element rightward ones
(convergent rule), . both; capture with --capture, release per step with --release. Each LEF
holds its two legs together by a harmonic bond.

Devices (--device): the CPU backend runs replicas in parallel on every core; the GPU backend
(WGSL compute shaders through wgpu on Vulkan, Metal or DX12) steps all replicas together as one
batch of independent chains, so many replicas cost little more than one. Both simulate the same
model; the GPU in single precision.

Ensemble: --replicas independent chains (in parallel), each equilibrated for --equilibration
steps and then sampled --samples times every --sample-every steps. Beads closer than
--contact-radius are in contact; contacts are counted in bins of --monomers-per-bin beads. The
same --seed gives the same files whatever the number of threads.

Relaxation: a chain starts as a random walk; after a time t (steps x dt) it is at equilibrium
over separations up to s* = pi sqrt(3 t / <b^2>) beads (Rouse model), the whole chain of N beads
after its Rouse time N^2 <b^2> / (3 pi^2). Each run reports s* at its first and last sample
(also in --stats) and warns when the chains were sampled before they relaxed. --equilibration
and --sample-every take steps, `auto` (3 and 0.5 Rouse times of the longest chain) or Rouse
times such as 2R; docs/simulation.md (Equilibration and sampling) says what to pick for a map.

Outputs:
  OUT.cool              contact counts; chromosomes chr1..chrK (one per chain), --monomer-bp bp
                        per bead, so bins are monomers-per-bin x monomer-bp bp
  --truth-boundaries    BED: the bins holding a boundary element (score tads calls against it
                        with `contactmap score boundaries`)
  --truth-domains       BED: the segments between consecutive boundary elements of a chain
  --truth-loops         BEDPE: chrom1 start1 end1 chrom2 start2 end2 fraction samples, the bin
                        pairs of boundary elements a LEF held bridged (both legs captured) at a
                        sample, and the fraction of samples that held them (score dots calls
                        against it with `contactmap score loops`)
  --truth-compartments  BED: chrom start end TYPE FRACTION_A per bin (with --types): its beads'
                        majority type and the fraction of type A (a phasing track: FILE:5);
                        score eigenvectors with `contactmap score compartments`
  --conformations       TSV(.gz): replica sample chain bead x y z of every sampled conformation;
                        with --conformations-format polychrom a polychrom trajectory folder
  --stats               TSV: replica sample chain radius_of_gyration time
                        relaxed_separation (s* at the sample's time)

Examples:
  contactmap simulate polymer -o ideal.cool --ideal --chains 200 --replicas 8
  contactmap simulate polymer -o globule.cool --chains 2000 --density 0.2
  contactmap simulate polymer -o loops.cool --chains 4000 --density 0.2 \\
      --extrusion --ctcf 500+,1000-,1500+,2000-,2500.,3000. \\
      --processivity 200 --separation 400 --monomers-per-bin 10 \\
      --truth-boundaries truth.bed
  contactmap simulate polymer -o ab.cool --chains 2000 --density 0.3 \\
      --types A200B200 --attraction 0.4 --monomers-per-bin 10 \\
      --truth-compartments ab.truth.bed")]
pub struct PolymerArgs {
    /// Output .cool file.
    #[arg(short, long, value_name = "OUT.cool")]
    pub output: PathBuf,
    /// Beads of each chain (comma separated, one chain = one chromosome).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "1000",
        value_name = "N,..."
    )]
    pub chains: Vec<usize>,
    /// Base pairs per bead (for the .cool's coordinates).
    #[arg(long, default_value_t = 1000, value_name = "BP")]
    pub monomer_bp: u64,
    /// Beads per bin of the contact map.
    #[arg(long, default_value_t = 1, value_name = "N")]
    pub monomers_per_bin: usize,
    /// Bonds along the chain.
    #[arg(long, value_enum, default_value = "harmonic")]
    pub bonds: BondArg,
    /// Harmonic bond stretch that costs 1 kT.
    #[arg(long, default_value_t = 0.1, value_name = "LENGTH")]
    pub bond_wiggle: f64,
    /// Angle stiffness k of E = k (1 - cos theta), in kT (0: none).
    #[arg(long, default_value_t = 0.0, value_name = "KT")]
    pub stiffness: f64,
    /// Excluded volume.
    #[arg(long, value_enum, default_value = "polynomial")]
    pub repulsion: RepulsionArg,
    /// Height of the polynomial repulsion at contact, in kT [default: 3, polychrom's; 0.6 with
    /// --saw].
    #[arg(long, value_name = "KT")]
    pub repulsion_energy: Option<f64>,
    /// Range of the polynomial repulsion [default: 1.05, polychrom's; 0.8 with --saw].
    #[arg(long, value_name = "LENGTH")]
    pub repulsion_radius: Option<f64>,
    /// Beads at most this far apart along a chain do not feel the pair potential (1: bonded
    /// neighbours only, as polychrom).
    #[arg(long, default_value_t = 1, value_name = "K")]
    pub exclude_neighbours: usize,
    /// Ideal (phantom) chain: no excluded volume (same as --repulsion none).
    #[arg(long, conflicts_with_all = ["saw", "repulsion", "repulsion_energy", "repulsion_radius"])]
    pub ideal: bool,
    /// Self-avoiding walk check: free chains in good solvent (no attraction, no confinement),
    /// with the polynomial repulsion at 0.6 kT and radius 0.8 unless given.
    #[arg(long, conflicts_with_all = ["density", "types"])]
    pub saw: bool,
    /// Bead types, cyclically along each chain: letters with optional run lengths, e.g.
    /// A200B200 (beads of equal type attract with --attraction).
    #[arg(long, value_name = "PATTERN")]
    pub types: Option<String>,
    /// Attraction between beads of equal type (well depth in kT).
    #[arg(long, default_value_t = 0.3, value_name = "KT", requires = "types")]
    pub attraction: f64,
    /// Range of the attraction.
    #[arg(long, default_value_t = 1.5, value_name = "LENGTH", requires = "types")]
    pub attraction_radius: f64,
    /// Bead density (beads per unit volume) of the confinement.
    #[arg(long, value_name = "RHO")]
    pub density: Option<f64>,
    /// Confinement [default: sphere with --density, else none].
    #[arg(long, value_enum)]
    pub confinement: Option<ConfinementArg>,
    /// Time step [default: 0.002, or 0.0002 with WCA or FENE].
    #[arg(long, value_name = "DT")]
    pub dt: Option<f64>,
    /// Independent replicas (run in parallel).
    #[arg(long, default_value_t = 8, value_name = "N")]
    pub replicas: usize,
    /// Steps before the first sample: a number of steps, `auto` (3 Rouse times of the longest
    /// chain: equilibrium at every separation) or Rouse times such as `0.5R`.
    #[arg(long, default_value = "20000", value_name = "STEPS|auto|xR")]
    pub equilibration: String,
    /// Steps between samples: a number of steps, `auto` (half a Rouse time: samples
    /// independent at the chain's scale) or Rouse times such as `0.1R`.
    #[arg(long, default_value = "2000", value_name = "STEPS|auto|xR")]
    pub sample_every: String,
    /// Samples per replica.
    #[arg(long, default_value_t = 50, value_name = "N")]
    pub samples: usize,
    /// Beads closer than this are in contact.
    #[arg(long, default_value_t = 1.5, value_name = "LENGTH")]
    pub contact_radius: f64,
    /// Seed of every random stream.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Loop extrusion on.
    #[arg(long)]
    pub extrusion: bool,
    /// Boundary elements: a BED file (strand column: + - .) or bead positions such as
    /// 500+,1000-,1500 (global bead index; + or - orientation, none or . for both).
    #[arg(long, value_name = "BED|POSITIONS", requires = "extrusion")]
    pub ctcf: Option<String>,
    /// Mean loop size grown by a LEF before it unloads, in beads.
    #[arg(long, default_value_t = 100.0, value_name = "BEADS")]
    pub processivity: f64,
    /// Beads per LEF.
    #[arg(long, default_value_t = 200.0, value_name = "BEADS")]
    pub separation: f64,
    /// Probability that a boundary element captures an arriving leg.
    #[arg(long, default_value_t = 0.9, value_name = "P")]
    pub capture: f64,
    /// Probability per 1D step that a captured leg is released.
    #[arg(long, default_value_t = 0.005, value_name = "P")]
    pub release: f64,
    /// 3D steps per 1D extrusion step.
    #[arg(long, default_value_t = 50, value_name = "STEPS")]
    pub steps_per_move: usize,
    /// Write the true boundary bins (BED).
    #[arg(long, value_name = "BED")]
    pub truth_boundaries: Option<PathBuf>,
    /// Write the true domains (BED).
    #[arg(long, value_name = "BED")]
    pub truth_domains: Option<PathBuf>,
    /// Write the loops LEFs held between boundary elements (BEDPE with the fraction of samples
    /// that held each), with --extrusion.
    #[arg(long, value_name = "BEDPE", requires = "extrusion")]
    pub truth_loops: Option<PathBuf>,
    /// Write each bin's type (BED: chrom start end TYPE FRACTION_A, the majority type of its
    /// beads and the fraction of them of type A), with --types.
    #[arg(long, value_name = "BED", requires = "types")]
    pub truth_compartments: Option<PathBuf>,
    /// Write every sampled conformation (TSV, .gz compresses; a folder with
    /// --conformations-format polychrom).
    #[arg(long, value_name = "FILE")]
    pub conformations: Option<PathBuf>,
    /// The conformations' format: tsv (replica sample chain bead x y z, 4 decimals), or polychrom
    /// (a trajectory folder of blocks_X-Y.h5 files, full precision, that polychrom's
    /// hdf5_format.list_URIs / load_URI and `polymer-map` read).
    #[arg(long, value_enum, default_value = "tsv", requires = "conformations")]
    pub conformations_format: ConformationsFormatArg,
    /// Write the radius of gyration of every sample (TSV).
    #[arg(long, value_name = "FILE")]
    pub stats: Option<PathBuf>,
    /// Threads for the replicas and within each chain [default: all cores]. The results do not
    /// depend on it: the same --seed gives the same files on any number of threads.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Where to simulate: auto takes a hardware GPU when one is usable (it says which device it
    /// used on stderr). The same seed gives the same map on the same kind of device; the CPU and
    /// the GPU agree in distribution, not bit for bit.
    #[arg(long, value_enum, default_value = "auto")]
    pub device: DeviceArg,
}

impl PolymerArgs {
    /// The library's parameters, checked before any work.
    /// The library's specification of the run (`contactmap::sim::spec`).
    pub fn spec(&self) -> Result<SimulationSpec> {
        let ctcf = match &self.ctcf {
            Some(value) => Some(BoundarySites::new(value, read_bed_if_file(value)?)),
            None => None,
        };
        Ok(SimulationSpec {
            chains: self.chains.clone(),
            monomer_bp: self.monomer_bp,
            monomers_per_bin: self.monomers_per_bin,
            bonds: match self.bonds {
                BondArg::Harmonic => BondKind::Harmonic,
                BondArg::Fene => BondKind::Fene,
            },
            bond_wiggle: self.bond_wiggle,
            stiffness: self.stiffness,
            repulsion: match self.repulsion {
                RepulsionArg::Polynomial => RepulsionKind::Polynomial,
                RepulsionArg::Wca => RepulsionKind::Wca,
                RepulsionArg::None => RepulsionKind::None,
            },
            repulsion_energy: self.repulsion_energy,
            repulsion_radius: self.repulsion_radius,
            exclude_neighbours: self.exclude_neighbours,
            ideal: self.ideal,
            saw: self.saw,
            types: self.types.clone(),
            attraction: self.attraction,
            attraction_radius: self.attraction_radius,
            density: self.density,
            confinement: self.confinement.map(|kind| match kind {
                ConfinementArg::Sphere => ConfinementKind::Sphere,
                ConfinementArg::Box => ConfinementKind::Box,
                ConfinementArg::None => ConfinementKind::None,
            }),
            dt: self.dt,
            replicas: self.replicas,
            equilibration: self.equilibration.clone(),
            sample_every: self.sample_every.clone(),
            samples: self.samples,
            contact_radius: self.contact_radius,
            seed: self.seed,
            extrusion: self.extrusion,
            ctcf,
            processivity: self.processivity,
            separation: self.separation,
            capture: self.capture,
            release: self.release,
            steps_per_move: self.steps_per_move,
            keep_conformations: self.conformations.is_some(),
        })
    }

    /// The simulator's parameters ([`SimulationSpec::params`]).
    pub fn params(&self) -> Result<EnsembleParams> {
        self.spec()?.params()
    }
}

/// Run `contactmap simulate polymer`.
pub fn run(args: &PolymerArgs) -> Result<()> {
    check_cool_output("simulate", &args.output)?;
    if args.threads == Some(0) {
        return Err(Error::Argument("--threads must be at least 1".into()));
    }
    let ctcf_file = args.ctcf.as_deref().map(Path::new).filter(|p| p.is_file());
    refuse_overwrites(
        &ctcf_file.into_iter().collect::<Vec<_>>(),
        &[
            Some(&args.output),
            args.truth_boundaries.as_deref(),
            args.truth_domains.as_deref(),
            args.truth_loops.as_deref(),
            args.truth_compartments.as_deref(),
            args.conformations.as_deref(),
            args.stats.as_deref(),
        ],
    )?;
    let params = args.params()?;
    let bins = params.bin_table(args.monomer_bp)?;
    let bar = if std::io::stderr().is_terminal() {
        let bar = indicatif::ProgressBar::new(params.replicas as u64);
        bar.set_message("simulating replicas");
        bar
    } else {
        indicatif::ProgressBar::hidden()
    };
    let backend = Backend::open(match args.device {
        DeviceArg::Auto => Device::Auto,
        DeviceArg::Cpu => Device::Cpu,
        DeviceArg::Gpu => Device::Gpu,
    })?;
    let pool = match args.threads {
        None => None,
        Some(threads) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .map_err(|err| Error::Argument(format!("--threads {threads}: {err}")))?,
        ),
    };
    let simulate = || {
        eprintln!("simulate polymer: {}", backend.description());
        backend.run(&params, &|_| bar.inc(1))
    };
    let ensemble = match &pool {
        Some(pool) => pool.install(simulate)?,
        None => simulate()?,
    };
    bar.finish_and_clear();
    let reader = InMemory::new("simulate polymer".into(), ensemble.matrix(bins.clone())?);
    write_cool(&reader, &args.output, &CoolWriteOptions::default())?;
    if let Some(path) = &args.truth_boundaries {
        write_text_file(path, params.truth_boundaries_bed(&bins))?;
    }
    if let (Some(path), Some(pattern)) = (&args.truth_compartments, &args.types) {
        let (_, letters) = parse_type_pattern(pattern)?;
        let text = params
            .truth_compartments_bed(&bins, &letters)
            .expect("--types sets the bead types");
        write_text_file(path, &text)?;
    }
    if let Some(path) = &args.truth_domains {
        write_text_file(path, params.truth_domains_bed(&bins, args.monomer_bp))?;
    }
    if let Some(path) = &args.truth_loops {
        write_text_file(path, ensemble.truth_loops_bedpe(&bins))?;
    }
    if let Some(path) = &args.conformations {
        match args.conformations_format {
            ConformationsFormatArg::Tsv => {
                let mut out = Output::open(Some(path))?;
                ensemble.write_conformations(&params, |bytes| out.write_all(bytes))?;
                out.finish()?;
            }
            ConformationsFormatArg::Polychrom => {
                contactmap::io::trajectory::polychrom::write_blocks(path, &ensemble.conformations)?;
            }
        }
    }
    if let Some(path) = &args.stats {
        write_text_file(path, ensemble.stats_tsv(&params))?;
    }
    let report = params.relaxation_report();
    let mut notes = Warnings::new();
    notes.note(report.note);
    if let Some(warning) = report.warning {
        notes.push(warning);
    }
    notes.print();
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use contactmap::sim::polymer::Repulsion;

    #[derive(clap::Parser)]
    struct Command {
        #[command(flatten)]
        args: PolymerArgs,
    }

    fn repulsion(extra: &[&str]) -> Repulsion {
        let argv = [&["simulate", "-o", "x.cool"][..], extra].concat();
        let command = <Command as clap::Parser>::try_parse_from(argv).unwrap();
        command.args.params().unwrap().polymer.repulsion
    }

    #[test]
    fn repulsion_defaults_and_overrides() {
        let polynomial = |energy, radius| Repulsion::Polynomial { energy, radius };
        assert_eq!(repulsion(&[]), polynomial(3.0, 1.05));
        assert_eq!(repulsion(&["--saw"]), polynomial(0.6, 0.8));
        assert_eq!(
            repulsion(&["--saw", "--repulsion-energy", "2"]),
            polynomial(2.0, 0.8)
        );
        assert_eq!(
            repulsion(&["--repulsion-radius", "1.2"]),
            polynomial(3.0, 1.2)
        );
        assert_eq!(repulsion(&["--ideal"]), Repulsion::None);
    }
}
