//! Issue 11, safety of outputs and inputs: stale temporaries of killed runs are removed by the
//! next run, `balance --store` refuses a file another process is writing, and the analyses refuse
//! negative, NaN or infinite counts in a cooler (naming the file and the pixel) while `dump` still
//! shows them.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::{data, run, run_err, run_ok};

/// A PID no process can have: above the kernel's `pid_max`.
fn dead_pid() -> u32 {
    std::fs::read_to_string("/proc/sys/kernel/pid_max")
        .ok()
        .and_then(|text| text.trim().parse::<u32>().ok())
        .unwrap_or(1 << 22)
        + 1
}

/// The names of the entries of `dir`, sorted.
fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

fn temporaries(dir: &Path) -> Vec<String> {
    entries(dir)
        .into_iter()
        .filter(|name| name.ends_with(".tmp"))
        .collect()
}

#[cfg(target_os = "linux")]
#[test]
fn convert_removes_stale_temporaries_of_dead_processes_only() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.mcool");
    let stale = dir.path().join(format!(".out.mcool.{}-0.tmp", dead_pid()));
    // The test process is alive: its temporary belongs to a run in progress.
    let live = dir
        .path()
        .join(format!(".out.mcool.{}-3.tmp", std::process::id()));
    std::fs::write(&stale, b"half an mcool").unwrap();
    std::fs::write(&live, b"half an mcool").unwrap();
    run_ok(&[
        "convert",
        &data("CN.mm9.10000kb.cool"),
        out.to_str().unwrap(),
    ]);
    assert!(!stale.exists(), "the dead process's temporary is removed");
    assert!(live.exists(), "a live process's temporary is kept");
    assert!(out.exists());
    assert_eq!(
        entries(dir.path()),
        vec![
            live.file_name().unwrap().to_string_lossy().into_owned(),
            "out.mcool".to_string()
        ]
    );
}

#[cfg(target_os = "linux")]
#[test]
fn a_killed_convert_leaves_no_temporary_after_the_next_run() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("yeast.mcool");
    let out_arg = out.to_str().unwrap().to_string();
    let input = data("yeast.10kb.cool");
    // Kill a convert once its temporary exists (the whole run takes about a second; retry in the
    // unlikely case it finished between two looks).
    let mut killed = false;
    for _ in 0..5 {
        let mut child = Command::new(env!("CARGO_BIN_EXE_contactmap"))
            .args(["convert", &input, &out_arg])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let start = Instant::now();
        while temporaries(dir.path()).is_empty()
            && child.try_wait().unwrap().is_none()
            && start.elapsed() < Duration::from_secs(60)
        {
            std::thread::sleep(Duration::from_millis(1));
        }
        if child.try_wait().unwrap().is_none() {
            std::thread::sleep(Duration::from_millis(20));
            child.kill().unwrap();
            let status = child.wait().unwrap();
            if !status.success() && !temporaries(dir.path()).is_empty() {
                killed = true;
                break;
            }
        } else {
            child.wait().unwrap();
        }
        let _ = std::fs::remove_file(&out);
    }
    assert!(killed, "no convert was killed while writing its temporary");
    assert_eq!(
        temporaries(dir.path()).len(),
        1,
        "{:?}",
        entries(dir.path())
    );
    assert!(!out.exists(), "a killed run leaves no output");
    run_ok(&["convert", &input, &out_arg]);
    assert_eq!(entries(dir.path()), vec!["yeast.mcool".to_string()]);
    // The output is whole: its base resolution has the input's pixels.
    let info = run_ok(&["info", &format!("{out_arg}::/resolutions/10000")]);
    let reference = run_ok(&["info", &input]);
    let nnz = |text: &str| {
        text.lines()
            .find(|l| l.starts_with("nnz"))
            .map(str::to_string)
            .unwrap()
    };
    assert_eq!(nnz(&info), nnz(&reference));
}

#[cfg(unix)]
#[test]
fn balance_store_refuses_a_file_another_process_is_writing() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.cool");
    std::fs::copy(data("layouts/base.cool"), &path).unwrap();
    let uri = path.to_str().unwrap();
    let before = std::fs::read(&path).unwrap();
    // Another writer (this test process) holds the lock.
    let lock_path = dir.path().join(".m.cool.lock");
    let holder = std::fs::File::create(&lock_path).unwrap();
    rustix::fs::flock(&holder, rustix::fs::FlockOperation::LockExclusive).unwrap();
    let line = run_err(&["balance", uri, "--store"]);
    assert!(line.contains(uri), "{line}");
    assert!(line.contains("another process is writing"), "{line}");
    assert_eq!(
        std::fs::read(&path).unwrap(),
        before,
        "the file is unchanged"
    );
    drop(holder);
    // Once the other writer is done, the store goes through and removes the lock file.
    run_ok(&["balance", uri, "--store"]);
    assert_eq!(entries(dir.path()), vec!["m.cool".to_string()]);
    let file = hdf5::File::open(&path).unwrap();
    assert!(file.link_exists("bins/weight"));
}

#[test]
fn two_concurrent_balance_stores_never_both_write() {
    // Two runs started together: each either stores (exit 0) or refuses at once naming the lock
    // (exit 2); at least one stores, and the file holds one complete column.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("y.cool");
    std::fs::copy(data("layouts/base.cool"), &path).unwrap();
    let uri = path.to_str().unwrap();
    let spawn = || {
        Command::new(env!("CARGO_BIN_EXE_contactmap"))
            .args(["balance", uri, "--store", "--force"])
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    };
    let (first, second) = (spawn(), spawn());
    let mut stored = 0;
    for child in [first, second] {
        let out = child.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        match out.status.code() {
            Some(0) => stored += 1,
            Some(2) => {
                assert_eq!(stderr.lines().count(), 1, "{stderr}");
                assert!(stderr.contains("another process is writing"), "{stderr}");
            }
            other => panic!("exit {other:?}: {stderr}"),
        }
    }
    assert!(stored >= 1);
    assert_eq!(entries(dir.path()), vec!["y.cool".to_string()]);
    // The stored column is whole: it equals the weights of a fresh run.
    let column = |text: &str, skip: usize| -> Vec<f64> {
        text.lines()
            .skip(skip)
            .map(|l| match l.split('\t').nth(3).unwrap() {
                "" => f64::NAN, // dump prints masked bins as an empty field, as cooler
                field => field.parse().unwrap(),
            })
            .collect()
    };
    let fresh = column(&run_ok(&["balance", uri]), 1);
    // dump prints 6 significant digits, as cooler dump.
    let dumped = column(&run_ok(&["dump", "-t", "bins", uri]), 0);
    assert_eq!(fresh.len(), dumped.len());
    for (a, b) in fresh.iter().zip(&dumped) {
        assert!(
            (a - b).abs() <= 1e-5 * a.abs() || (a.is_nan() && b.is_nan()),
            "{a} vs {b}"
        );
    }
}

/// A copy of `layouts/base.cool` in `dir` with its count column rewritten as float64 and, when
/// `bad` is given, a cis pixel two bins off the diagonal set to it. Returns the path and the
/// pixel's (bin1, bin2).
fn float_copy(dir: &Path, name: &str, bad: Option<f64>) -> (PathBuf, u64, u64) {
    let path = dir.join(name);
    std::fs::copy(data("layouts/base.cool"), &path).unwrap();
    let file = hdf5::File::open_rw(&path).unwrap();
    let pixels = file.group("pixels").unwrap();
    let bin1: Vec<i64> = pixels.dataset("bin1_id").unwrap().read_raw().unwrap();
    let bin2: Vec<i64> = pixels.dataset("bin2_id").unwrap().read_raw().unwrap();
    let counts: Vec<i32> = pixels.dataset("count").unwrap().read_raw().unwrap();
    let mut values: Vec<f64> = counts.iter().map(|&c| f64::from(c)).collect();
    let k = (0..values.len())
        .find(|&k| bin1[k] >= 30 && bin2[k] == bin1[k] + 2)
        .expect("a pixel two bins off the diagonal");
    if let Some(bad) = bad {
        values[k] = bad;
    }
    pixels.unlink("count").unwrap();
    pixels
        .new_dataset_builder()
        .with_data(values.as_slice())
        .create("count")
        .unwrap();
    drop(pixels);
    drop(file);
    (path, bin1[k] as u64, bin2[k] as u64)
}

/// The analyses, each writing its output into `dir`.
fn analyses(uri: &str, dir: &Path) -> Vec<Vec<String>> {
    let out = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let command = |args: &[&str]| args.iter().map(|a| a.to_string()).collect::<Vec<_>>();
    vec![
        command(&["balance", uri, "-o", &out("w.tsv")]),
        command(&["expected", uri, "--raw", "-o", &out("e.tsv")]),
        command(&["normalize", uri, &out("oe.cool"), "--raw"]),
        command(&[
            "tads",
            uri,
            "--raw",
            "--window",
            "30k",
            "-o",
            &out("ins.tsv"),
        ]),
    ]
}

#[test]
fn analyses_refuse_negative_nan_and_infinite_counts_and_dump_shows_them() {
    let dir = tempfile::tempdir().unwrap();
    // The bins as dump prints them (`chrom start end` per bin id), from the untouched fixture.
    let bins: Vec<String> = run_ok(&["dump", "-t", "bins", &data("layouts/base.cool")])
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            format!("{}:{}-{}", f[0], f[1], f[2])
        })
        .collect();

    // Control: the float copy without a bad count runs every analysis.
    let (good, _, _) = float_copy(dir.path(), "good.cool", None);
    let good = good.to_str().unwrap().to_string();
    for args in analyses(&good, dir.path()) {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        run_ok(&args);
    }

    for (name, bad, shown) in [
        ("negative.cool", -3.0, "-3"),
        ("nan.cool", f64::NAN, "nan"),
        ("infinite.cool", f64::INFINITY, "inf"),
    ] {
        let case = tempfile::tempdir().unwrap();
        let (path, bin1, bin2) = float_copy(case.path(), name, Some(bad));
        let uri = path.to_str().unwrap().to_string();
        let pixel = format!(
            "pixel bin1_id={bin1} bin2_id={bin2} ({} x {})",
            bins[bin1 as usize], bins[bin2 as usize]
        );
        for args in analyses(&uri, case.path()) {
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            let line = run_err(&args);
            assert!(line.contains(&uri), "{args:?}: {line}");
            assert!(line.contains(&pixel), "{args:?}: {line} (expected {pixel})");
            assert_eq!(
                entries(case.path()),
                vec![name.to_string()],
                "{args:?} leaves no output"
            );
        }
        // dump shows the pixel as stored.
        let dump = run_ok(&["dump", &uri]);
        let row = dump
            .lines()
            .find(|l| l.starts_with(&format!("{bin1}\t{bin2}\t")))
            .unwrap_or_else(|| panic!("pixel {bin1} {bin2} in dump"));
        let value = row.rsplit('\t').next().unwrap();
        assert!(value.eq_ignore_ascii_case(shown), "{row}");
        assert!(run(&["info", &uri]).status.success());
    }
}
