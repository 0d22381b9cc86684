//! cooltools' expected tables as text: the cis table (`cooltools expected-cis`), the trans
//! table (`expected-trans`) and the log-binned P(s), written as cooltools writes them and read
//! back (for P(s) plots, observed / expected against a given expected).
//!
//! The records are this module's ([`CisExpected`], [`TransExpected`], [`LogBinned`]); the text
//! layer (header-addressed columns, number formatting) is [`crate::io::tables`], which stands below
//! the algorithms and does not know them.

use std::collections::HashMap;
use std::ops::Range;

use super::logbin::LogBinned;
use super::result::{CisExpected, TransExpected};
use crate::error::{Error, Result};
use crate::genome::BinTable;
use crate::io::tables::{Table, region_table, write_real, write_u64};
use crate::normalize::DiagonalCurve;

impl CisExpected {
    /// A cooltools `expected-cis` table (as `cooltools expected-cis` or `contactmap expected`
    /// write it, read by [`Table::read`]), for the P(s) analyses. The smoothed columns are not read; the
    /// averages are the table's own. Errors name the file and line: a trans table, regions
    /// whose rows are apart, missing or out-of-order diagonals, `dist_bp` that is not `dist`
    /// times one bin size.
    ///
    /// # Examples
    ///
    /// ```
    /// use contactmap::expected::CisExpected;
    /// use contactmap::io::tables::Table;
    ///
    /// let path = std::env::temp_dir().join(format!("cis-{}.tsv", std::process::id()));
    /// std::fs::write(
    ///     &path,
    ///     "region1\tregion2\tdist\tdist_bp\tn_total\tn_valid\tcount.sum\tcount.avg\n\
    ///      chr1\tchr1\t0\t0\t4\t4\t40\t10\nchr1\tchr1\t1\t1000\t3\t3\t12\t4\n",
    /// )?;
    /// let table = CisExpected::from_table(&Table::read(path.to_str().unwrap())?)?;
    /// assert_eq!((table.resolution, table.average()), (1000, &[10.0, 4.0][..]));
    /// assert_eq!(table.median_region_length_bp(), 2000.0);
    /// assert_eq!(String::from_utf8(table.to_tsv())?.lines().count(), 3);
    /// # std::fs::remove_file(&path)?;
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn from_table(table: &Table) -> Result<CisExpected> {
        let path = table.path();
        let (c1, c2) = (table.column("region1")?, table.column("region2")?);
        let dist_column = table.column("dist")?;
        let dist_bp_column = table.column("dist_bp")?;
        let (n_total_column, n_valid_column) = (table.column("n_total")?, table.column("n_valid")?);
        let count_sum_column = table.column("count.sum")?;
        let balanced_sum_column = table.column("balanced.sum").ok();
        let count_avg_column = table.column("count.avg")?;
        let balanced_avg_column = match balanced_sum_column {
            Some(_) => Some(table.column("balanced.avg")?),
            None => None,
        };
        if table.is_empty() {
            return Err(Error::format(path, "the expected table has no rows"));
        }
        let bad_row = |row: usize, message: String| Error::parse(path, row as u64 + 2, message);
        let whole = |row: usize, column: usize| -> Result<u64> {
            let value = table.number(row, column)?;
            if value >= 0.0 && value.fract() == 0.0 && value < 2f64.powi(53) {
                Ok(value as u64)
            } else {
                Err(bad_row(
                    row,
                    format!(
                        "'{}' in column '{}' is not a non-negative integer",
                        table.text(row, column),
                        table.header()[column]
                    ),
                ))
            }
        };
        let mut out = CisExpected {
            resolution: 0,
            region_names: Vec::new(),
            region: Vec::with_capacity(table.len()),
            dist: Vec::with_capacity(table.len()),
            dist_bp: Vec::with_capacity(table.len()),
            n_total: Vec::with_capacity(table.len()),
            n_valid: Vec::with_capacity(table.len()),
            count_sum: Vec::with_capacity(table.len()),
            balanced_sum: balanced_sum_column.map(|_| Vec::with_capacity(table.len())),
            count_avg: Vec::with_capacity(table.len()),
            balanced_avg: balanced_avg_column.map(|_| Vec::with_capacity(table.len())),
            avg_smoothed: None,
            avg_smoothed_agg: None,
        };
        let mut rows_per_region: Vec<u64> = Vec::new();
        for row in 0..table.len() {
            let (r1, r2) = (table.text(row, c1), table.text(row, c2));
            if r1 != r2 {
                return Err(bad_row(
                    row,
                    format!(
                        "region1 '{r1}' differs from region2 '{r2}': a trans table, not the cis expected (contactmap expected, cooltools expected-cis)"
                    ),
                ));
            }
            if out.region_names.last().map(String::as_str) != Some(r1) {
                if out.region_names.iter().any(|name| name == r1) {
                    return Err(bad_row(
                        row,
                        format!("the rows of region '{r1}' are not together"),
                    ));
                }
                out.region_names.push(r1.to_string());
                rows_per_region.push(0);
            }
            let region = out.region_names.len() - 1;
            rows_per_region[region] += 1;
            let (dist, dist_bp) = (whole(row, dist_column)?, whole(row, dist_bp_column)?);
            let expected_dist = rows_per_region[region] - 1;
            if dist != expected_dist {
                return Err(bad_row(
                    row,
                    format!(
                        "dist {dist} where {expected_dist} was expected (one row per diagonal of each region, in order)"
                    ),
                ));
            }
            if let Some(size) = dist_bp.checked_div(dist) {
                if out.resolution == 0 {
                    out.resolution = size;
                }
                if dist.checked_mul(out.resolution) != Some(dist_bp) || out.resolution == 0 {
                    return Err(bad_row(
                        row,
                        format!(
                            "dist_bp {dist_bp} is not dist {dist} times the bin size {} of the rows above",
                            out.resolution
                        ),
                    ));
                }
            }
            out.region.push(region as u32);
            out.dist.push(dist);
            out.dist_bp.push(dist_bp);
            out.n_total.push(whole(row, n_total_column)?);
            out.n_valid.push(whole(row, n_valid_column)?);
            out.count_sum.push(table.number(row, count_sum_column)?);
            out.count_avg.push(table.number(row, count_avg_column)?);
            if let (Some(sums), Some(column)) = (out.balanced_sum.as_mut(), balanced_sum_column) {
                sums.push(table.number(row, column)?);
            }
            if let (Some(avgs), Some(column)) = (out.balanced_avg.as_mut(), balanced_avg_column) {
                avgs.push(table.number(row, column)?);
            }
        }
        if out.resolution == 0 {
            return Err(Error::format(
                path,
                "every region has a single diagonal: no distances to plot",
            ));
        }
        Ok(out)
    }

    /// The median length of the regions in bp: each region has one row per diagonal, so its
    /// length is its number of rows times the bin size (the default fit range of P(s) ends at a
    /// quarter of it).
    pub fn median_region_length_bp(&self) -> f64 {
        let mut lengths = vec![0u64; self.region_names.len()];
        for &region in &self.region {
            lengths[region as usize] += self.resolution;
        }
        lengths.sort_unstable();
        let n = lengths.len();
        match n {
            0 => f64::NAN,
            _ if n % 2 == 1 => lengths[n / 2] as f64,
            _ => (lengths[n / 2 - 1] + lengths[n / 2]) as f64 / 2.0,
        }
    }

    /// The table as `cooltools expected-cis` writes it (tab-separated, header line).
    pub fn to_tsv(&self) -> Vec<u8> {
        region_table(
            self.n_rows(),
            &self.columns(),
            |row| self.region_name(row).to_string(),
            |row| self.region_name(row).to_string(),
        )
    }
}

impl TransExpected {
    /// The table as `cooltools expected-trans` writes it (tab-separated, header line).
    pub fn to_tsv(&self) -> Vec<u8> {
        region_table(
            self.n_rows(),
            &self.columns(),
            |row| self.region1[row].clone(),
            |row| self.region2[row].clone(),
        )
    }
}

impl LogBinned {
    /// The combined log-binned P(s) with its local slopes, one line per log bin:
    /// `dist_bin_id X.avg n_valid dist.avg dist_bin_start dist_bin_end low_err high_err
    /// dist_bp.avg slope slope.low_err slope.high_err slope.dist.avg slope.n_valid` (`X` is
    /// `balanced` or `count`; `nan` slopes on the last bin).
    pub fn to_tsv(&self) -> Vec<u8> {
        let mut text = Vec::new();
        let header = [
            "dist_bin_id".to_string(),
            format!("{}.avg", self.prefix),
            "n_valid".into(),
            "dist.avg".into(),
            "dist_bin_start".into(),
            "dist_bin_end".into(),
            "low_err".into(),
            "high_err".into(),
            "dist_bp.avg".into(),
            "slope".into(),
            "slope.low_err".into(),
            "slope.high_err".into(),
            "slope.dist.avg".into(),
            "slope.n_valid".into(),
        ];
        text.extend_from_slice(header.join("\t").as_bytes());
        text.push(b'\n');
        for bin in &self.combined {
            write_u64(&mut text, bin.dist_bin_id as u64);
            text.push(b'\t');
            write_real(&mut text, bin.average);
            text.push(b'\t');
            write_u64(&mut text, bin.n_valid);
            text.push(b'\t');
            write_real(&mut text, bin.dist_avg);
            text.push(b'\t');
            write_u64(&mut text, bin.dist_bin_start);
            text.push(b'\t');
            write_u64(&mut text, bin.dist_bin_end);
            for value in [
                bin.low_err,
                bin.high_err,
                bin.dist_avg * self.resolution as f64,
            ] {
                text.push(b'\t');
                write_real(&mut text, value);
            }
            match self
                .slopes
                .iter()
                .find(|s| s.dist_bin_id == bin.dist_bin_id)
            {
                Some(slope) => {
                    for value in [slope.slope, slope.low_err, slope.high_err, slope.dist_avg] {
                        text.push(b'\t');
                        write_real(&mut text, value);
                    }
                    text.push(b'\t');
                    write_u64(&mut text, slope.n_valid);
                }
                None => text.extend_from_slice(b"\tnan\tnan\tnan\tnan\tnan"),
            }
            text.push(b'\n');
        }
        text
    }
}

/// Per-chromosome expected curves (for observed / expected) from column `column` of the
/// cooltools expected-cis table `table`, whose regions must be whole chromosomes of `bins`
/// (`balanced.avg` is the usual column, `count.avg` for raw counts).
///
/// # Examples
///
/// ```
/// use contactmap::expected::table::curves;
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::tables::Table;
///
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 300)], 100)?;
/// let path = std::env::temp_dir().join(format!("curves-{}.tsv", std::process::id()));
/// std::fs::write(
///     &path,
///     "region1\tregion2\tdist\tn_valid\tbalanced.avg\nchr1\tchr1\t0\t3\t0.5\nchr1\tchr1\t1\t2\t0.25\n",
/// )?;
/// let curves = curves(&Table::read(path.to_str().unwrap())?, &bins, "balanced.avg")?;
/// assert_eq!(curves[0].expected[1], 0.25);
/// assert!(curves[0].expected[2].is_nan()); // a diagonal the table does not give
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn curves(table: &Table, bins: &BinTable, column: &str) -> Result<Vec<DiagonalCurve>> {
    let (c1, c2) = (table.column("region1")?, table.column("region2")?);
    let (dist, n_valid, value) = (
        table.column("dist")?,
        table.column("n_valid")?,
        table.column(column)?,
    );
    let mut curves: HashMap<usize, DiagonalCurve> = HashMap::new();
    for row in 0..table.len() {
        let (r1, r2) = (table.text(row, c1), table.text(row, c2));
        if r1 != r2 {
            continue;
        }
        let chrom = bins.chrom_id(r1).ok_or_else(|| {
            Error::format(
                table.path(),
                format!("region '{r1}' is not a chromosome of the matrix (regions must be whole chromosomes)"),
            )
        })?;
        let range: Range<usize> = bins.chrom_bins(chrom);
        let curve = curves.entry(chrom).or_insert_with(|| DiagonalCurve {
            expected: vec![f64::NAN; range.len()],
            n_valid: vec![0.0; range.len()],
            bins: range.clone(),
        });
        let d = table.number(row, dist)?;
        if !(d >= 0.0 && d.fract() == 0.0 && (d as usize) < range.len()) {
            return Err(Error::format(
                table.path(),
                format!(
                    "row {}: dist {d} is not a diagonal of {r1} ({} bins)",
                    row + 1,
                    range.len()
                ),
            ));
        }
        curve.expected[d as usize] = table.number(row, value)?;
        curve.n_valid[d as usize] = table.number(row, n_valid)?;
    }
    let mut curves: Vec<DiagonalCurve> = curves.into_values().collect();
    curves.sort_by_key(|c| c.bins.start);
    Ok(curves)
}

/// Column `column` of a cooltools cis expected table (`expected-cis` / `contactmap expected`)
/// for each region of `view`, by diagonal: `values[r][d]` (NaN where the table has no row).
/// Errors name the file and what does not fit: a region of the view missing from the table, a
/// `dist` beyond its region (the table was made on another view), a `dist_bp` that is not
/// `dist` times the bin size of `bins` (another resolution).
///
/// ```
/// use contactmap::expected::table::region_column;
/// use contactmap::io::tables::Table;
/// use contactmap::genome::View;
/// use contactmap::io::{open_matrix, OpenOptions};
/// let reader = open_matrix("data/cooler_test_file.mcool::/resolutions/100000", &OpenOptions::default())?;
/// let view = View::chromosomes(reader.bins());
/// let table = Table::read("data/reference/numerics/dm6_100kb.expected_cis.raw.tsv.gz")?;
/// let values = region_column(&table, reader.bins(), &view, "count.avg")?;
/// assert_eq!(values.len(), view.regions().len());
/// assert!(values[0][0].is_nan() && values[0][2] > values[0][10]);
/// let other = open_matrix("data/cooler_test_file.mcool::/resolutions/1000000", &OpenOptions::default())?;
/// assert!(region_column(&table, other.bins(), &View::chromosomes(other.bins()), "count.avg").is_err());
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn region_column(
    table: &Table,
    bins: &BinTable,
    view: &crate::genome::View,
    column: &str,
) -> Result<Vec<Vec<f64>>> {
    let (c1, c2, dist) = (
        table.column("region1")?,
        table.column("region2")?,
        table.column("dist")?,
    );
    let value = table.column(column)?;
    let dist_bp = table.column("dist_bp").ok();
    let resolution = bins.resolution();
    let regions = view.regions();
    let mut values: Vec<Vec<f64>> = regions.iter().map(|r| vec![f64::NAN; r.n_bins()]).collect();
    let mut seen = vec![false; regions.len()];
    for row in 0..table.len() {
        let (r1, r2) = (table.text(row, c1), table.text(row, c2));
        if r1 != r2 {
            continue;
        }
        let Some(r) = regions.iter().position(|region| region.name == r1) else {
            continue;
        };
        seen[r] = true;
        let d = table.number(row, dist)?;
        let n = regions[r].n_bins();
        if !(d >= 0.0 && d.fract() == 0.0 && (d as usize) < n) {
            return Err(Error::format(
                table.path(),
                format!(
                    "row {}: dist {d} is not a diagonal of region {r1} ({n} bins in this view): \
                     the expected was computed on another view or resolution",
                    row + 2
                ),
            ));
        }
        if let (Some(c), Some(size)) = (dist_bp, resolution) {
            let bp = table.number(row, c)?;
            if bp != d * size as f64 {
                return Err(Error::format(
                    table.path(),
                    format!(
                        "row {}: dist_bp {bp} is not dist {d} x {size} bp: the expected is for \
                         another resolution",
                        row + 2
                    ),
                ));
            }
        }
        values[r][d as usize] = table.number(row, value)?;
    }
    if let Some(r) = seen.iter().position(|s| !s) {
        return Err(Error::format(
            table.path(),
            format!(
                "no rows for region '{}' of the view: the expected must cover every region \
                 (compute it with `contactmap expected` on the same view)",
                regions[r].name
            ),
        ));
    }
    Ok(values)
}

/// Column `column` of a cooltools trans expected table (`expected-trans` / `contactmap expected
/// --trans`) for every two regions of `view`, as a matrix `[a][b]` with `a < b` (view order;
/// NaN where the table has no row), as [`TransExpected::average_by_pair`] gives it.
///
/// [`TransExpected::average_by_pair`]: super::TransExpected::average_by_pair
///
/// ```
/// use contactmap::expected::{expected_trans, table::pair_column};
/// use contactmap::io::tables::Table;
/// use contactmap::genome::View;
/// use contactmap::io::{open_matrix, LoadedPixels, OpenOptions, StreamedPixels};
/// let reader = open_matrix("data/yeast.10kb.cool", &OpenOptions::default())?;
/// let view = View::chromosomes(reader.bins());
/// let pixels = LoadedPixels::Streamed(StreamedPixels::new(reader.as_ref()));
/// let table = expected_trans(&pixels, None, &view)?;
/// let path = std::env::temp_dir().join(format!("trans-{}.tsv", std::process::id()));
/// let mut text = String::from("region1\tregion2\tcount.avg\n");
/// for ((r1, r2), v) in table.region1.iter().zip(&table.region2).zip(&table.count_avg) {
///     text.push_str(&format!("{r1}\t{r2}\t{v}\n"));
/// }
/// std::fs::write(&path, text)?;
/// let values = pair_column(&Table::read(path.to_str().unwrap())?, &view, "count.avg")?;
/// // the same matrix (NaN below the diagonal, so compared as text)
/// assert_eq!(format!("{values:?}"), format!("{:?}", table.average_by_pair(&view)));
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn pair_column(
    table: &Table,
    view: &crate::genome::View,
    column: &str,
) -> Result<Vec<Vec<f64>>> {
    let (c1, c2) = (table.column("region1")?, table.column("region2")?);
    let value = table.column(column)?;
    let regions = view.regions();
    let index = |name: &str| regions.iter().position(|r| r.name == name);
    let mut values = vec![vec![f64::NAN; regions.len()]; regions.len()];
    for row in 0..table.len() {
        let (r1, r2) = (table.text(row, c1), table.text(row, c2));
        if let (Some(a), Some(b)) = (index(r1), index(r2)) {
            if a != b {
                values[a.min(b)][a.max(b)] = table.number(row, value)?;
            }
        }
    }
    Ok(values)
}
