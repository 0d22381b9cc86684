//! Snippets cut out of the map and summed as they are cut, on every core.
//!
//! The snippets of a view region are sorted by their first row and gathered in runs of nearby
//! rows; each run's pixels (the upper triangle, its rows whole) are read once, kept in the
//! reader's own blocks, while the previous run is cut, in parallel, in fixed
//! chunks whose sums are added in order (the same result on any number of threads). Memory: one
//! run's pixels and one sum per group and core, never a stack of snippets.

use std::ops::Range;

use ndarray::Array2;
use rayon::prelude::*;

use super::rescale::{rescale_snippet, zoom_axis};
use crate::error::Result;
use crate::io::{MatrixReader, read_ahead_by};
use crate::matrix::PixelBlock;

/// Rows read together at most (unless one snippet is taller).
const RUN_ROWS: usize = 512;
/// Snippets whose rows are this close to a run's join it.
const RUN_GAP: usize = 64;
/// Snippets cut per parallel task.
const CHUNK: usize = 64;
/// Runs read ahead at once: two, so that one run's decoding keeps the cores busy while another
/// run's rows are checked (serial).
const READ_AHEAD_RUNS: usize = 2;

/// One snippet to cut: genome-wide bins, and where its values go.
#[derive(Clone, Debug, PartialEq)]
pub struct Snip {
    /// Rows (anchor 1).
    pub rows: Range<usize>,
    /// Columns (anchor 2).
    pub cols: Range<usize>,
    /// Index of the view region of the rows (for the expected).
    pub region: usize,
    /// Index of the view region of the columns (the rows' in cis).
    pub col_region: usize,
    /// The sums it adds to.
    pub slots: Vec<usize>,
    /// Flipped about the anti-diagonal (negative strand).
    pub flip: bool,
}

/// Per slot: the sum of the snippets' values (NaN left out), the number of finite values per
/// pixel, the number of snippets.
#[derive(Clone, Debug, PartialEq)]
pub struct Sums {
    /// Sum of the non-NaN values.
    pub sum: Array2<f64>,
    /// Finite values per pixel.
    pub num: Array2<u64>,
    /// Snippets added.
    pub n: usize,
    /// Summed coverage of the rows' bins (with a coverage to normalise by).
    pub cov_start: Vec<f64>,
    /// Summed coverage of the columns' bins.
    pub cov_end: Vec<f64>,
}

impl Sums {
    fn new(size: usize) -> Sums {
        Sums {
            sum: Array2::zeros((size, size)),
            num: Array2::zeros((size, size)),
            n: 0,
            cov_start: vec![0.0; size],
            cov_end: vec![0.0; size],
        }
    }

    fn add(&mut self, snippet: &Array2<f64>, coverage: Option<&(Vec<f64>, Vec<f64>)>) {
        if let Some((start, end)) = coverage {
            self.cov_start
                .iter_mut()
                .zip(start)
                .for_each(|(s, v)| *s += v);
            self.cov_end.iter_mut().zip(end).for_each(|(s, v)| *s += v);
        }
        for ((s, k), &v) in self.sum.iter_mut().zip(self.num.iter_mut()).zip(snippet) {
            if !v.is_nan() {
                *s += v;
                *k += v.is_finite() as u64;
            }
        }
        self.n += 1;
    }

    /// Add `other` to these sums.
    pub fn merge(&mut self, other: &Sums) {
        self.sum += &other.sum;
        self.num += &other.num;
        self.n += other.n;
        self.cov_start
            .iter_mut()
            .zip(&other.cov_start)
            .for_each(|(s, v)| *s += v);
        self.cov_end
            .iter_mut()
            .zip(&other.cov_end)
            .for_each(|(s, v)| *s += v);
    }
}

/// Reads the map and cuts snippets out of it.
pub struct Cutter<'a> {
    /// The map.
    pub reader: &'a dyn MatrixReader,
    /// How snippets are made.
    pub make: Make<'a>,
}

/// How snippets are made from the pixels read.
pub struct Make<'a> {
    /// Balancing weights (NaN for a masked bin), or raw counts.
    pub weights: Option<&'a [f64]>,
    /// Per view region, the expected of each diagonal (observed / expected); in trans, per
    /// two regions `[a][b]` (`a < b`), their expected; or none.
    pub expected: Option<&'a [Vec<f64>]>,
    /// Pixels with `j - i` below this are NaN.
    pub ignore_diags: usize,
    /// Rescaled to this size.
    pub rescale: Option<usize>,
    /// On the diagonal (symmetrised before rescaling).
    pub local: bool,
    /// Between chromosomes: no diagonal left out, one expected per two regions.
    pub trans: bool,
    /// The side of the pileup.
    pub size: usize,
    /// Per bin, the coverage to normalise by (coolpuppy's `coverage_norm`).
    pub coverage: Option<&'a [f64]>,
}

/// The stored pixels of some rows, row by row: the reader's blocks as they came (no copy), and
/// where in them each row lies.
struct Rows {
    first: usize,
    blocks: Vec<PixelBlock>,
    /// Per row from `first`: its block and its stretch of that block's pixels.
    spans: Vec<(usize, Range<usize>)>,
}

impl Rows {
    /// The whole rows `rows` (the reader hands out rows whole, sorted by column; weights are
    /// applied later, when cutting).
    fn read(reader: &dyn MatrixReader, rows: Range<usize>) -> Result<Rows> {
        let first = rows.start;
        let mut spans = vec![(0, 0..0); rows.len()];
        let mut blocks = Vec::new();
        reader.read_rows_owned(rows, &mut |block| {
            let mut k = 0;
            while k < block.len() {
                let i = block.bin1[k];
                let end = k + block.bin1[k..].partition_point(|&b| b == i);
                spans[i as usize - first] = (blocks.len(), k..end);
                k = end;
            }
            blocks.push(block);
            Ok(())
        })?;
        Ok(Rows {
            first,
            blocks,
            spans,
        })
    }

    /// The stored pixels of row `i` in `cols`: `(column, count)`.
    fn row(
        &self,
        i: usize,
        cols: &Range<usize>,
    ) -> impl Iterator<Item = (usize, f64)> + '_ + use<'_> {
        let (b, span) = &self.spans[i - self.first];
        let block = &self.blocks[*b];
        let (c, v) = (&block.bin2[span.clone()], &block.count[span.clone()]);
        let from = c.partition_point(|&j| (j as usize) < cols.start);
        let end = cols.end as u64;
        c[from..]
            .iter()
            .zip(&v[from..])
            .take_while(move |&(&j, _)| j < end)
            .map(|(&j, &v)| (j as usize, v))
    }
}

impl Make<'_> {
    /// The snippet of `snip`: masked, observed / expected, rescaled and flipped as asked. (In
    /// trans the rows' region comes first in the view, which is sorted, so its rows precede
    /// its columns in the stored upper triangle.)
    fn snippet(&self, rows: &Rows, snip: &Snip) -> Array2<f64> {
        let (r0, c0) = (snip.rows.start, snip.cols.start);
        let mut s = Array2::<f64>::zeros((snip.rows.len(), snip.cols.len()));
        for i in snip.rows.clone() {
            for (j, count) in rows.row(i, &snip.cols) {
                s[[i - r0, j - c0]] = match self.weights {
                    Some(w) => (w[i] * w[j]) * count,
                    None => count,
                };
            }
        }
        // the expected of pixel (i, j): of its diagonal in the region, or in trans one value
        // for the two regions
        let expected = |i: usize, j: usize| {
            self.expected.map(|e| {
                let (a, b) = (snip.region, snip.col_region);
                if self.trans {
                    e[a.min(b)][a.max(b)]
                } else {
                    e[a].get(j - i).copied().unwrap_or(f64::NAN)
                }
            })
        };
        for ((p, q), value) in s.indexed_iter_mut() {
            let (i, j) = (r0 + p, c0 + q);
            let masked = self.weights.is_some_and(|w| w[i].is_nan() || w[j].is_nan());
            if masked || (!self.trans && (j as i64 - i as i64) < self.ignore_diags as i64) {
                *value = f64::NAN;
            } else if let Some(e) = expected(i, j) {
                *value /= e;
            }
        }
        if let Some(size) = self.rescale {
            s = rescale_snippet(&s, size, self.local);
        }
        if snip.flip {
            let (h, w) = s.dim();
            s = Array2::from_shape_fn((w, h), |(i, j)| s[[h - 1 - j, w - 1 - i]]);
        }
        s
    }

    fn cut_run(&self, rows: &Rows, snips: &[Snip], n_slots: usize) -> Result<Vec<Sums>> {
        let parts: Vec<Vec<Sums>> = snips
            .par_chunks(CHUNK)
            .map(|chunk| {
                let mut sums = vec![Sums::new(self.size); n_slots];
                for snip in chunk {
                    let s = self.snippet(rows, snip);
                    let coverage = self.coverage.map(|c| {
                        let cut = |bins: &Range<usize>| match self.rescale {
                            Some(size) => zoom_axis(&c[bins.clone()], size),
                            None => c[bins.clone()].to_vec(),
                        };
                        (cut(&snip.rows), cut(&snip.cols))
                    });
                    for &slot in &snip.slots {
                        sums[slot].add(&s, coverage.as_ref());
                    }
                }
                sums
            })
            .collect();
        let mut total = vec![Sums::new(self.size); n_slots];
        for part in &parts {
            for (t, p) in total.iter_mut().zip(part) {
                t.merge(p);
            }
        }
        Ok(total)
    }
}

impl Cutter<'_> {
    /// The sums of `snips` (all in one view region) into `n_slots` slots.
    pub fn sum(&self, mut snips: Vec<Snip>, n_slots: usize) -> Result<Vec<Sums>> {
        snips.sort_by_key(|s| s.rows.start);
        let runs = runs(&snips);
        let mut total = vec![Sums::new(self.make.size); n_slots];
        // each run is cut while the next ones are read
        read_ahead_by(
            &runs,
            READ_AHEAD_RUNS,
            |run| self.read_run(&snips[(*run).clone()]),
            |run, rows| {
                let parts = self.make.cut_run(&rows, &snips[run.clone()], n_slots)?;
                for (t, p) in total.iter_mut().zip(&parts) {
                    t.merge(p);
                }
                for block in rows.blocks {
                    self.reader.recycle(block);
                }
                Ok(())
            },
        )?;
        Ok(total)
    }

    fn read_run(&self, snips: &[Snip]) -> Result<Rows> {
        let rows = snips.iter().map(|s| s.rows.start).min().unwrap_or(0)
            ..snips.iter().map(|s| s.rows.end).max().unwrap_or(0);
        Rows::read(self.reader, rows)
    }
}

/// Runs of snippets (sorted by first row) to read together: rows within `RUN_GAP` of the run,
/// the run at most `RUN_ROWS` tall.
fn runs(snips: &[Snip]) -> Vec<Range<usize>> {
    let mut out = Vec::new();
    let mut k = 0;
    while k < snips.len() {
        let (start, mut end) = (snips[k].rows.start, snips[k].rows.end);
        let mut m = k + 1;
        while m < snips.len()
            && snips[m].rows.start <= end + RUN_GAP
            && snips[m].rows.end.max(end) - start <= RUN_ROWS
        {
            end = end.max(snips[m].rows.end);
            m += 1;
        }
        out.push(k..m);
        k = m;
    }
    out
}
