//! A pileup's tables as `contactmap pileup` writes them: the grid and the scores, floats in
//! Python's shortest round-trip form.

use super::Pileup;
use crate::io::output::python_float;

/// The grid, tab-separated, one line per row (`nan` where no snippet has a value).
pub fn grid_tsv(pileup: &Pileup) -> String {
    let mut text = String::new();
    for row in pileup.data.rows() {
        let fields: Vec<String> = row.iter().map(|&v| python_float(v)).collect();
        text.push_str(&fields.join("\t"));
        text.push('\n');
    }
    text
}

/// `score value` lines with a header: `n` (the snippets piled up), then `scores` in order.
pub fn scores_tsv(pileup: &Pileup, scores: &[(String, f64)]) -> String {
    let mut text = format!("score\tvalue\nn\t{}\n", pileup.n);
    for (name, value) in scores {
        text.push_str(&format!("{name}\t{}\n", python_float(*value)));
    }
    text
}
