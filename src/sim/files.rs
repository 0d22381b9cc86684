//! The polymer simulator's files: the bead-type pattern and the boundary elements it reads
//! (`A200B200`, a BED of CTCF sites or a list of beads), and what it writes besides the map (the
//! true boundaries, domains and compartments as BED, the radius of gyration of every sample,
//! the sampled conformations), with the relaxation report of a run.

use std::path::Path;

use super::ensemble::{Ensemble, EnsembleParams};
use super::extrusion::{BoundaryElement, Orientation};
use super::polymer::chain_ranges;
use super::relaxation::Relaxation;
use crate::error::{Error, Result};
use crate::genome::{BinTable, Chrom};
use crate::io::bed::{BedRecord, bins_bed, write_bed_line};
use crate::io::tables::write_real;
use crate::matrix::{ContactMatrix, CountType, MatrixBuilder};

/// A bead-type pattern such as `A200B200` or `AABB` (letters, each with an optional run length)
/// as one type per bead of a period, and the letter of each type (in order of first use).
///
/// # Examples
///
/// ```
/// use contactmap::sim::files::parse_type_pattern;
///
/// let (period, letters) = parse_type_pattern("A2B3a1")?;
/// assert_eq!(period, [0, 0, 1, 1, 1, 0]);
/// assert_eq!(letters, b"AB");
/// assert!(parse_type_pattern("2A").is_err());
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn parse_type_pattern(pattern: &str) -> Result<(Vec<u8>, Vec<u8>)> {
    let bad = || {
        Error::Argument(format!(
            "bad --types '{pattern}' (expected letters with optional run lengths, e.g. A200B200)"
        ))
    };
    let mut types = Vec::new();
    let mut letters: Vec<u8> = Vec::new();
    let mut chars = pattern.trim().chars().peekable();
    while let Some(c) = chars.next() {
        if !c.is_ascii_alphabetic() {
            return Err(bad());
        }
        let mut digits = String::new();
        while let Some(d) = chars.peek().filter(|d| d.is_ascii_digit()) {
            digits.push(*d);
            chars.next();
        }
        let count: usize = if digits.is_empty() {
            1
        } else {
            digits.parse().map_err(|_| bad())?
        };
        let upper = c.to_ascii_uppercase() as u8;
        let id = match letters.iter().position(|&l| l == upper) {
            Some(id) => id,
            None => {
                letters.push(upper);
                letters.len() - 1
            }
        } as u8;
        types.extend(std::iter::repeat_n(id, count));
    }
    if types.is_empty() {
        return Err(bad());
    }
    Ok((types, letters))
}

fn orientation(strand: Option<char>) -> Orientation {
    match strand {
        Some('+') => Orientation::Forward,
        Some('-') => Orientation::Reverse,
        _ => Orientation::Both,
    }
}

/// Boundary elements from the `records` of the BED file at `path` (named in messages; CTCF sites:
/// `chrK start end [name score strand]`, `+` stops left-moving legs, `-` right-moving ones, no
/// strand both), on the chains of lengths `chains` (chromosomes `chr1..chrN`) whose beads are
/// `monomer_bp` long.
pub fn boundary_elements_from_bed(
    path: &Path,
    records: &[BedRecord],
    chains: &[usize],
    monomer_bp: u64,
    capture: f64,
    release: f64,
) -> Result<Vec<BoundaryElement>> {
    let mut elements = Vec::new();
    let starts = chain_ranges(chains);
    for record in records {
        let chain = record
            .chrom
            .strip_prefix("chr")
            .and_then(|k| k.parse::<usize>().ok())
            .filter(|&k| k >= 1 && k <= chains.len())
            .ok_or_else(|| {
                Error::Data(format!(
                    "{}: chromosome '{}' is not one of the simulated chains chr1..chr{}",
                    path.display(),
                    record.chrom,
                    chains.len()
                ))
            })?;
        let bead = (record.start / monomer_bp) as usize;
        if bead >= chains[chain - 1] {
            return Err(Error::Data(format!(
                "{}: boundary element at {}:{} is beyond the chain ({} bp)",
                path.display(),
                record.chrom,
                record.start,
                chains[chain - 1] as u64 * monomer_bp
            )));
        }
        elements.push(BoundaryElement {
            position: starts[chain - 1].start + bead,
            orientation: orientation(record.strand),
            capture,
            release,
        });
    }
    Ok(elements)
}

/// Boundary elements from a comma-separated list of bead indices, each with an optional `+`,
/// `-` or `.` orientation (`100+,250-,400`).
///
/// # Examples
///
/// ```
/// use contactmap::sim::extrusion::Orientation;
/// use contactmap::sim::files::boundary_elements_from_list;
///
/// let elements = boundary_elements_from_list("100+, 250-,400", 1.0, 0.0)?;
/// assert_eq!(elements.len(), 3);
/// assert_eq!((elements[1].position, elements[1].orientation), (250, Orientation::Reverse));
/// assert_eq!(elements[2].orientation, Orientation::Both);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn boundary_elements_from_list(
    text: &str,
    capture: f64,
    release: f64,
) -> Result<Vec<BoundaryElement>> {
    text.split(',')
        .filter(|token| !token.trim().is_empty())
        .map(|token| {
            let token = token.trim();
            let (number, strand) = match token.chars().last() {
                Some(c @ ('+' | '-')) => (&token[..token.len() - 1], Some(c)),
                Some('.') => (&token[..token.len() - 1], None),
                _ => (token, None),
            };
            let position: usize = number.parse().map_err(|_| {
                Error::Argument(format!(
                    "bad --ctcf element '{token}' (expected a bead index with an optional + or \
                     -, or an existing BED file)"
                ))
            })?;
            Ok(BoundaryElement {
                position,
                orientation: orientation(strand),
                capture,
                release,
            })
        })
        .collect()
}

/// How far a run relaxed, from Rouse estimates ([`Relaxation`]).
#[derive(Clone, Debug, PartialEq)]
pub struct RelaxationReport {
    /// The separations relaxed at the first and last samples, and how far apart samples are
    /// independent.
    pub note: String,
    /// Set when the chains were sampled before they relaxed.
    pub warning: Option<String>,
}

impl EnsembleParams {
    /// The bin table of the map: one chromosome `chrK` per chain, beads `monomer_bp` long,
    /// `monomers_per_bin` beads per bin.
    pub fn bin_table(&self, monomer_bp: u64) -> Result<BinTable> {
        let chroms = self
            .polymer
            .chains
            .iter()
            .enumerate()
            .map(|(k, &length)| Chrom::new(format!("chr{}", k + 1), length as u64 * monomer_bp))
            .collect();
        BinTable::fixed(chroms, self.monomers_per_bin as u64 * monomer_bp)
    }

    /// The simulated time of sample `k` (0-based) of every replica: equilibration, then `k + 1`
    /// intervals.
    pub fn sample_time(&self, k: usize) -> f64 {
        (self.equilibration_steps + (k + 1) * self.sample_every) as f64 * self.polymer.dt
    }

    /// How far the run relaxes, and a warning when the chains are sampled before they relax.
    pub fn relaxation_report(&self) -> RelaxationReport {
        let relaxation = Relaxation::new(&self.polymer);
        let longest = self.polymer.chains.iter().copied().max().unwrap_or(0);
        let dt = self.polymer.dt;
        let rouse_steps = relaxation.rouse_time(longest) / dt;
        let relaxed = |time: f64| relaxation.relaxed_separation(time).min(longest as f64);
        let first = relaxed(self.sample_time(0));
        let last = relaxed(self.sample_time(self.samples - 1));
        let independent = relaxed(self.sample_every as f64 * dt);
        let note = format!(
            "relaxed over separations up to s* = {first:.0} beads at the first \
             sample, {last:.0} at the last; samples independent up to {independent:.0} beads apart \
             (Rouse estimates: the {longest}-bead chain's Rouse time is {rouse_steps:.0} steps)"
        );
        let warning = (first < longest as f64).then(|| {
            format!(
                "the chains were sampled before they relaxed: after {} equilibration steps ({:.2} \
                 Rouse times) only segments up to {first:.0} of {longest} beads had reached \
                 equilibrium from the random-walk start, so contacts farther apart are not at \
                 equilibrium; --equilibration auto relaxes the whole chain (3 Rouse times, {:.0} \
                 steps); docs/simulation.md says what to pick for a map",
                self.equilibration_steps,
                self.equilibration_steps as f64 / rouse_steps,
                (3.0 * rouse_steps).ceil()
            )
        });
        RelaxationReport { note, warning }
    }

    /// The bins holding a boundary element, as BED (one line per bin).
    pub fn truth_boundaries_bed(&self, bins: &BinTable) -> Vec<u8> {
        let (bead_bin, _) = self.bins();
        let mut element_bins: Vec<usize> = self
            .boundary_beads()
            .into_iter()
            .map(|bead| bead_bin[bead] as usize)
            .collect();
        element_bins.dedup();
        bins_bed(
            bins,
            element_bins
                .into_iter()
                .map(|bin| (bin, bin + 1, Vec::new())),
        )
    }

    /// Each bin's majority bead type (a tie goes to the type met first in the pattern) and its
    /// fraction of type `A`, as BED `chrom start end TYPE fraction_A`; `letters` are the
    /// pattern's letters ([`parse_type_pattern`]). `None` without bead types.
    pub fn truth_compartments_bed(&self, bins: &BinTable, letters: &[u8]) -> Option<Vec<u8>> {
        let counts = self.bin_type_counts(letters.len())?;
        let a = letters.iter().position(|&l| l == b'A');
        let rows = counts.iter().enumerate().map(|(bin, c)| {
            let total: usize = c.iter().sum();
            let best = (0..c.len()).fold(0, |best, t| if c[t] > c[best] { t } else { best });
            let fraction_a = a.map_or(0.0, |a| c[a] as f64 / total.max(1) as f64);
            (
                bin,
                bin + 1,
                vec![(letters[best] as char).to_string(), format!("{fraction_a}")],
            )
        });
        Some(bins_bed(bins, rows))
    }

    /// The domains between boundary elements, as BED in bp (beads `monomer_bp` long).
    pub fn truth_domains_bed(&self, bins: &BinTable, monomer_bp: u64) -> Vec<u8> {
        let mut text = Vec::new();
        for (chain, beads) in self.true_domains() {
            write_bed_line(
                &mut text,
                &bins.chroms()[chain].name,
                beads.start as u64 * monomer_bp,
                beads.end as u64 * monomer_bp,
                &[],
            )
            .expect("writing to memory");
        }
        text
    }
}

impl Ensemble {
    /// The loops LEFs held bridged between boundary elements (`simulate polymer --truth-loops`),
    /// as BEDPE with a header: `chrom1 start1 end1 chrom2 start2 end2 fraction samples`, one
    /// line per pair of bins (from [`EnsembleParams::bin_table`]) in which some sample held a
    /// pair of elements, `samples` the number of samples that held one and `fraction` that
    /// number over all samples. Pairs within one bin are left out (they lie on the diagonal).
    pub fn truth_loops_bedpe(&self, bins: &BinTable) -> Vec<u8> {
        use std::io::Write as _;
        let mut text = b"chrom1\tstart1\tend1\tchrom2\tstart2\tend2\tfraction\tsamples\n".to_vec();
        let total = self.n_conformations.max(1) as f64;
        for &(bin1, bin2, samples) in &self.held_loops {
            if bin1 == bin2 {
                continue;
            }
            let (a, b) = (bins.bin(bin1 as usize), bins.bin(bin2 as usize));
            let chrom = |id: usize| &bins.chroms()[id].name;
            writeln!(
                text,
                "{}\t{}\t{}\t{}\t{}\t{}\t{}\t{samples}",
                chrom(a.chrom_id),
                a.start,
                a.end,
                chrom(b.chrom_id),
                b.start,
                b.end,
                samples as f64 / total
            )
            .expect("writing to memory");
        }
        text
    }

    /// The contact map of the ensemble on `bins` (from [`EnsembleParams::bin_table`]).
    pub fn matrix(&self, bins: BinTable) -> Result<ContactMatrix> {
        let mut builder = MatrixBuilder::new(bins, CountType::Integer);
        for &(bin1, bin2, count) in &self.pixels {
            builder.push(bin1 as u64, bin2 as u64, count as f64)?;
        }
        Ok(builder.build())
    }

    /// The radius of gyration of every chain of every sample, with the sample's time and the
    /// separation relaxed by then: `replica sample chain radius_of_gyration time
    /// relaxed_separation`.
    pub fn stats_tsv(&self, params: &EnsembleParams) -> Vec<u8> {
        let relaxation = Relaxation::new(&params.polymer);
        let mut text =
            b"replica\tsample\tchain\tradius_of_gyration\ttime\trelaxed_separation\n".to_vec();
        for (index, radii) in self.radii_of_gyration.iter().enumerate() {
            let sample = index % params.samples;
            let time = params.sample_time(sample);
            for (chain, &rg) in radii.iter().enumerate() {
                text.extend_from_slice(
                    format!("{}\t{sample}\t{}\t", index / params.samples, chain + 1).as_bytes(),
                );
                write_real(&mut text, rg);
                text.push(b'\t');
                write_real(&mut text, time);
                text.push(b'\t');
                let relaxed = relaxation
                    .relaxed_separation(time)
                    .min(params.polymer.chains[chain] as f64);
                write_real(&mut text, (relaxed * 10.0).round() / 10.0);
                text.push(b'\n');
            }
        }
        text
    }

    /// The kept conformations as text, one bead per line (`replica sample chain bead x y z`,
    /// 4 decimals), given to `write` a line at a time.
    pub fn write_conformations(
        &self,
        params: &EnsembleParams,
        mut write: impl FnMut(&[u8]) -> Result<()>,
    ) -> Result<()> {
        write(b"replica\tsample\tchain\tbead\tx\ty\tz\n")?;
        let mut text = Vec::new();
        for (index, positions) in self.conformations.iter().enumerate() {
            for (chain, range) in params.polymer.chain_ranges().into_iter().enumerate() {
                for (k, p) in positions[range].iter().enumerate() {
                    text.clear();
                    text.extend_from_slice(
                        format!(
                            "{}\t{}\t{}\t{k}\t{:.4}\t{:.4}\t{:.4}\n",
                            index / params.samples,
                            index % params.samples,
                            chain + 1,
                            p[0],
                            p[1],
                            p[2]
                        )
                        .as_bytes(),
                    );
                    write(&text)?;
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn type_patterns() {
        assert_eq!(
            parse_type_pattern("A2B3").unwrap(),
            (vec![0, 0, 1, 1, 1], b"AB".to_vec())
        );
        assert_eq!(parse_type_pattern("ABBA").unwrap().0, vec![0, 1, 1, 0]);
        assert_eq!(
            parse_type_pattern("b3a1").unwrap(),
            (vec![0, 0, 0, 1], b"BA".to_vec())
        );
        for bad in ["", "2A", "A-1", "A B"] {
            assert!(parse_type_pattern(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn ctcf_lists() {
        let elements = boundary_elements_from_list("10+,20-,30,40.", 0.9, 0.01).unwrap();
        let summary: Vec<(usize, Orientation)> = elements
            .iter()
            .map(|e| (e.position, e.orientation))
            .collect();
        assert_eq!(
            summary,
            vec![
                (10, Orientation::Forward),
                (20, Orientation::Reverse),
                (30, Orientation::Both),
                (40, Orientation::Both)
            ]
        );
        assert!(boundary_elements_from_list("x+", 0.9, 0.01).is_err());
    }
}
