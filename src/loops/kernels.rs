//! The four HiCCUPS kernels as cooltools builds them (`cooltools.lib.numutils.get_kernel`), their
//! footprints as `scipy.ndimage.convolve` applies them, and cooltools' choice of `(w, p)` by bin
//! size.

use crate::error::{Error, Result};

/// The kinds of local neighbourhood a pixel is compared with, in cooltools' order (the order of
/// the output columns).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KernelType {
    /// The square of half-width `w` around the pixel less the inner square of half-width `p` and
    /// the pixel's row and column.
    Donut,
    /// Three columns through the pixel, above and below the inner square.
    Vertical,
    /// Three rows through the pixel, left and right of the inner square.
    Horizontal,
    /// The quarter toward the diagonal (rows below, columns left) less the inner square.
    Lowleft,
}

impl KernelType {
    /// The four kernels, in cooltools' order.
    pub const ALL: [KernelType; 4] = [
        KernelType::Donut,
        KernelType::Vertical,
        KernelType::Horizontal,
        KernelType::Lowleft,
    ];

    /// cooltools' name (`la_exp.{name}.value`).
    pub fn name(self) -> &'static str {
        match self {
            KernelType::Donut => "donut",
            KernelType::Vertical => "vertical",
            KernelType::Horizontal => "horizontal",
            KernelType::Lowleft => "lowleft",
        }
    }
}

/// cooltools' `recommend_kernels`: `(w, p)` = (7, 4) for bins of 4-8 kb, (5, 2) for 8-18 kb and
/// (3, 1) for 18-28 kb; other bin sizes have none (give `w` and `p`).
///
/// ```
/// use contactmap::loops::kernels::recommended_w_p;
/// assert_eq!(recommended_w_p(5_000), Some((7, 4)));
/// assert_eq!(recommended_w_p(10_000), Some((5, 2)));
/// assert_eq!(recommended_w_p(25_000), Some((3, 1)));
/// assert_eq!(recommended_w_p(100_000), None);
/// ```
pub fn recommended_w_p(resolution: u64) -> Option<(usize, usize)> {
    match resolution {
        0..=3_999 => None,
        4_000..=7_999 => Some((7, 4)),
        8_000..=17_999 => Some((5, 2)),
        18_000..=28_000 => Some((3, 1)),
        _ => None,
    }
}

/// One kernel: its footprint as offsets from the scored pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct Kernel {
    /// Which kernel.
    pub kind: KernelType,
    /// Outer half-width.
    pub w: usize,
    /// Inner half-width.
    pub p: usize,
    /// `(dy, dx)` of every cell the kernel sums for pixel `(i, j)`: cell `(i + dy, j + dx)`. This
    /// is `get_kernel(w, p, kind)` reflected through its centre, as `scipy.ndimage.convolve`
    /// applies a kernel (it matters for the lower-left kernel only).
    pub cells: Vec<(i32, i32)>,
    /// The same cells as rectangles `(dy0, dy1, dx0, dx1)`, bounds included.
    pub rects: Vec<(i32, i32, i32, i32)>,
}

impl Kernel {
    /// The kernel `kind` with half-widths `w > p >= 0`, as `get_kernel(w, p, kind)`.
    ///
    /// ```
    /// use contactmap::loops::kernels::{Kernel, KernelType};
    /// let donut = Kernel::new(KernelType::Donut, 3, 1)?;
    /// // 7 x 7, less the 3 x 3 centre and the rest of the centre row and column
    /// assert_eq!(donut.cells.len(), 49 - 9 - 4 * 2);
    /// let lowleft = Kernel::new(KernelType::Lowleft, 3, 1)?;
    /// assert!(lowleft.cells.iter().all(|&(dy, dx)| dy > 0 && dx < 0));
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn new(kind: KernelType, w: usize, p: usize) -> Result<Kernel> {
        if w == 0 || p >= w || w > 64 {
            return Err(Error::parameter(
                "w",
                w,
                format!("the outer half-width must exceed p ({p}) and be at most 64"),
            ));
        }
        let (wi, pi) = (w as i32, p as i32);
        // get_kernel's mask in its own coordinates: y (rows) and x (columns) from -w to w.
        let zero = |y: i32, x: i32| -> bool {
            let inner = (-pi..=pi).contains(&x) && (-pi..=pi).contains(&y);
            match kind {
                KernelType::Donut => inner || x == 0 || y == 0,
                KernelType::Vertical => !(-1..=1).contains(&x) || inner,
                KernelType::Horizontal => !(-1..=1).contains(&y) || inner,
                // the upright mask reflected through the centre ([::-1, ::-1])
                KernelType::Lowleft => {
                    let (y, x) = (-y, -x);
                    (x >= -pi && y <= pi) || x >= 0 || y <= 0
                }
            }
        };
        // scipy's convolve reflects the kernel: array cell (y, x) weighs input (i - y, j - x).
        let mut cells = Vec::new();
        for dy in -wi..=wi {
            for dx in -wi..=wi {
                if !zero(-dy, -dx) {
                    cells.push((dy, dx));
                }
            }
        }
        let rects = rectangles(&cells);
        Ok(Kernel {
            kind,
            w,
            p,
            cells,
            rects,
        })
    }

    /// The four kernels with half-widths `(w, p)`, in cooltools' order.
    pub fn hiccups(w: usize, p: usize) -> Result<Vec<Kernel>> {
        KernelType::ALL
            .iter()
            .map(|&kind| Kernel::new(kind, w, p))
            .collect()
    }
}

/// `cells` (sorted by `dy` then `dx`) as rectangles: each row's runs of consecutive `dx`, rows
/// with the same runs merged when they follow one another.
fn rectangles(cells: &[(i32, i32)]) -> Vec<(i32, i32, i32, i32)> {
    let mut rows: Vec<(i32, Vec<(i32, i32)>)> = Vec::new();
    for &(dy, dx) in cells {
        match rows.last_mut() {
            Some((y, runs)) if *y == dy => match runs.last_mut() {
                Some(run) if run.1 + 1 == dx => run.1 = dx,
                _ => runs.push((dx, dx)),
            },
            _ => rows.push((dy, vec![(dx, dx)])),
        }
    }
    let mut rects: Vec<(i32, i32, i32, i32)> = Vec::new();
    let mut k = 0;
    while k < rows.len() {
        let mut end = k;
        while end + 1 < rows.len()
            && rows[end + 1].0 == rows[end].0 + 1
            && rows[end + 1].1 == rows[k].1
        {
            end += 1;
        }
        for &(dx0, dx1) in &rows[k].1 {
            rects.push((rows[k].0, rows[end].0, dx0, dx1));
        }
        k = end + 1;
    }
    rects
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The kernels of cooltools 0.7.1 `get_kernel(3, 1, kind)`, printed by numpy (rows y = -3..3).
    #[test]
    fn kernels_are_cooltools_get_kernel() {
        let arrays = [
            (
                KernelType::Donut,
                [
                    "1110111", "1110111", "1100011", "0000000", "1100011", "1110111", "1110111",
                ],
            ),
            (
                KernelType::Vertical,
                [
                    "0011100", "0011100", "0000000", "0000000", "0000000", "0011100", "0011100",
                ],
            ),
            (
                KernelType::Horizontal,
                [
                    "0000000", "0000000", "1100011", "1100011", "1100011", "0000000", "0000000",
                ],
            ),
            (
                KernelType::Lowleft,
                [
                    "0000111", "0000111", "0000011", "0000000", "0000000", "0000000", "0000000",
                ],
            ),
        ];
        for (kind, rows) in arrays {
            let kernel = Kernel::new(kind, 3, 1).unwrap();
            // array cell (y, x) is offset (-y, -x)
            let mut expected: Vec<(i32, i32)> = Vec::new();
            for (r, row) in rows.iter().enumerate() {
                for (c, ch) in row.chars().enumerate() {
                    if ch == '1' {
                        expected.push((3 - r as i32, 3 - c as i32));
                    }
                }
            }
            expected.sort();
            assert_eq!(kernel.cells, expected, "{kind:?}");
            let covered: usize = kernel
                .rects
                .iter()
                .map(|&(y0, y1, x0, x1)| ((y1 - y0 + 1) * (x1 - x0 + 1)) as usize)
                .sum();
            assert_eq!(covered, kernel.cells.len(), "{kind:?}");
            for &(dy, dx) in &kernel.cells {
                let n = kernel
                    .rects
                    .iter()
                    .filter(|&&(y0, y1, x0, x1)| (y0..=y1).contains(&dy) && (x0..=x1).contains(&dx))
                    .count();
                assert_eq!(n, 1, "{kind:?} ({dy}, {dx})");
            }
        }
    }
}
