//! The levels of an .mcool against each other: each coarser level the sum of the finer one.

use super::check::CheckedCooler;
use super::columns::PixelColumns;
use crate::error::Result;
use crate::io::cool::BLOCK_PIXELS;
use crate::validate::report::{Class, Collector};
use crate::validate::tolerance::FLOAT_TOLERANCE;
use std::fs::File;

pub(crate) struct PixelSummary {
    pub(crate) sum: f64,
    pub(crate) clean: bool,
}

/// Streams the pixels of a cooler in order, a block at a time.
pub(crate) struct PixelCursor<'a> {
    columns: &'a PixelColumns,
    raw: &'a File,
    next_block: usize,
    block: (Vec<i64>, Vec<i64>, Vec<f64>),
    position: usize,
}

impl<'a> PixelCursor<'a> {
    pub(crate) fn new(columns: &'a PixelColumns, raw: &'a File) -> Self {
        PixelCursor {
            columns,
            raw,
            next_block: 0,
            block: Default::default(),
            position: 0,
        }
    }

    pub(crate) fn peek(&mut self) -> Result<Option<(i64, i64, f64)>> {
        if self.position == self.block.0.len() {
            let n = self.columns.len();
            if self.next_block >= n {
                return Ok(None);
            }
            let hi = (self.next_block + BLOCK_PIXELS).min(n);
            self.block = self.columns.read(self.raw, self.next_block, hi)?;
            self.next_block = hi;
            self.position = 0;
        }
        let k = self.position;
        Ok(Some((self.block.0[k], self.block.1[k], self.block.2[k])))
    }

    pub(crate) fn advance(&mut self) {
        self.position += 1;
    }
}

/// The state of one coarse level during the coarsening comparison.
pub(crate) struct LevelComparison<'a> {
    name: &'a str,
    /// Coarse bin of every base bin.
    coarse_of: Vec<u64>,
    row: Option<u64>,
    entries: Vec<(u64, f64)>,
    stored: PixelCursor<'a>,
}

impl LevelComparison<'_> {
    pub(crate) fn push(&mut self, i: u64, j: u64, c: f64, out: &mut Collector) -> Result<()> {
        let (ci, cj) = (self.coarse_of[i as usize], self.coarse_of[j as usize]);
        if self.row != Some(ci) {
            self.flush(out)?;
            self.row = Some(ci);
        }
        self.entries.push((cj, c));
        Ok(())
    }

    /// Compare the accumulated coarse row with the stored pixels of that row (and report stored
    /// rows before it, which the base does not have).
    pub(crate) fn flush(&mut self, out: &mut Collector) -> Result<()> {
        let Some(row) = self.row.take() else {
            return Ok(());
        };
        self.entries.sort_unstable_by_key(|&(j, _)| j);
        let mut expected: Vec<(u64, f64)> = Vec::with_capacity(self.entries.len());
        for &(j, c) in &self.entries {
            match expected.last_mut() {
                Some(last) if last.0 == j => last.1 += c,
                _ => expected.push((j, c)),
            }
        }
        self.entries.clear();
        self.drain_before(row as i64, out)?;
        let mut next = expected.iter().peekable();
        loop {
            let stored = match self.stored.peek()? {
                Some((i, j, c)) if i == row as i64 => Some((j as u64, c)),
                _ => None,
            };
            let computed = next.peek().copied().copied();
            let (j, stored_count, computed_count) = match (stored, computed) {
                (None, None) => break,
                (Some((sj, sc)), Some((cj, cc))) if sj == cj => {
                    self.stored.advance();
                    next.next();
                    (sj, sc, cc)
                }
                (Some((sj, sc)), Some((cj, _))) if sj < cj => {
                    self.stored.advance();
                    (sj, sc, 0.0)
                }
                (Some((sj, sc)), None) => {
                    self.stored.advance();
                    (sj, sc, 0.0)
                }
                (_, Some((cj, cc))) => {
                    next.next();
                    (cj, 0.0, cc)
                }
            };
            self.compare(row, j, stored_count, computed_count, out);
        }
        Ok(())
    }

    pub(crate) fn compare(&self, i: u64, j: u64, stored: f64, computed: f64, out: &mut Collector) {
        if (stored - computed).abs() > FLOAT_TOLERANCE * stored.abs().max(computed.abs()) {
            out.add(self.name, Class::Coarsening, || {
                (
                    format!("pixel ({i}, {j})"),
                    format!("stored count {stored}; the base resolution's pixels sum to {computed} in this coarse pixel"),
                )
            });
        }
    }

    /// Stored pixels in rows before `row` (all rows when `row` is `i64::MAX`) have no base pixel.
    pub(crate) fn drain_before(&mut self, row: i64, out: &mut Collector) -> Result<()> {
        while let Some((i, j, c)) = self.stored.peek()? {
            if i >= row {
                break;
            }
            self.stored.advance();
            self.compare(i as u64, j as u64, c, 0.0, out);
        }
        Ok(())
    }
}

/// Every coarser level equals the base (finest) level summed into its bins.
pub(crate) fn check_coarsening(
    raw: &File,
    coolers: &[CheckedCooler],
    out: &mut Collector,
) -> Result<()> {
    let Some(base) = coolers.first() else {
        return Ok(());
    };
    let (Some(base_bins), Some(base_pixels), true, Some(base_resolution)) = (
        &base.bins,
        &base.pixels,
        base.pixels_clean,
        base.resolution.filter(|&r| r > 0),
    ) else {
        out.notes.push(format!(
            "coarsening not checked: the base resolution {} has defects (listed above) or no fixed bin size",
            base.name
        ));
        return Ok(());
    };
    let mut levels = Vec::new();
    for level in &coolers[1..] {
        let Some(resolution) = level.resolution else {
            out.notes.push(format!(
                "{}: no resolution known (no bin-size): coarsening not checked",
                level.name
            ));
            continue;
        };
        if resolution % base_resolution != 0 {
            out.add(&level.name, Class::Coarsening, || {
                (
                    "bins".into(),
                    format!("resolution {resolution} is not a multiple of the base resolution {base_resolution}"),
                )
            });
            continue;
        }
        let Ok(expected_bins) = base_bins.coarsen(resolution / base_resolution) else {
            continue;
        };
        let (Some(bins), Some(pixels), true) = (&level.bins, &level.pixels, level.pixels_clean)
        else {
            out.notes.push(format!(
                "{}: coarsening not checked (the level's own defects are listed above)",
                level.name
            ));
            continue;
        };
        let same_bins = bins.n_bins() == expected_bins.n_bins()
            && bins.chroms() == expected_bins.chroms()
            && bins.iter().zip(expected_bins.iter()).all(|(a, b)| a == b);
        if !same_bins {
            out.add(&level.name, Class::Coarsening, || {
                (
                    "bins".into(),
                    format!(
                        "the bin table ({} bins) is not the base resolution's bins coarsened to {resolution} bp ({} bins)",
                        bins.n_bins(),
                        expected_bins.n_bins()
                    ),
                )
            });
            continue;
        }
        let coarse_of = base_bins
            .iter()
            .map(|b| expected_bins.bin_at(b.chrom_id, b.start) as u64)
            .collect();
        levels.push(LevelComparison {
            name: &level.name,
            coarse_of,
            row: None,
            entries: Vec::new(),
            stored: PixelCursor::new(pixels, raw),
        });
    }
    if levels.is_empty() {
        return Ok(());
    }
    let mut cursor = PixelCursor::new(base_pixels, raw);
    while let Some((i, j, c)) = cursor.peek()? {
        cursor.advance();
        let (i, j) = (i as u64, j as u64);
        for level in &mut levels {
            level.push(i, j, c, out)?;
        }
    }
    for level in &mut levels {
        level.flush(out)?;
        level.drain_before(i64::MAX, out)?;
    }
    Ok(())
}
