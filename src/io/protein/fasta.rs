//! GC content of a map's bins from a genome FASTA (plain or gzip), as `cooltools genome gc`
//! (bioframe's `frac_gc` with `mapped_only=True`): per bin, (G + C) / (bases - N), case
//! ignored, NaN where a bin has no base other than N. The FASTA is streamed: one line in memory.

use std::io::BufRead;
use std::path::Path;

use crate::error::{Error, Result};
use crate::genome::BinTable;

/// Per-bin tallies while the sequence streams past.
#[derive(Clone, Copy, Default)]
struct Tally {
    gc: u64,
    n: u64,
    bases: u64,
}

/// The GC fraction of every bin of `bins` (NaN for bins with no mapped base). Every chromosome
/// of `bins` must be in the FASTA; FASTA records that are not chromosomes of the map are
/// skipped.
pub fn gc_content(path: &Path, bins: &BinTable) -> Result<Vec<f64>> {
    let reader = crate::io::plumbing::input::open_text(path)?;
    let mut tallies = vec![Tally::default(); bins.n_bins()];
    let mut seen = vec![false; bins.chroms().len()];
    // the current record: its bins, the bin being filled, the position
    let mut current: Option<(std::ops::Range<usize>, usize, u64)> = None;
    let mut saw_header = false;
    for (index, line) in reader.split(b'\n').enumerate() {
        let mut line = line.map_err(|e| Error::io(path, e))?;
        if line.last() == Some(&b'\r') {
            line.pop();
        }
        if let Some(header) = line.strip_prefix(b">") {
            saw_header = true;
            let name = String::from_utf8_lossy(header);
            let name = name.split_whitespace().next().unwrap_or("");
            current = bins
                .chrom_id(name)
                .map(|c| {
                    if seen[c] {
                        return Err(Error::parse(
                            path,
                            index as u64 + 1,
                            format!("sequence '{name}' appears twice"),
                        ));
                    }
                    seen[c] = true;
                    let range = bins.chrom_bins(c);
                    let first = range.start;
                    Ok((range, first, 0))
                })
                .transpose()?;
            continue;
        }
        if line.is_empty() || line.starts_with(b";") {
            continue;
        }
        if !saw_header {
            return Err(Error::parse(
                path,
                index as u64 + 1,
                "expected a FASTA header ('>name') before the sequence",
            ));
        }
        let Some((range, bin, pos)) = current.as_mut() else {
            continue;
        };
        let mut rest: &[u8] = &line;
        while !rest.is_empty() && *bin < range.end {
            let span = bins.bin(*bin);
            if *pos < span.start {
                // before the first bin (a map over part of the chromosome)
                let skip = ((span.start - *pos) as usize).min(rest.len());
                rest = &rest[skip..];
                *pos += skip as u64;
                continue;
            }
            let room = (span.end - *pos) as usize;
            let (here, after) = rest.split_at(room.min(rest.len()));
            let t = &mut tallies[*bin];
            for &b in here {
                match b {
                    b'G' | b'g' | b'C' | b'c' => t.gc += 1,
                    b'N' | b'n' => t.n += 1,
                    _ => {}
                }
            }
            t.bases += here.len() as u64;
            *pos += here.len() as u64;
            rest = after;
            if *pos == span.end {
                *bin += 1;
            }
        }
    }
    let missing: Vec<&str> = bins
        .chroms()
        .iter()
        .zip(&seen)
        .filter(|(_, s)| !**s)
        .map(|(c, _)| c.name.as_str())
        .collect();
    if !missing.is_empty() {
        return Err(Error::format(
            path,
            format!(
                "no sequence for chromosome{} {} of the map (the FASTA must be the map's genome assembly)",
                if missing.len() > 1 { "s" } else { "" },
                missing.join(", ")
            ),
        ));
    }
    Ok(tallies
        .iter()
        .map(|t| {
            let mapped = t.bases - t.n;
            if mapped > 0 {
                t.gc as f64 / mapped as f64
            } else {
                f64::NAN
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::genome::Chrom;

    #[test]
    fn gc_by_bin_as_bioframe() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("g.fa");
        // chrA: 10 bp in lines of 4; chrB 6 bp; an extra record the map lacks
        std::fs::write(
            &path,
            ">chrX extra\nACGT\n>chrA desc\nGGCC\nATNN\nnc\n>chrB\nACGTAC\n",
        )
        .unwrap();
        let bins = BinTable::fixed(
            vec![
                Chrom {
                    name: "chrA".into(),
                    length_bp: 10,
                },
                Chrom {
                    name: "chrB".into(),
                    length_bp: 6,
                },
            ],
            4,
        )
        .unwrap();
        let gc = gc_content(&path, &bins).unwrap();
        // chrA bins: GGCC -> 1; ATNN -> 0/2; nc -> 1/1; chrB: ACGT -> 0.5; AC -> 0.5
        assert_eq!(gc[0], 1.0);
        assert_eq!(gc[1], 0.0);
        assert_eq!(gc[2], 1.0);
        assert_eq!(gc[3], 0.5);
        assert_eq!(gc[4], 0.5);
        std::fs::write(&path, ">chrA\nACGT\n").unwrap();
        let err = gc_content(&path, &bins).unwrap_err().to_string();
        assert!(err.contains("chrB") && err.contains("no sequence"), "{err}");
    }
}
