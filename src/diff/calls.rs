//! The loops `diff loops` tests when none are given: each condition's replicates summed, balanced
//! (ICE, cooler's defaults), dots called on the sum as `contactmap dots` calls them (cooltools'
//! HiCCUPS-style caller, the kernels cooltools recommends for the bin size), and the two
//! conditions' dots pooled, a dot of B within `radius` of one of A on both anchors counted once.

use super::loops::LoopSite;
use super::maps::{check_conditions, check_same_bins};
use crate::balance::{BalanceParams, balance};
use crate::error::{Error, Result};
use crate::expected::expected_to_divide_by;
use crate::genome::view::View;
use crate::io::bed::{BedRecord, BedpeRecord};
use crate::io::merged::MergedReader;
use crate::io::{MatrixReader, default_memory_budget, load_pixels_for_balancing};
use crate::loops::{DotsParams, call_dots};

/// One condition's dots.
#[derive(Debug, Clone)]
pub struct ConditionDots {
    /// The dots' pixels.
    pub sites: Vec<LoopSite>,
    /// Whether ICE converged on the summed replicates (the dots are called with its last
    /// weights either way; a caller should say so when it did not).
    pub converged: bool,
    /// ICE's iterations.
    pub n_iterations: usize,
}

/// The dots of one condition: its replicates summed, balanced, called (`params`: the caller's
/// settings, [`DotsParams::for_resolution`] when `None`). The summed pixels are held in memory
/// when they take at most `memory_budget` bytes (16 a pixel), else read again on every pass.
pub fn condition_dots(
    replicates: &[&dyn MatrixReader],
    params: Option<&DotsParams>,
    memory_budget: u64,
) -> Result<ConditionDots> {
    let merged = MergedReader::new(replicates.to_vec())?;
    let bins = merged.bins();
    let resolution = bins.resolution().ok_or_else(|| {
        Error::Data(format!(
            "{}: calling loops needs bins of one size; give the loops with --loops",
            replicates[0].source()
        ))
    })?;
    let params = match params {
        Some(params) => params.clone(),
        None => DotsParams::for_resolution(resolution)?,
    };
    // the summed pixels in memory when they fit (balancing passes over them many times)
    let pixels = load_pixels_for_balancing(&merged, memory_budget)?;
    let balanced = balance(&pixels, &BalanceParams::default())?;
    let view = View::chromosomes(bins);
    let expected = expected_to_divide_by(
        &pixels,
        Some(&balanced.weights),
        &view,
        None,
        "balanced.avg",
        false,
    )?;
    // the dots read the summed pixels from memory, not the replicates again
    let from_memory = pixels.reader(&merged);
    let summed: &dyn MatrixReader = match &from_memory {
        Some(reader) => reader,
        None => &merged,
    };
    let calls = call_dots(summed, &balanced.weights, &view, &expected, &params)?;
    let sites = calls
        .dots
        .unwrap_or_default()
        .iter()
        .map(|dot| LoopSite {
            bin1: dot.pixel.bin1,
            bin2: dot.pixel.bin2,
        })
        .collect();
    Ok(ConditionDots {
        sites,
        converged: balanced.converged,
        n_iterations: balanced.n_iterations,
    })
}

/// The loops called in two conditions, pooled ([`called_loops`]).
#[derive(Debug, Clone)]
pub struct CalledLoops {
    /// The loops, sorted by position.
    pub sites: Vec<LoopSite>,
    /// The same loops as BEDPE records (each anchor its bin).
    pub records: Vec<BedpeRecord>,
    /// Dots of the first condition, and of the second.
    pub n_first: usize,
    /// Dots of the second condition.
    pub n_second: usize,
    /// The pooling radius (the dots' clustering radius).
    pub radius_bp: f64,
    /// The conditions (`A`, `B`) whose ICE did not converge, with its iterations.
    pub unconverged: Vec<(&'static str, usize)>,
}

/// The loops `diff loops` tests when none are given: [`condition_dots`] of each condition (with
/// the kernels' half-widths `kernels = (w, p)` where given, else cooltools' recommended ones for
/// the bin size), pooled by [`union`] within the dots' clustering radius (20 kb). Maps on other
/// bins (checked first, before the calling) and no dot in either condition are errors.
pub fn called_loops(
    first: &[&dyn MatrixReader],
    second: &[&dyn MatrixReader],
    kernels: Option<(usize, usize)>,
) -> Result<CalledLoops> {
    check_conditions(first.len() + second.len(), first.len())?;
    let every: Vec<&dyn MatrixReader> = first.iter().chain(second).copied().collect();
    check_same_bins(&every)?;
    let params = match kernels {
        Some((w, p)) => {
            let params = DotsParams {
                w,
                p,
                ..DotsParams::default()
            };
            params.check()?;
            params
        }
        None => match first[0].bins().resolution() {
            Some(resolution) => DotsParams::for_resolution(resolution).map_err(|_| {
                Error::Argument(format!(
                    "calling the dots of {resolution} bp bins needs kernels: cooltools recommends \
                     them for bins of 4-28 kb only; give --w and --p (HiCCUPS: 7 and 4 at 5 kb, 5 \
                     and 2 at 10 kb, 3 and 1 at 25 kb) or the loops with --loops"
                ))
            })?,
            None => {
                return Err(Error::Data(format!(
                    "{}: calling loops needs bins of one size; give the loops with --loops",
                    first[0].source()
                )));
            }
        },
    };
    let radius_bp = DotsParams::default()
        .clustering_radius_bp
        .unwrap_or(20_000.0);
    let bins = first[0].bins();
    let resolution = bins.resolution().unwrap_or(1) as f64;
    // the two conditions side by side (each on its own thread, each half the memory budget):
    // reading and the serial parts of one fill the cores the other leaves idle
    let budget = default_memory_budget() / 2;
    let dots_of = |name: &str, replicates: &[&dyn MatrixReader]| {
        condition_dots(replicates, Some(&params), budget).map_err(|e| match e {
            Error::Data(message) => Error::Data(format!(
                "the dots of condition {name} (its replicates summed): {message}; give the loops \
                 with --loops"
            )),
            other => other,
        })
    };
    let (dots_a, dots_b) = std::thread::scope(|scope| {
        let a = scope.spawn(|| dots_of("A", first));
        let b = dots_of("B", second);
        (a.join().expect("condition A's thread panicked"), b)
    });
    let (dots_a, dots_b) = (dots_a?, dots_b?);
    let unconverged = [("A", &dots_a), ("B", &dots_b)]
        .into_iter()
        .filter(|(_, dots)| !dots.converged)
        .map(|(name, dots)| (name, dots.n_iterations))
        .collect();
    let called = [dots_a.sites, dots_b.sites];
    let sites = union(
        &called[0],
        &called[1],
        (radius_bp / resolution).ceil() as usize,
    );
    if sites.is_empty() {
        return Err(Error::Data(
            "no dots were called in either condition: give the loops with --loops".to_string(),
        ));
    }
    let records = sites
        .iter()
        .enumerate()
        .map(|(k, site)| {
            let anchor = |bin_id: usize| {
                let bin = bins.bin(bin_id);
                BedRecord::new(bins.chroms()[bin.chrom_id].name.clone(), bin.start, bin.end)
            };
            BedpeRecord {
                first: anchor(site.bin1),
                second: anchor(site.bin2),
                rest: Vec::new(),
                line: k as u64 + 1,
            }
        })
        .collect();
    Ok(CalledLoops {
        sites,
        records,
        n_first: called[0].len(),
        n_second: called[1].len(),
        radius_bp,
        unconverged,
    })
}

/// The union of two conditions' dots: every dot of `first`, then each dot of `second` that lies
/// farther than `radius_bins` on either anchor from every dot of `first`; sorted by position.
pub fn union(first: &[LoopSite], second: &[LoopSite], radius_bins: usize) -> Vec<LoopSite> {
    let mut sorted_first = first.to_vec();
    sorted_first.sort_by_key(|s| (s.bin1, s.bin2));
    let mut out = sorted_first.clone();
    for site in second {
        let from = sorted_first.partition_point(|s| s.bin1 + radius_bins < site.bin1);
        let near = sorted_first[from..]
            .iter()
            .take_while(|s| s.bin1 <= site.bin1 + radius_bins)
            .any(|s| s.bin2.abs_diff(site.bin2) <= radius_bins);
        if !near {
            out.push(*site);
        }
    }
    out.sort_by_key(|s| (s.bin1, s.bin2));
    out.dedup();
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The union against its definition, checked pair by pair (a naive all-pairs version).
    #[test]
    fn union_keeps_each_loop_once_within_the_radius() {
        let site = |bin1, bin2| LoopSite { bin1, bin2 };
        let first = [site(10, 50), site(100, 140), site(30, 90)];
        let second = [
            site(11, 52),
            site(12, 53),
            site(100, 150),
            site(200, 260),
            site(31, 89),
        ];
        let got = union(&first, &second, 2);
        let mut want: Vec<LoopSite> = first.to_vec();
        for s in second {
            if !first
                .iter()
                .any(|f| f.bin1.abs_diff(s.bin1) <= 2 && f.bin2.abs_diff(s.bin2) <= 2)
            {
                want.push(s);
            }
        }
        want.sort_by_key(|s| (s.bin1, s.bin2));
        assert_eq!(got, want);
        // (11, 52) and (31, 89) are A's loops; (12, 53) is 3 bins from (10, 50)
        assert_eq!(got.len(), 6);
    }

    /// The summed replicates held in memory (a compact copy for ICE, the dots read from memory)
    /// or streamed from the files on every pass (a budget of 0): the same dots.
    #[test]
    fn dots_are_the_same_from_memory_and_streamed() {
        use crate::io::{OpenOptions, open_matrix};
        let path = "data/sim_extrusion.5kb.cool";
        let first = open_matrix(path, &OpenOptions::default()).unwrap();
        let second = open_matrix(path, &OpenOptions::default()).unwrap();
        let replicates: Vec<&dyn MatrixReader> = vec![&*first, &*second];
        let in_memory = condition_dots(&replicates, None, u64::MAX).unwrap();
        let streamed = condition_dots(&replicates, None, 0).unwrap();
        assert!(!in_memory.sites.is_empty());
        assert_eq!(in_memory.sites, streamed.sites);
        assert_eq!(in_memory.n_iterations, streamed.n_iterations);
    }
}
