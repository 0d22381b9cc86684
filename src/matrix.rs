//! The sparse contact matrix and the pixel blocks that readers stream.
//!
//! A [`ContactMatrix`] stores the upper triangle (`bin1 <= bin2`) of a symmetric genome-wide
//! matrix in compressed sparse rows, as cooler's `symmetric-upper` storage mode does, together with
//! its bin table and any number of named per-bin weight columns. It is built once by a
//! [`MatrixBuilder`] (which sums duplicate pixels) and is immutable afterwards.
//!
//! Large files are not loaded into a `ContactMatrix`: readers stream [`PixelBlock`]s sorted by
//! `(bin1, bin2)`, so that a whole-genome 10 kb map can be dumped or converted with bounded memory.

mod block;
pub mod builder;
mod contact;
pub mod pixels;
mod weights;

pub use block::{CountType, PixelBlock};
pub use builder::{MatrixBuilder, ZeroCounts};
pub use contact::ContactMatrix;
pub use pixels::{PixelSlice, PixelSource, Pixels};
pub use weights::{Weights, invert_weight};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::genome::{BinTable, Chrom};

    fn small() -> ContactMatrix {
        let bins = BinTable::fixed(vec![Chrom::new("a", 30), Chrom::new("b", 20)], 10).unwrap();
        let mut b = MatrixBuilder::new(bins, CountType::Integer);
        for &(i, j, c) in &[
            (0, 0, 1.0),
            (0, 2, 2.0),
            (2, 0, 3.0),
            (1, 4, 4.0),
            (4, 4, 5.0),
        ] {
            b.push(i, j, c).unwrap();
        }
        b.build()
    }

    #[test]
    fn builder_sums_duplicates_and_mirrors_lower_pixels() {
        let m = small();
        assert_eq!(m.nnz(), 4);
        assert_eq!(m.sum(), 15.0);
        assert_eq!(m.get(0, 2), 5.0);
        assert_eq!(m.get(2, 0), 5.0);
        assert_eq!(m.get(1, 1), 0.0);
        assert_eq!(m.row_offsets(), &[0, 2, 3, 3, 3, 4]);
    }

    #[test]
    fn dense_view_is_symmetric() {
        let m = small();
        let d = m.dense(0..5, 0..5);
        for i in 0..5 {
            for j in 0..5 {
                assert_eq!(d[[i, j]], d[[j, i]]);
                assert_eq!(d[[i, j]], m.get(i, j));
            }
        }
        let r = m.dense(3..5, 0..2);
        assert_eq!(r[[1, 1]], 4.0);
        assert_eq!(r[[0, 0]], 0.0);
    }

    #[test]
    fn rectangle_query_keeps_the_upper_triangle() {
        let m = small();
        let p = m.pixels_in(0..2, 2..5);
        assert_eq!(p.bin1, vec![0, 1]);
        assert_eq!(p.bin2, vec![2, 4]);
        assert_eq!(p.count, vec![5.0, 4.0]);
    }

    #[test]
    fn divisive_weights_are_inverted() {
        let w = Weights::from_divisive("KR", &[2.0, 0.0, f64::NAN, 0.5], "test".into());
        assert_eq!(w.values[0], 0.5);
        assert!(w.values[1].is_nan() && w.values[2].is_nan());
        assert_eq!(w.values[3], 2.0);
    }
}
