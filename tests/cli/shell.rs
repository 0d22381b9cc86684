//! Shell integration: completions load in bash and complete subcommands; man pages build.

use super::*;

/// Complete `words` (the last one partial) with the bash script of `contactmap completions`.
fn bash_complete(words: &[&str]) -> Vec<String> {
    let script = run_ok(&["completions", "bash"]);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("contactmap.bash");
    std::fs::write(&path, script).unwrap();
    let line = words.join(" ");
    let program = format!(
        "source '{}'; COMP_WORDS=({line}); COMP_CWORD={}; COMP_LINE='{line}'; COMP_POINT=${{#COMP_LINE}}; \
         _contactmap contactmap '{}' '{}'; printf '%s\\n' \"${{COMPREPLY[@]}}\"",
        path.display(),
        words.len() - 1,
        words[words.len() - 1],
        words[words.len() - 2],
    );
    let out = std::process::Command::new("bash")
        .args(["-c", &program])
        .output()
        .expect("bash runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout)
        .unwrap()
        .split_whitespace()
        .map(String::from)
        .collect()
}

#[test]
fn bash_completes_subcommands_and_options() {
    assert_eq!(
        bash_complete(&["contactmap", "comp"]),
        ["compartments", "completions"]
    );
    assert_eq!(bash_complete(&["contactmap", "plot", "sad"]), ["saddle"]);
    let options = bash_complete(&["contactmap", "compartments", "--pha"]);
    assert_eq!(options, ["--phasing-track"]);
    for shell in ["zsh", "fish"] {
        let script = run_ok(&["completions", shell]);
        assert!(
            script.contains("compartments") && script.contains("phasing-track"),
            "{shell}"
        );
    }
}

#[test]
fn man_pages_build() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("man");
    let status = run(&["man", "--dir", out.to_str().unwrap()]);
    assert!(status.status.success());
    for page in [
        "contactmap.1",
        "contactmap-balance.1",
        "contactmap-plot-saddle.1",
        "contactmap-score-compartments.1",
    ] {
        let text = std::fs::read_to_string(out.join(page)).unwrap_or_else(|_| panic!("{page}"));
        assert!(text.starts_with(".ie") || text.contains(".TH"), "{page}");
        assert!(text.contains(".SH NAME"), "{page}");
    }
    let balance = std::fs::read_to_string(out.join("contactmap-balance.1")).unwrap();
    assert!(balance.contains("store"), "the options are documented");
}

#[test]
fn summaries_as_json_and_one_record_per_input() {
    // info over several inputs: one JSON object per line, in order
    let inputs = [data("yeast.10kb.cool"), data("CN.mm9.10000kb.cool")];
    let out = run_ok(&["info", &inputs[0], &inputs[1], "--json"]);
    let lines: Vec<serde_json::Value> = out
        .lines()
        .map(|l| serde_json::from_str(l).expect("one JSON object per line"))
        .collect();
    assert_eq!(lines.len(), 2);
    assert_eq!(lines[0]["uri"], inputs[0].as_str());
    assert_eq!(lines[1]["bin-size"], 10_000_000);
    // the same values as one input at a time
    for (line, input) in lines.iter().zip(&inputs) {
        let single: serde_json::Value =
            serde_json::from_str(&run_ok(&["info", input, "--json"])).unwrap();
        assert_eq!(&single, line);
    }
    // balance --json: the convergence summary on stdout, the weights in the file
    let dir = tempfile::tempdir().unwrap();
    let weights = dir.path().join("w.tsv");
    let uri = data("cooler_test_file.mcool::/resolutions/100000");
    let summary: serde_json::Value = serde_json::from_str(&run_ok(&[
        "balance",
        &uri,
        "-o",
        weights.to_str().unwrap(),
        "--json",
    ]))
    .unwrap();
    assert_eq!(summary["method"], "ice");
    assert_eq!(summary["converged"], true);
    assert_eq!(summary["n_bins"], 1380);
    assert!(std::fs::read_to_string(&weights).unwrap().lines().count() > 1380);
    let err = run_err(&["balance", &uri, "--json"]);
    assert!(err.contains("--json"), "{err}");
    // tads --json: the counts of the BED files written
    let (track, bed) = (dir.path().join("ins.tsv"), dir.path().join("b.bed"));
    let summary: serde_json::Value = serde_json::from_str(&run_ok(&[
        "tads",
        &uri,
        "--window",
        "300k,500k",
        "-o",
        track.to_str().unwrap(),
        "--boundaries",
        bed.to_str().unwrap(),
        "--json",
    ]))
    .unwrap();
    let n_bed = std::fs::read_to_string(&bed).unwrap().lines().count();
    assert_eq!(summary["n_boundaries"], n_bed);
    assert_eq!(summary["windows"][1]["window_bp"], 500000);
    let err = run_err(&["tads", &uri, "--json"]);
    assert!(err.contains("-o FILE"), "{err}");
}

/// Issue 26: the top-level help names every nested subcommand (`score compartments`, `score
/// overlap` and `plot saddle` were missing), read from each group's own list.
#[test]
fn top_level_help_names_every_nested_subcommand() {
    let top = crate::run_ok(&["--help"]);
    let top = top.split_whitespace().collect::<Vec<_>>().join(" ");
    for group in ["score", "plot", "simulate"] {
        let help = crate::run_ok(&[group, "--help"]);
        let names: Vec<&str> = help
            .lines()
            .skip_while(|l| !l.starts_with("Commands:"))
            .skip(1)
            .take_while(|l| l.starts_with("  "))
            .filter(|l| l.starts_with("  ") && !l.starts_with("   "))
            .filter_map(|l| l.split_whitespace().next())
            .filter(|name| *name != "help")
            .collect();
        assert!(names.len() >= 2, "{group}: {names:?}");
        for name in names {
            assert!(
                top.contains(&format!("`{group} {name}`")),
                "contactmap --help does not name `{group} {name}`"
            );
        }
    }
}

/// The help of `args` rendered for a terminal of `columns` columns (no terminal: clap reads
/// COLUMNS).
fn help_at(args: &[&str], columns: &str) -> String {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_contactmap"))
        .args(args)
        .arg("--help")
        .env("COLUMNS", columns)
        .output()
        .unwrap();
    assert!(out.status.success(), "{args:?}");
    String::from_utf8(out.stdout).unwrap()
}

/// The lines of a help's `Examples:` section.
fn examples(help: &str) -> Vec<String> {
    help.lines()
        .skip_while(|l| !l.trim_end().ends_with("Examples:"))
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .map(String::from)
        .collect()
}

/// Issue 26: every command's examples read the same in a 40-column terminal as in a 300-column
/// one: never wrapped inside a command, so they can be pasted (help is written at 80 columns at
/// least, and every example line fits in 78). Issue 51: every other line of text fits in 100.
#[test]
fn help_examples_are_never_wrapped() {
    let top = crate::run_ok(&["--help"]);
    let commands: Vec<&str> = top
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter(|l| !l.starts_with("   "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|name| *name != "help")
        .collect();
    let mut checked = 0;
    for command in commands {
        let mut paths = vec![vec![command]];
        let own = help_at(&[command], "300");
        for line in own
            .lines()
            .skip_while(|l| !l.starts_with("Commands:"))
            .skip(1)
            .take_while(|l| l.starts_with("  "))
            .filter(|l| !l.starts_with("   "))
        {
            let name = line.split_whitespace().next().unwrap();
            if name != "help" {
                paths.push(vec![command, name]);
            }
        }
        for path in paths {
            let wide = examples(&help_at(&path, "300"));
            let narrow = examples(&help_at(&path, "40"));
            assert_eq!(narrow, wide, "{path:?}: examples wrapped");
            for line in &wide {
                assert!(line.len() <= 78, "{path:?}: {line}");
            }
            // issue 51: every paragraph of the help is written to fit 100 columns (so none is
            // wrapped mid-sentence by clap in a terminal that wide); clap wraps the option
            // descriptions (10 spaces in) and option names itself
            for line in help_at(&path, "300").lines() {
                let indent = line.len() - line.trim_start().len();
                let option = line.trim_start().starts_with('-') && indent <= 6;
                if line.starts_with("Usage:") || option || indent == 10 {
                    continue;
                }
                assert!(
                    line.chars().count() <= 100,
                    "{path:?}: a help line of {} characters: {line}",
                    line.chars().count()
                );
            }
            checked += usize::from(!wide.is_empty());
        }
    }
    assert!(checked >= 20, "only {checked} commands with examples");
}
