//! A frame as MDTraj measures it: the measured atoms in single-precision nanometres and the
//! periodic cell reduced as MDTraj reduces it.

use crate::io::trajectory::{Conformation, LengthUnit};

/// A frame as MDTraj holds it: single-precision nanometres, and its periodic cell.
pub(super) struct Frame {
    /// The atoms' positions.
    pub(super) xyz: Vec<[f32; 3]>,
    /// The periodic cell, if any (and measured periodically).
    pub(super) cell: Option<Cell>,
}

/// A periodic cell, in single-precision nanometres.
pub(super) enum Cell {
    /// A rectangular box: its edges.
    Box([f32; 3]),
    /// A triclinic cell: MDTraj's reduced box vectors and the reciprocals of their diagonal.
    Triclinic([[f32; 3]; 3], [f32; 3]),
}

fn to_nm(value: f64, unit: LengthUnit) -> f32 {
    match unit {
        LengthUnit::Nanometre => value as f32,
        _ => value as f32 * 0.1f32,
    }
}

impl Frame {
    /// The frame of the atoms `used` of an MD conformation (Angstrom or nm), in that order
    /// (`None`: every atom, the conformation holding only those measured).
    pub(super) fn new(conformation: &Conformation, used: Option<&[u32]>, periodic: bool) -> Frame {
        let unit = conformation.unit;
        let nm = |p: &[f64; 3]| p.map(|x| to_nm(x, unit));
        let positions = &conformation.positions;
        let xyz = match used {
            Some(used) => used.iter().map(|&a| nm(&positions[a as usize])).collect(),
            None => positions.iter().map(nm).collect(),
        };
        let cell = conformation.cell.filter(|_| periodic).map(|vectors| {
            let v = vectors.map(|row| row.map(|x| to_nm(x, unit)));
            let rectangular = v[0][1] == 0.0
                && v[0][2] == 0.0
                && v[1][0] == 0.0
                && v[1][2] == 0.0
                && v[2][0] == 0.0
                && v[2][1] == 0.0;
            if rectangular {
                Cell::Box([v[0][0], v[1][1], v[2][2]])
            } else {
                let [a, mut b, mut c] = v;
                let sub = |x: &mut [f32; 3], y: [f32; 3], k: f32| {
                    for d in 0..3 {
                        x[d] -= y[d] * k;
                    }
                };
                let k = (c[1] / b[1]).round();
                sub(&mut c, b, k);
                let k = (c[0] / a[0]).round();
                sub(&mut c, a, k);
                let k = (b[0] / a[0]).round();
                sub(&mut b, a, k);
                Cell::Triclinic([a, b, c], [1.0 / a[0], 1.0 / b[1], 1.0 / c[2]])
            }
        });
        Frame { xyz, cell }
    }

    /// A lower bound of the (minimum-image) distance between two points, in double precision.
    pub(super) fn separation(&self, a: [f64; 3], b: [f64; 3]) -> f64 {
        let mut r = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let norm = |r: [f64; 3]| (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
        let vectors: [[f64; 3]; 3] = match &self.cell {
            None => return norm(r),
            Some(Cell::Box(e)) => [
                [f64::from(e[0]), 0.0, 0.0],
                [0.0, f64::from(e[1]), 0.0],
                [0.0, 0.0, f64::from(e[2])],
            ],
            Some(Cell::Triclinic(v, _)) => v.map(|row| row.map(f64::from)),
        };
        for k in [2, 1, 0] {
            let n = (r[k] / vectors[k][k]).round();
            for d in 0..3 {
                r[d] -= vectors[k][d] * n;
            }
        }
        let mut best = f64::MAX;
        for x in -1..=1 {
            for y in -1..=1 {
                for z in -1..=1 {
                    let (x, y, z) = (f64::from(x), f64::from(y), f64::from(z));
                    let image = [0, 1, 2]
                        .map(|d| r[d] + vectors[0][d] * x + vectors[1][d] * y + vectors[2][d] * z);
                    best = best.min(norm(image));
                }
            }
        }
        best
    }
}
