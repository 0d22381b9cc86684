//! The XTC and DCD readers against MDTraj on corrupted copies of the fixtures: every mutant that
//! MDTraj refuses is refused, at the frame where MDTraj stopped or before it, and a mutant that
//! is read is read to MDTraj's number of frames. The mutants and MDTraj's verdicts come from
//! `scripts/md_mutants.py` (`data/reference/mdtraj/mutants.tsv.gz`); the mutants are drawn again
//! here with the same generator.

use super::stream::open_trajectories;

/// splitmix64: the next (state, value).
fn splitmix64(state: u64) -> (u64, u64) {
    let state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    (state, z ^ (z >> 31))
}

/// Mutant `index` of `data` and its (kind, offset, length), as scripts/md_mutants.py draws it.
fn mutant(data: &[u8], index: u64) -> (Vec<u8>, u64, usize, usize) {
    let (state, kind) = splitmix64(index);
    let kind = kind % 3;
    let (mut state, offset) = splitmix64(state);
    let offset = (offset % data.len() as u64) as usize;
    let mut out = data.to_vec();
    match kind {
        0 => {
            let (next, length) = splitmix64(state);
            state = next;
            let length = (1 + length % 2000).min((data.len() - offset) as u64) as usize;
            for byte in &mut out[offset..offset + length] {
                let (next, value) = splitmix64(state);
                state = next;
                *byte = value as u8;
            }
            (out, kind, offset, length)
        }
        1 => {
            out[offset] = splitmix64(state).1 as u8;
            (out, kind, offset, 1)
        }
        _ => {
            out.truncate(offset);
            (out, kind, offset, 0)
        }
    }
}

/// The frame number an error message names (`...:frame N: ...`), if any.
fn frame_named(message: &str) -> Option<usize> {
    let rest = &message[message.find(":frame ")? + 7..];
    rest.split(|c: char| !c.is_ascii_digit())
        .next()?
        .parse()
        .ok()
}

#[test]
fn every_mutant_mdtraj_refuses_is_refused_at_its_frame() {
    let mut table = String::new();
    let file = std::fs::File::open("data/reference/mdtraj/mutants.tsv.gz").unwrap();
    std::io::Read::read_to_string(&mut flate2::read::GzDecoder::new(file), &mut table).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let (mut refused, mut stricter, mut rows) = (0, 0, 0);
    let mut failures = Vec::new();
    for line in table.lines().skip(1) {
        let f: Vec<&str> = line.split('\t').collect();
        let (name, index, verdict) = (f[0], f[1].parse::<u64>().unwrap(), f[5]);
        let frames: usize = f[6].parse().unwrap();
        let data = std::fs::read(format!("data/md/{name}")).unwrap();
        let (body, kind, offset, length) = mutant(&data, index);
        assert_eq!(
            (kind.to_string(), offset.to_string(), length.to_string()),
            (f[2].to_string(), f[3].to_string(), f[4].to_string()),
            "{name} mutant {index} drawn as the script drew it"
        );
        rows += 1;
        let path = dir
            .path()
            .join(format!("m{index}.{}", &name[name.len() - 3..]));
        std::fs::write(&path, &body).unwrap();
        let read: Result<Vec<_>, _> =
            open_trajectories(&[path.to_string_lossy().into_owned()]).and_then(|t| t.collect());
        let what = format!("{name} mutant {index} (kind {kind}, offset {offset}, length {length})");
        match (verdict, read) {
            ("refused", Ok(conformations)) => failures.push(format!(
                "{what}: MDTraj refuses it after {frames} frames, we read {}",
                conformations.len()
            )),
            ("refused", Err(error)) => {
                refused += 1;
                let message = error.to_string();
                // MDTraj read `frames` frames: the failing one is frames + 1 (or the header)
                if let Some(named) = frame_named(&message) {
                    if named > frames + 1 {
                        failures.push(format!(
                            "{what}: MDTraj stops at frame {}, we at frame {named}: {message}",
                            frames + 1
                        ));
                    }
                } else if frames > 0 {
                    failures.push(format!("{what}: no frame named in '{message}'"));
                }
            }
            (_, Ok(conformations)) if conformations.len() != frames => failures.push(format!(
                "{what}: MDTraj reads {frames} frames, we {}",
                conformations.len()
            )),
            (_, Ok(_)) => {}
            (_, Err(_)) => stricter += 1,
        }
    }
    assert!(
        rows > 600 && refused > 250,
        "{rows} mutants, {refused} refused"
    );
    assert!(
        failures.is_empty(),
        "{} of {rows} mutants ({stricter} refused by us alone):\n{}",
        failures.len(),
        failures.join("\n")
    );
}
