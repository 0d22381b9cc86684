//! The eigenvector outputs as `cooltools eigs-cis` / `eigs-trans` write them: the `.vecs.tsv`
//! table (the bins, the map's weight columns, then `E1..En`) and the `.lam.txt` eigenvalues.

use std::ops::Range;

use super::cis::RegionEigs;
use super::saddle::{Digitized, Saddle};
use crate::error::Result;
use crate::genome::BinTable;
use crate::genome::View;
use crate::io::tables::{write_real, write_u64};

/// The `.vecs.tsv` table of `regions` (bin range, its eigenvectors): `chrom start end`, the
/// `columns` (cooltools writes every weight column of the cooler, sorted by name), then
/// `E1..E{n_eigs}`, one line per bin. The text goes to `write` in pieces of about 1 MiB, so a
/// genome-wide table at high resolution is never whole in memory.
///
/// # Examples
///
/// ```
/// use contactmap::compartments::cis::RegionEigs;
/// use contactmap::compartments::tables::eigenvector_table;
/// use contactmap::genome::{BinTable, Chrom};
///
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 200)], 100)?;
/// let eigs = RegionEigs { values: vec![2.0], vectors: vec![vec![0.5, -0.5]], unconverged: 0 };
/// let weight = ("weight".to_string(), vec![1.0, f64::NAN]);
/// let mut text = Vec::new();
/// eigenvector_table(&bins, &[weight], &[(0..2, &eigs)], 1, |bytes| {
///     text.extend_from_slice(bytes);
///     Ok(())
/// })?;
/// assert_eq!(text, b"chrom\tstart\tend\tweight\tE1\nchr1\t0\t100\t1\t0.5\nchr1\t100\t200\tnan\t-0.5\n");
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn eigenvector_table(
    bins: &BinTable,
    columns: &[(String, Vec<f64>)],
    regions: &[(Range<usize>, &RegionEigs)],
    n_eigs: usize,
    mut write: impl FnMut(&[u8]) -> Result<()>,
) -> Result<()> {
    let mut first: Vec<&str> = vec!["chrom", "start", "end"];
    first.extend(columns.iter().map(|(name, _)| name.as_str()));
    let mut bytes = header_line(&first, "E", n_eigs).into_bytes();
    for (range, eigs) in regions {
        for bin in range.clone() {
            let b = bins.bin(bin);
            bytes.extend_from_slice(bins.chroms()[b.chrom_id].name.as_bytes());
            bytes.push(b'\t');
            write_u64(&mut bytes, b.start);
            bytes.push(b'\t');
            write_u64(&mut bytes, b.end);
            for (_, values) in columns {
                bytes.push(b'\t');
                write_real(&mut bytes, values[bin]);
            }
            for vector in &eigs.vectors {
                bytes.push(b'\t');
                write_real(&mut bytes, vector[bin - range.start]);
            }
            bytes.push(b'\n');
        }
        if bytes.len() > 1 << 20 {
            write(&bytes)?;
            bytes.clear();
        }
    }
    write(&bytes)
}

/// The `.cis.lam.txt` table: `chrom start end name eigval1..eigvalN`, one line per region of
/// `view`, whose eigenpairs `results` holds in view order.
pub fn cis_eigenvalue_table(
    bins: &BinTable,
    view: &View,
    results: &[RegionEigs],
    n_eigs: usize,
) -> String {
    let mut lam = header_line(&["chrom", "start", "end", "name"], "eigval", n_eigs);
    for (region, eigs) in view.regions().iter().zip(results) {
        let fields = [
            bins.chroms()[region.chrom_id].name.clone(),
            region.start_bp.to_string(),
            region.end_bp.to_string(),
            region.name.clone(),
        ];
        lam.push_str(&tab_line(&fields, &eigs.values));
    }
    lam
}

/// The `.trans.lam.txt` table: a header `eigval1..eigvalN` and one line of eigenvalues.
pub fn trans_eigenvalue_table(eigs: &RegionEigs, n_eigs: usize) -> String {
    header_line(&[], "eigval", n_eigs) + &tab_line(&[], &eigs.values)
}

fn header_line(first: &[&str], stem: &str, n: usize) -> String {
    let mut line: Vec<String> = first.iter().map(|s| s.to_string()).collect();
    line.extend((1..=n).map(|k| format!("{stem}{k}")));
    line.join("\t") + "\n"
}

/// `fields` then `values`, tab-separated, with a newline.
fn tab_line(fields: &[String], values: &[f64]) -> String {
    let mut bytes = fields.join("\t").into_bytes();
    for (k, &v) in values.iter().enumerate() {
        if k > 0 || !fields.is_empty() {
            bytes.push(b'\t');
        }
        write_real(&mut bytes, v);
    }
    bytes.push(b'\n');
    String::from_utf8(bytes).expect("utf-8 fields")
}

/// The saddle as `contactmap saddle` writes PREFIX.saddle.tsv: `i j sum count`, one line per
/// pair of classes (row-major, the outer classes included).
///
/// ```
/// use contactmap::compartments::saddle::Saddle;
/// use contactmap::compartments::tables::saddle_table;
/// let saddle = Saddle { n_classes: 1, sum: vec![2.5], count: vec![2.0] };
/// assert_eq!(saddle_table(&saddle), "i\tj\tsum\tcount\n0\t0\t2.5\t2\n");
/// ```
pub fn saddle_table(saddle: &Saddle) -> String {
    let n = saddle.n_classes;
    let mut table = String::from("i\tj\tsum\tcount\n");
    for a in 0..n {
        for b in 0..n {
            let k = a * n + b;
            table.push_str(&format!(
                "{a}\t{b}\t{}\t{}\n",
                saddle.sum[k], saddle.count[k]
            ));
        }
    }
    table
}

/// The class edges of a digitized track (PREFIX.edges.tsv): `edge`, one per line.
///
/// ```
/// use contactmap::compartments::saddle::Digitized;
/// use contactmap::compartments::tables::edges_table;
/// let digitized = Digitized { edges: vec![-0.5, 0.5], classes: vec![1, 2] };
/// assert_eq!(edges_table(&digitized), "edge\n-0.5\n0.5\n");
/// ```
pub fn edges_table(digitized: &Digitized) -> String {
    let mut edges = String::from("edge\n");
    for e in &digitized.edges {
        edges.push_str(&format!("{e}\n"));
    }
    edges
}

/// Each bin's class (PREFIX.digitized.tsv): `chrom start end {column}.d`, as cooltools names
/// the digitized track.
///
/// ```
/// use contactmap::compartments::saddle::Digitized;
/// use contactmap::compartments::tables::digitized_table;
/// use contactmap::genome::{BinTable, Chrom};
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 200)], 100)?;
/// let digitized = Digitized { edges: vec![0.0, 1.0], classes: vec![1, -1] };
/// assert_eq!(
///     digitized_table(&bins, "E1", &digitized),
///     "chrom\tstart\tend\tE1.d\nchr1\t0\t100\t1\nchr1\t100\t200\t-1\n"
/// );
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn digitized_table(bins: &BinTable, column: &str, digitized: &Digitized) -> String {
    let mut classes = format!("chrom\tstart\tend\t{column}.d\n");
    for (k, bin) in bins.iter().enumerate() {
        classes.push_str(&format!(
            "{}\t{}\t{}\t{}\n",
            bins.chroms()[bin.chrom_id].name,
            bin.start,
            bin.end,
            digitized.classes[k]
        ));
    }
    classes
}

/// The saddle strength at every extent `k >= 1` (PREFIX.strength.tsv): `k strength`.
///
/// ```
/// use contactmap::compartments::tables::strength_table;
/// assert_eq!(strength_table(&[0.0, 2.0, 1.5]), "k\tstrength\n1\t2\n2\t1.5\n");
/// ```
pub fn strength_table(strength: &[f64]) -> String {
    let mut text = String::from("k\tstrength\n");
    for (k, s) in strength.iter().enumerate().skip(1) {
        text.push_str(&format!("{k}\t{s}\n"));
    }
    text
}
