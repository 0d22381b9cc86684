//! The resolutions of a multi-resolution file, as `cooler zoomify --resolutions` reads them:
//! bin sizes in bp, `BASE`N (1-2-5 steps: `1000N` is 1000, 2000, 5000, 10000, ...), `BASE`B
//! (doublings), `N` / `B` starting at the input's bin size, and `4DN` (`1000,2000,5000N`).

use crate::error::{Error, Result};
use crate::genome::BinTable;

/// Expand resolutions (numbers, `BASE`N and `BASE`B progressions) into a sorted list, each a
/// multiple of `base` (the input's bin size), the progressions up to `longest_bp`.
pub fn parse_resolutions(items: &[String], base: u64, longest_bp: u64) -> Result<Vec<u64>> {
    let nice = |start: u64| {
        let mut out = Vec::new();
        let mut decade = 1u64;
        while start.saturating_mul(decade) <= longest_bp.max(start) {
            for step in [1, 2, 5] {
                let r = start.saturating_mul(decade).saturating_mul(step);
                if r <= longest_bp.max(start) {
                    out.push(r);
                }
            }
            decade = decade.saturating_mul(10);
        }
        out
    };
    let doubling = |start: u64| {
        let mut out = Vec::new();
        let mut r = start;
        while r <= longest_bp.max(start) {
            out.push(r);
            r = r.saturating_mul(2);
        }
        out
    };
    let mut resolutions = Vec::new();
    if items.is_empty() {
        resolutions = nice(base);
    }
    for item in items {
        let item = item.trim();
        let bad = || {
            Error::Argument(format!(
                "--resolutions: '{item}' is not a resolution (a bin size in bp, or BASE N / BASE B)"
            ))
        };
        if let Some(start) = item.strip_suffix(['N', 'n']) {
            resolutions.extend(nice(start.parse().map_err(|_| bad())?));
        } else if let Some(start) = item.strip_suffix(['B', 'b']) {
            resolutions.extend(doubling(start.parse().map_err(|_| bad())?));
        } else {
            resolutions.push(item.parse().map_err(|_| bad())?);
        }
    }
    resolutions.sort_unstable();
    resolutions.dedup();
    for &r in &resolutions {
        if r == 0 || r % base != 0 {
            return Err(Error::Argument(format!(
                "--resolutions: {r} is not a multiple of the input's bin size {base}"
            )));
        }
    }
    Ok(resolutions)
}

/// The bin size of a matrix with fixed-size bins (an .mcool or .hic needs one); `source` names
/// it in the error.
pub fn fixed_resolution(bins: &BinTable, source: &str) -> Result<u64> {
    bins.resolution().ok_or_else(|| {
        Error::Unsupported(format!(
            "{source}: multi-resolution outputs (.mcool, .hic) need fixed-size bins; this matrix has variable bins"
        ))
    })
}

/// The resolutions of an .mcool made from a matrix on `bins`: `items` as [`parse_resolutions`]
/// reads them, after [`expand_tokens`], up to the longest chromosome.
///
/// # Examples
///
/// ```
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::cool::resolutions::mcool_resolutions;
///
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 25_000)], 1_000)?;
/// let items = ["N".to_string()];
/// assert_eq!(mcool_resolutions(&bins, "in.cool", &items)?, [1000, 2000, 5000, 10000, 20000]);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn mcool_resolutions(bins: &BinTable, source: &str, items: &[String]) -> Result<Vec<u64>> {
    let base = fixed_resolution(bins, source)?;
    let longest = bins
        .chroms()
        .iter()
        .map(|c| c.length_bp)
        .max()
        .unwrap_or(base);
    parse_resolutions(&expand_tokens(items, base), base, longest)
}

/// cooler's progressions without a start (`B`, `N`) start at `base`; `4DN` is
/// `1000,2000,5000N`.
pub fn expand_tokens(items: &[String], base: u64) -> Vec<String> {
    let mut out = Vec::new();
    for item in items {
        match item.trim() {
            "B" | "b" => out.push(format!("{base}B")),
            "N" | "n" => out.push(format!("{base}N")),
            "4DN" | "4dn" => out.extend(["1000", "2000", "5000N"].map(String::from)),
            other => out.push(other.to_string()),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resolution_lists_and_progressions() {
        let list = |items: &[&str]| {
            parse_resolutions(
                &items.iter().map(|s| s.to_string()).collect::<Vec<_>>(),
                1000,
                30_000,
            )
        };
        assert_eq!(
            list(&["1000", "5000", "2000"]).unwrap(),
            vec![1000, 2000, 5000]
        );
        assert_eq!(
            list(&["1000N"]).unwrap(),
            vec![1000, 2000, 5000, 10000, 20000]
        );
        assert_eq!(
            list(&["1000B"]).unwrap(),
            vec![1000, 2000, 4000, 8000, 16000]
        );
        assert_eq!(list(&[]).unwrap(), vec![1000, 2000, 5000, 10000, 20000]);
        assert!(list(&["1500"]).is_err());
        assert!(list(&["abc"]).is_err());
        let items = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        assert_eq!(expand_tokens(&items(&["B"]), 10), items(&["10B"]));
        assert_eq!(
            expand_tokens(&items(&["4DN", "7"]), 1000),
            items(&["1000", "2000", "5000N", "7"])
        );
    }
}
