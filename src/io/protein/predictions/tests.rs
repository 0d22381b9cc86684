use super::*;

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/protein");

/// The bytes of a fixture, decompressed when it is stored gzip-compressed.
fn bytes(relative: &str) -> Vec<u8> {
    read_bytes(Path::new(&format!("{DATA}/{relative}"))).unwrap()
}

#[test]
fn gzip_predictions_read_as_their_plain_text() {
    let dir = tempfile::tempdir().unwrap();
    for (file, format) in [
        ("toxd/toxd.mat.gz", PredictionFormat::Matrix),
        ("1atzA/1atzA.apc.mat.gz", PredictionFormat::Matrix),
        ("1aapA/1aapA.rr.gz", PredictionFormat::Rr),
    ] {
        let gzip = format!("{DATA}/{file}");
        assert!(std::fs::read(&gzip).unwrap().starts_with(&[0x1f, 0x8b]));
        let plain = dir
            .path()
            .join(file.rsplit('/').next().unwrap().trim_end_matches(".gz"));
        std::fs::write(&plain, bytes(file)).unwrap();
        let from_plain = read_prediction(&plain, None).unwrap();
        let from_gzip = read_prediction(&gzip, None).unwrap();
        assert!(!from_gzip.pairs.is_empty(), "{file}");
        assert_eq!(from_gzip, from_plain, "{file}");
        assert_eq!(read_prediction(&gzip, Some(format)).unwrap(), from_plain);
        // whatever the name: gzip is recognised from the content
        let renamed = dir.path().join("prediction");
        std::fs::copy(&gzip, &renamed).unwrap();
        assert_eq!(read_prediction(&renamed, None).unwrap(), from_plain);
    }
    // a truncated gzip file is an error naming the file, not a panic
    let gzip = std::fs::read(format!("{DATA}/toxd/toxd.mat.gz")).unwrap();
    let cut = dir.path().join("cut.mat.gz");
    std::fs::write(&cut, &gzip[..gzip.len() / 2]).unwrap();
    let err = read_prediction(&cut, None).unwrap_err();
    assert!(err.to_string().contains("cut.mat.gz"), "{err}");
}

#[test]
fn detects_every_fixture_format() {
    for (file, format) in [
        ("toxd/toxd.mat.gz", PredictionFormat::Matrix),
        ("1atzA/1atzA.apc.mat.gz", PredictionFormat::Matrix),
        ("1aapA/1aapA.rr.gz", PredictionFormat::Rr),
        ("1guuA/1guuA.contact.rr", PredictionFormat::Rr),
        ("1guuA/1guuA.npz", PredictionFormat::Npz),
        ("1guuA/1guuA.predicted.npy", PredictionFormat::Npy),
    ] {
        assert_eq!(
            detect_format(&bytes(file), Path::new(file)).unwrap(),
            format,
            "{file}"
        );
    }
    let err = detect_format(b"hello world\n", Path::new("x.txt")).unwrap_err();
    assert!(
        err.to_string().contains("unknown prediction format"),
        "{err}"
    );
    assert_eq!(
        detect_format(b"# i j score\n1 10 0.5\n", Path::new("t")).unwrap(),
        PredictionFormat::Table
    );
}

#[test]
fn reads_matrices_skipping_comments() {
    let toxd = read_prediction(format!("{DATA}/toxd/toxd.mat.gz"), None).unwrap();
    assert_eq!(toxd.pairs.len(), 59 * 58 / 2);
    assert_eq!(toxd.pairs[0].0, 1);
    assert_eq!(toxd.pairs.last().unwrap().1, 59);
    let atz = read_prediction(format!("{DATA}/1atzA/1atzA.apc.mat.gz"), None).unwrap();
    assert_eq!(atz.pairs.len(), 75 * 74 / 2);
    let err = parse_matrix("1 2 3\n4 5 6\n", Path::new("m")).unwrap_err();
    assert!(err.to_string().contains("not square"), "{err}");
    let err = parse_matrix("1 2\n4 5 6\n", Path::new("m")).unwrap_err();
    assert!(matches!(err, Error::Parse { line: 2, .. }), "{err}");
}

#[test]
fn reads_rr_with_and_without_header() {
    let rr = read_prediction(format!("{DATA}/1aapA/1aapA.rr.gz"), None).unwrap();
    assert_eq!(rr.sequence.as_deref().unwrap().len(), 56);
    assert_eq!(rr.pairs[0], (14, 38, 41.427055));
    let text = "PFRMAT RR\nTARGET T0001\nMODEL 1\nACDEF\nGHIKL\n1 7 0.9\n2 9 0 8 0.5\nEND\n3 4 1\n";
    let rr = parse_rr(text, Path::new("x.rr")).unwrap();
    assert_eq!(rr.sequence.as_deref(), Some("ACDEFGHIKL"));
    assert_eq!(rr.pairs, vec![(1, 7, 0.9), (2, 9, 0.5)]);
    let err = parse_rr("ACDEF\n1 9 0.5\n", Path::new("x.rr")).unwrap_err();
    assert!(matches!(err, Error::Parse { line: 2, .. }), "{err}");
    assert!(err.to_string().contains("beyond the sequence"), "{err}");
    let err = parse_rr("1 9 0 0.5\n", Path::new("x.rr")).unwrap_err();
    assert!(err.to_string().contains("4 fields"), "{err}");
}

#[test]
fn reads_rr_mode_2_evfold_and_gremlin() {
    let mode2 = "PFRMAT RR\nRMODE 2\nMODEL 1\nACDEFGHIKL\n\
                 1 9 0.7 0.1 0.2 0.4 0.1 0.1 0.05 0.05 0 0 0\nEND\n";
    assert_eq!(
        detect_format(mode2.as_bytes(), Path::new("m")).unwrap(),
        PredictionFormat::Rr
    );
    let rr = parse_rr(mode2, Path::new("m")).unwrap();
    assert_eq!(rr.pairs, vec![(1, 9, 0.7)]);
    let err = parse_rr("1 9 0.7 0.1 x 0 0 0 0 0 0 0 0\n", Path::new("m")).unwrap_err();
    assert!(err.to_string().contains("'x'"), "{err}");

    let evfold = "1 M 3 K 0 0.25\n2 A 3 K 0 0.5\n1 M 2 A 0 -0.1\n";
    assert_eq!(
        detect_format(evfold.as_bytes(), Path::new("e")).unwrap(),
        PredictionFormat::Evfold
    );
    let prediction = parse_evfold(evfold, Path::new("e")).unwrap();
    assert_eq!(
        prediction.pairs,
        vec![(1, 3, 0.25), (2, 3, 0.5), (1, 2, -0.1)]
    );
    assert_eq!(prediction.sequence.as_deref(), Some("MAK"));
    let err = parse_evfold("1 M 3 K 0 0.25\n1 A 2 K 0 0.5\n", Path::new("e")).unwrap_err();
    assert!(matches!(err, Error::Parse { line: 2, .. }), "{err}");
    // A filtered list that skips residue 2: no sequence.
    let prediction = parse_evfold("1 M 3 K 0 0.25\n", Path::new("e")).unwrap();
    assert_eq!(prediction.sequence, None);

    let gremlin = "i\tj\ti_id\tj_id\tr_sco\ts_sco\tprob\n\
                   1\t3\t1_M\t3_K\t0.31\t2.1\t0.9\n2\t3\t2_A\t3_K\t0.12\t1.0\t0.4\n";
    assert_eq!(
        detect_format(gremlin.as_bytes(), Path::new("g")).unwrap(),
        PredictionFormat::Gremlin
    );
    let prediction = parse_gremlin(gremlin, Path::new("g")).unwrap();
    assert_eq!(prediction.pairs, vec![(1, 3, 0.31), (2, 3, 0.12)]);
    assert_eq!(prediction.sequence.as_deref(), Some("MAK"));
    let inter = "i j gene i_id j_id r_sco s_sco prob I_prob\n1 3 A 1_M 3_K 0.31 2.1 0.9 N/A\n";
    assert_eq!(
        parse_gremlin(inter, Path::new("g")).unwrap().pairs,
        vec![(1, 3, 0.31)]
    );
    let err = parse_gremlin(
        "i j i_id j_id r_sco s_sco prob\n1 3 2_M 3_K 0.3 2 1\n",
        Path::new("g"),
    )
    .unwrap_err();
    assert!(err.to_string().contains("'2_M'"), "{err}");
    // plmDCA writes `i,j,score`.
    assert_eq!(
        detect_format(b"1,3,0.02\n", Path::new("p")).unwrap(),
        PredictionFormat::Table
    );
}

#[test]
fn attaching_a_sequence_checks_residue_numbers() {
    let prediction = parse_table("1 9 0.5\n2,4,0.1\n", Path::new("t")).unwrap();
    assert_eq!(prediction.pairs, vec![(1, 9, 0.5), (2, 4, 0.1)]);
    assert!(prediction.clone().with_sequence("ACDEFGHIK").is_ok());
    let err = prediction.with_sequence("ACDEFGHI").unwrap_err();
    assert!(err.to_string().contains("beyond the sequence"), "{err}");
}

#[test]
fn reads_trrosetta_npz_and_npy_distances() {
    let npz = read_prediction(format!("{DATA}/1guuA/1guuA.npz"), None).unwrap();
    assert_eq!(npz.pairs.len(), 50 * 49 / 2);
    assert!(
        npz.pairs
            .iter()
            .all(|p| (-1e-6..=1.0 + 1e-5).contains(&p.2))
    );
    let npy = read_prediction(format!("{DATA}/1guuA/1guuA.predicted.npy"), None).unwrap();
    assert_eq!(npy.pairs.len(), 50 * 49 / 2);
    assert!(npy.pairs.iter().all(|p| p.2 < 0.0));
    // float16 true distance map.
    let truth = parse_npy(&bytes("1guuA/1guuA.true.npy"), Path::new("t")).unwrap();
    assert_eq!(truth.shape, vec![50, 50]);
    assert_eq!(truth.values[0], 0.0);
    // numpy: t[0, 1] == 5.973 (float16 0x45F9 == 5.97265625), t[0, 2] == 8.086.
    assert_eq!(truth.values[1], 5.97265625);
    assert!((truth.values[2] - 8.086).abs() < 4e-3);
}

#[test]
fn npz_without_dist_is_an_error() {
    // A zip holding only omega.npy, written with the zip crate.
    let mut buffer = std::io::Cursor::new(Vec::new());
    {
        let mut writer = zip::ZipWriter::new(&mut buffer);
        let options = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Stored);
        writer.start_file("omega.npy", options).unwrap();
        std::io::Write::write_all(&mut writer, b"\x93NUMPY").unwrap();
        writer.finish().unwrap();
    }
    let err = parse_npz(buffer.get_ref(), Path::new("x.npz")).unwrap_err();
    assert!(err.to_string().contains("no 'dist' array"), "{err}");
    assert!(err.to_string().contains("omega.npy"), "{err}");
}

/// A version-1 `.npy` with `header` (padded with spaces and a newline) and `data`.
fn npy(header: &str, data: &[u8]) -> Vec<u8> {
    let mut header = header.to_string();
    while !(10 + header.len() + 1).is_multiple_of(64) {
        header.push(' ');
    }
    header.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
    bytes.extend_from_slice(header.as_bytes());
    bytes.extend_from_slice(data);
    bytes
}

fn npy_error(bytes: &[u8]) -> String {
    let message = parse_npy(bytes, Path::new("m.npy"))
        .unwrap_err()
        .to_string();
    assert!(message.starts_with("m.npy: "), "{message}");
    assert!(!message.contains('\n'), "{message}");
    message
}

#[test]
fn npy_shapes_are_checked_against_the_data_before_allocating() {
    let data: Vec<u8> = [1.0f64, 2.0, 3.0, 4.0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let header =
        |shape: &str| format!("{{'descr': '<f8', 'fortran_order': False, 'shape': ({shape}), }}");
    let array = parse_npy(&npy(&header("2, 2"), &data), Path::new("m.npy")).unwrap();
    assert_eq!(array.shape, vec![2, 2]);
    assert_eq!(array.values, vec![1.0, 2.0, 3.0, 4.0]);
    // An empty dimension is an empty array, however large the others.
    let empty = parse_npy(
        &npy(&header(&format!("0, {}", usize::MAX)), &[]),
        Path::new("e"),
    );
    assert_eq!(empty.unwrap().values, Vec::<f64>::new());
    // The fuzz findings F-NPY-1: products that overflow usize, in 8-byte values or in count.
    let max = usize::MAX;
    for shape in [
        format!("{max}, {max}, 1"),
        format!("{}, 4", i64::MAX),
        "4294967296, 4294967296, 1".to_string(),
    ] {
        let message = npy_error(&npy(&header(&shape), &data));
        assert!(message.contains("is too large"), "{message}");
    }
    // A product that fits but that the file does not hold.
    let message = npy_error(&npy(&header("3, 3"), &data));
    assert!(message.contains("needs 72 bytes, found 32"), "{message}");
    // The same through the distance-map and .npz readers.
    let bytes = npy(&header(&format!("{max}, {max}, 1")), &data);
    let err = parse_distance_npy(&bytes, Path::new("d.npy")).unwrap_err();
    assert!(err.to_string().contains("is too large"), "{err}");
}

#[test]
fn npy_header_problems_are_said_without_quoting_the_header() {
    let data = [0u8; 8];
    let message = npy_error(&npy(
        "{'descr': '<f8', 'fortran_order': True, 'shape': (1,), }",
        &data,
    ));
    assert_eq!(
        message,
        "m.npy: .npy array in Fortran order is not supported"
    );
    // F-NPY-2: a damaged fortran_order key used to be reported as Fortran order, with the
    // raw header (newline and all) in the message.
    let message = npy_error(&npy(
        "{'descr': '<f8', 'fortran_ordeR': False, 'shape': (1,), }",
        &data,
    ));
    assert_eq!(
        message,
        "m.npy: the .npy header has no 'fortran_order' entry"
    );
    let message = npy_error(&npy(
        "{'descr': '<f8', 'fortran_order': Fa\nlse\u{7f}, 'shape': (1,), }",
        &data,
    ));
    assert_eq!(
        message,
        "m.npy: the .npy header's 'fortran_order' is 'Fa\\nlse\\u{7f}', expected True or False"
    );
    let message = npy_error(&npy(
        "{'descr': '<f8', 'fortran_order': False, 'shapE': (1,), }",
        &data,
    ));
    assert_eq!(message, "m.npy: the .npy header has no 'shape' entry");
    // What is quoted from the header is escaped and cut after 40 characters.
    let long = "x\n".repeat(30);
    let message = npy_error(&npy(
        &format!("{{'descr': '<f8', 'fortran_order': False, 'shape': (1, {long}), }}"),
        &data,
    ));
    assert_eq!(
        message,
        format!(
            "m.npy: bad .npy shape dimension '{}...'",
            "x\\n".repeat(13) + "x"
        )
    );
    let message = npy_error(&npy(
        "{'descr': '\u{e9}\t', 'fortran_order': False, 'shape': (1,), }",
        &data,
    ));
    assert_eq!(
        message,
        "m.npy: .npy dtype '\\u{e9}\\t' is not supported (expected <f2, <f4 or <f8)"
    );
    // A header longer than the file, and one that is not text.
    let mut bytes = npy(
        "{'descr': '<f8', 'fortran_order': False, 'shape': (1,), }",
        &[],
    );
    bytes.truncate(40);
    let message = npy_error(&bytes);
    assert!(message.contains("truncated .npy header"), "{message}");
    let mut bytes = npy(
        "{'descr': '<f8', 'fortran_order': False, 'shape': (1,), }",
        &data,
    );
    bytes[12] = 0xff;
    let message = npy_error(&bytes);
    assert_eq!(message, "m.npy: the .npy header is not text (byte 2)");
}

#[test]
fn half_precision() {
    assert_eq!(f16_to_f64(0x3c00), 1.0);
    assert_eq!(f16_to_f64(0xc000), -2.0);
    assert_eq!(f16_to_f64(0x0001), 2f64.powi(-24));
}

#[test]
fn fasta() {
    assert_eq!(
        read_fasta(format!("{DATA}/toxd/toxd.fasta")).unwrap().len(),
        59
    );
}
