use super::*;
use hdf5::types::FixedAscii;

/// What a synthetic file holds; every dataset can be made inconsistent on purpose.
struct Layout {
    chr_list: Vec<&'static str>,
    start_list: Vec<i64>,
    end_list: Vec<i64>,
    data: Vec<f64>,
    indices: Vec<i64>,
    indptr: Vec<i64>,
    shape: Vec<i64>,
    correction_factors: Option<Vec<f64>>,
    nan_bins: Option<Vec<i64>>,
}

/// Two chromosomes of 10 bp bins: a (0..40, 4 bins), b (0..25, 3 bins, the last 5 bp).
fn bins_layout() -> (Vec<&'static str>, Vec<i64>, Vec<i64>) {
    (
        vec!["a", "a", "a", "a", "b", "b", "b"],
        vec![0, 10, 20, 30, 0, 10, 20],
        vec![10, 20, 30, 40, 10, 20, 25],
    )
}

/// A dense symmetric 7 x 7 test matrix with zeros here and there.
fn dense() -> Vec<Vec<f64>> {
    let n = 7;
    (0..n)
        .map(|i| {
            (0..n)
                .map(|j| ((i.min(j) * 5 + i.max(j) * 3) % 7) as f64)
                .collect()
        })
        .collect()
}

/// CSR of `m`: the upper triangle, or the full matrix with each row's columns reversed and
/// the first kept entry split into two duplicates (scipy allows both).
fn csr(m: &[Vec<f64>], full: bool) -> (Vec<f64>, Vec<i64>, Vec<i64>) {
    let (mut data, mut indices, mut indptr) = (Vec::new(), Vec::new(), vec![0i64]);
    for (i, row) in m.iter().enumerate() {
        let mut entries: Vec<(i64, f64)> = row
            .iter()
            .enumerate()
            .filter(|&(j, &v)| v != 0.0 && (full || j >= i))
            .map(|(j, &v)| (j as i64, v))
            .collect();
        if full {
            entries.reverse();
            if let Some(&(j, v)) = entries.first() {
                entries[0] = (j, v / 2.0);
                entries.push((j, v / 2.0));
            }
        }
        for (j, v) in entries {
            indices.push(j);
            data.push(v);
        }
        indptr.push(indices.len() as i64);
    }
    (data, indices, indptr)
}

fn layout(full: bool) -> Layout {
    let (chr_list, start_list, end_list) = bins_layout();
    let (data, indices, indptr) = csr(&dense(), full);
    Layout {
        chr_list,
        start_list,
        end_list,
        data,
        indices,
        indptr,
        shape: vec![7, 7],
        correction_factors: None,
        nan_bins: None,
    }
}

fn write(dir: &tempfile::TempDir, name: &str, l: &Layout) -> String {
    let path = dir.path().join(name);
    let file = hdf5::File::create(&path).unwrap();
    let matrix = file.create_group("matrix").unwrap();
    let intervals = file.create_group("intervals").unwrap();
    matrix
        .new_dataset_builder()
        .with_data(&l.data)
        .create("data")
        .unwrap();
    let indices: Vec<i32> = l.indices.iter().map(|&v| v as i32).collect();
    matrix
        .new_dataset_builder()
        .with_data(&indices)
        .create("indices")
        .unwrap();
    matrix
        .new_dataset_builder()
        .with_data(&l.indptr)
        .create("indptr")
        .unwrap();
    matrix
        .new_dataset_builder()
        .with_data(&l.shape)
        .create("shape")
        .unwrap();
    let names: Vec<FixedAscii<9>> = l
        .chr_list
        .iter()
        .map(|s| FixedAscii::from_ascii(s.as_bytes()).unwrap())
        .collect();
    intervals
        .new_dataset_builder()
        .with_data(&names)
        .create("chr_list")
        .unwrap();
    intervals
        .new_dataset_builder()
        .with_data(&l.start_list)
        .create("start_list")
        .unwrap();
    intervals
        .new_dataset_builder()
        .with_data(&l.end_list)
        .create("end_list")
        .unwrap();
    let extra = vec![1.0; l.start_list.len()];
    intervals
        .new_dataset_builder()
        .with_data(&extra)
        .create("extra_list")
        .unwrap();
    if let Some(cf) = &l.correction_factors {
        // HiCExplorer stores them as an (n, 1) column.
        file.new_dataset::<f64>()
            .shape((cf.len(), 1))
            .create("correction_factors")
            .unwrap()
            .write_raw(cf)
            .unwrap();
    }
    if let Some(nan_bins) = &l.nan_bins {
        file.new_dataset_builder()
            .with_data(nan_bins)
            .create("nan_bins")
            .unwrap();
    }
    path.to_string_lossy().into_owned()
}

fn pixels(
    reader: &HicExplorerReader,
    rows: Range<usize>,
    cols: Range<usize>,
) -> Vec<(u64, u64, f64)> {
    let mut out = Vec::new();
    reader
        .read_pixels(rows, cols, &mut |block| {
            for k in 0..block.len() {
                out.push((block.bin1[k], block.bin2[k], block.count[k]));
            }
            Ok(())
        })
        .unwrap();
    out
}

/// The naive reference: every non-zero entry of the upper triangle, row-major.
fn naive(m: &[Vec<f64>], factor: impl Fn(usize, usize) -> f64) -> Vec<(u64, u64, f64)> {
    let mut out = Vec::new();
    for (i, row) in m.iter().enumerate() {
        for (j, &value) in row.iter().enumerate().skip(i) {
            if value != 0.0 {
                out.push((i as u64, j as u64, value * factor(i, j)));
            }
        }
    }
    out
}

#[test]
fn upper_and_full_storage_give_the_dense_upper_triangle() {
    let dir = tempfile::tempdir().unwrap();
    let expected = naive(&dense(), |_, _| 1.0);
    for full in [false, true] {
        let path = write(&dir, &format!("m{full}.h5"), &layout(full));
        assert!(is_hicexplorer(&path).unwrap());
        let reader = HicExplorerReader::open(&path).unwrap();
        assert_eq!(pixels(&reader, 0..7, 0..7), expected, "full = {full}");
        // Sub-rectangles are the matching part of the whole.
        let part: Vec<_> = expected
            .iter()
            .copied()
            .filter(|&(i, j, _)| (2..5).contains(&i) && (3..6).contains(&j))
            .collect();
        assert_eq!(pixels(&reader, 2..5, 3..6), part);
        assert_eq!(reader.count_type(), CountType::Float);
        assert!(reader.weight_names().is_empty());
    }
}

#[test]
fn intervals_become_a_fixed_bin_table_with_lengths_from_the_last_bin() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(&dir, "m.h5", &layout(false));
    let reader = HicExplorerReader::open(&path).unwrap();
    let bins = reader.bins();
    assert_eq!(bins.resolution(), Some(10));
    let chroms: Vec<(&str, u64)> = bins
        .chroms()
        .iter()
        .map(|c| (c.name.as_str(), c.length_bp))
        .collect();
    assert_eq!(chroms, vec![("a", 40), ("b", 25)]);
    assert_eq!(bins.chrom_offsets(), &[0, 4, 7]);
}

#[test]
fn correction_factors_restore_counts_and_become_multiplicative_weights() {
    let dir = tempfile::tempdir().unwrap();
    let mut l = layout(false);
    // Bin 2 is a nan_bin (factor NaN), bin 5 has a zero factor.
    let c = vec![0.5, 2.0, f64::NAN, 4.0, 1.0, 0.0, 0.25];
    let usable = |k: usize| c[k].is_finite() && c[k] > 0.0;
    l.correction_factors = Some(c.clone());
    l.nan_bins = Some(vec![2]);
    let path = write(&dir, "c.h5", &l);
    let reader = HicExplorerReader::open(&path).unwrap();
    let expected = naive(&dense(), |i, j| {
        if usable(i) && usable(j) {
            c[i] * c[j]
        } else {
            1.0
        }
    });
    assert_eq!(pixels(&reader, 0..7, 0..7), expected);
    assert_eq!(reader.weight_names(), vec!["nan_bins", "weight"]);
    let weight = reader.weights("weight").unwrap().values;
    for (k, w) in weight.iter().enumerate() {
        if usable(k) {
            assert_eq!(*w, 1.0 / c[k]);
        } else {
            assert!(w.is_nan(), "bin {k}");
        }
    }
    // Balanced = stored corrected value wherever both weights exist.
    let m = dense();
    for (i, j, count) in pixels(&reader, 0..7, 0..7) {
        let (i, j) = (i as usize, j as usize);
        if usable(i) && usable(j) {
            let balanced = count * weight[i] * weight[j];
            assert!((balanced - m[i][j]).abs() <= 1e-12 * m[i][j]);
        }
    }
    let mask = reader.weights("nan_bins").unwrap().values;
    assert!(mask[2].is_nan());
    assert_eq!(mask.iter().filter(|w| **w == 1.0).count(), 6);
    assert_eq!(reader.nan_bins(), &[2]);
    assert!(reader.weights("KR").is_err());
    assert!(reader.info().notes.iter().any(|n| n.contains("1 / c")));
}

/// Open (and read) a damaged file: the error must name the file and the dataset.
fn damaged(name: &str, change: impl FnOnce(&mut Layout), dataset: &str) {
    let dir = tempfile::tempdir().unwrap();
    let mut l = layout(false);
    change(&mut l);
    let path = write(&dir, name, &l);
    let error = HicExplorerReader::open(&path)
        .and_then(|r| r.read_pixels(0..7, 0..7, &mut |_| Ok(())))
        .unwrap_err();
    assert!(matches!(error, Error::Format { .. }), "{name}: {error}");
    let text = error.to_string();
    assert!(
        text.contains(&path) && text.contains(dataset),
        "{name}: {text}"
    );
}

#[test]
fn inconsistent_files_are_format_errors_naming_the_dataset() {
    damaged(
        "short.h5",
        |l| {
            l.indptr.pop();
        },
        "matrix/indptr",
    );
    damaged(
        "decreasing.h5",
        |l| l.indptr[3] = l.indptr[5],
        "matrix/indptr",
    );
    damaged(
        "end.h5",
        |l| *l.indptr.last_mut().unwrap() -= 1,
        "matrix/indptr",
    );
    damaged("column.h5", |l| l.indices[4] = 7, "matrix/indices");
    damaged("negative.h5", |l| l.indices[0] = -1, "matrix/indices");
    damaged("shape.h5", |l| l.shape = vec![8, 8], "matrix/shape");
    damaged("square.h5", |l| l.shape = vec![7, 6], "matrix/shape");
    damaged(
        "data.h5",
        |l| {
            l.data.pop();
        },
        "matrix/data",
    );
    damaged(
        "intervals.h5",
        |l| {
            l.end_list.pop();
        },
        "end_list",
    );
    damaged("interleaved.h5", |l| l.chr_list[2] = "b", "chromosome a");
    damaged("gap.h5", |l| l.start_list[2] = 25, "intervals");
    damaged(
        "factors.h5",
        |l| l.correction_factors = Some(vec![1.0; 6]),
        "correction_factors",
    );
    damaged("nan_bins.h5", |l| l.nan_bins = Some(vec![7]), "nan_bins");
}

#[test]
fn a_dataspace_larger_than_the_file_can_hold_is_refused_before_reading() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(&dir, "huge.h5", &layout(false));
    {
        // matrix/data and matrix/indices claim 10^10 values each (80 GB) that the file does
        // not hold: chunked, never written, so they occupy no storage.
        let file = hdf5::File::open_rw(&path).unwrap();
        let matrix = file.group("matrix").unwrap();
        for name in ["data", "indices"] {
            matrix.unlink(name).unwrap();
            matrix
                .new_dataset::<f64>()
                .chunk(1 << 16)
                .shape(10_000_000_000usize)
                .create(name)
                .unwrap();
        }
    }
    let error = HicExplorerReader::open(&path).unwrap_err();
    let text = error.to_string();
    assert!(matches!(error, Error::Format { .. }), "{text}");
    assert!(
        text.contains(&path) && text.contains("matrix/data claims 10000000000 values"),
        "{text}"
    );
}

#[test]
fn coolers_are_not_taken_for_hicexplorer_files() {
    let cool = concat!(env!("CARGO_MANIFEST_DIR"), "/data/CN.mm9.10000kb.cool");
    assert!(!is_hicexplorer(cool).unwrap());
}
