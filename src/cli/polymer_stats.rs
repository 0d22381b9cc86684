//! `contactmap polymer-stats`: P(s), `<R^2(s)>`, `<Rg^2(s)>` and each conformation's `Rg^2` of a
//! set of 3D conformations, as polychrom's `polymer_analyses` computes them
//! ([`contactmap::conformations::stats`]).

use std::path::{Path, PathBuf};

use clap::Args;

use crate::cli::output::{refuse_overwrites, write_text_file};
use contactmap::conformations::stats::ensemble_stats;
use contactmap::error::Result;
use contactmap::io::output::python_float;
use contactmap::io::trajectory::open_trajectories;

/// Arguments of `contactmap polymer-stats`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Per conformation, as polychrom's polymer_analyses computes it, then the mean over conformations:
  PREFIX.scaling.tsv  s_mid contact_probability: contact_scaling, the contacts (beads at most
                      --contact-radius apart) whose separation j - i lies in [b_k, b_k+1), over
                      the pairs possible there, at sqrt(b_k (b_k+1 - 1)); b are generate_bins(N):
                      log-spaced from 4 to N - 1, about 10 per decade
  PREFIX.r2.tsv       s r2 rg2: R2_scaling (mean squared distance of beads s apart) and
                      Rg2_scaling (mean squared radius of gyration of subchains of s beads)
  PREFIX.rg2.tsv      conformation rg2: each conformation's squared radius of gyration (Rg2), in
                      the order read (over time, for a trajectory)
Every conformation is one chain of N beads (polychrom's functions take one). Inputs as
`polymer-map`'s: polychrom folders, blocks files or URIs, conformations tables, XYZ, DCD, XTC,
multi-model PDB / mmCIF (every atom a bead).
`contactmap plot polymer-stats PREFIX -o stats.png` draws the tables.

Examples:
  contactmap polymer-stats traj/ -o traj
  contactmap polymer-stats conformations.tsv.gz --contact-radius 1.5 -o sim")]
pub struct PolymerStatsArgs {
    /// Trajectories: polychrom folders, blocks files or URIs; conformations tables; XYZ, DCD,
    /// XTC, multi-model PDB / mmCIF files.
    #[arg(value_name = "TRAJ", required = true)]
    pub inputs: Vec<String>,
    /// Beads at most this far apart are in contact (polychrom's contact_scaling cutoff).
    #[arg(long, default_value_t = 1.1, value_name = "R")]
    pub contact_radius: f64,
    /// Output prefix: PREFIX.scaling.tsv, PREFIX.r2.tsv, PREFIX.rg2.tsv.
    #[arg(short, long, value_name = "PREFIX")]
    pub out: PathBuf,
}

/// Run `contactmap polymer-stats`.
pub fn run(args: &PolymerStatsArgs) -> Result<()> {
    let prefix = args.out.to_string_lossy().into_owned();
    let outputs = ["scaling", "r2", "rg2"].map(|k| PathBuf::from(format!("{prefix}.{k}.tsv")));
    let inputs: Vec<&Path> = args
        .inputs
        .iter()
        .map(|i| Path::new(i.split("::").next().unwrap_or(i)))
        .collect();
    refuse_overwrites(
        &inputs,
        &[Some(&outputs[0]), Some(&outputs[1]), Some(&outputs[2])],
    )?;
    let stats = ensemble_stats(open_trajectories(&args.inputs)?, args.contact_radius)?;
    let mut scaling = String::from("s_mid\tcontact_probability\n");
    for &(mid, p) in &stats.contact_scaling {
        scaling.push_str(&format!("{}\t{}\n", python_float(mid), python_float(p)));
    }
    let mut r2 = String::from("s\tr2\trg2\n");
    for ((s, a), b) in stats.bins.iter().zip(&stats.r2).zip(&stats.rg2_of_s) {
        r2.push_str(&format!(
            "{s}\t{}\t{}\n",
            python_float(*a),
            python_float(*b)
        ));
    }
    let mut rg2 = String::from("conformation\trg2\n");
    for (label, g) in &stats.rg2 {
        rg2.push_str(&format!("{label}\t{}\n", python_float(*g)));
    }
    write_text_file(&outputs[0], scaling)?;
    write_text_file(&outputs[1], r2)?;
    write_text_file(&outputs[2], rg2)?;
    eprintln!(
        "polymer-stats: {} conformations of {} beads, {} separations",
        stats.rg2.len(),
        stats.n_beads,
        stats.bins.len()
    );
    Ok(())
}
