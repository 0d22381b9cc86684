//! A pileup's tables as `contactmap pileup` writes them: the grids and the scores, floats in
//! Python's shortest round-trip form.

use super::result::{Pileup, Pileups};
use crate::io::npz::{NpyArray, NpyData};
use crate::io::output::python_float;

fn grid_lines(pileup: &Pileup, prefix: &str, text: &mut String) {
    for (r, row) in pileup.data.rows().into_iter().enumerate() {
        let fields: Vec<String> = row.iter().map(|&v| python_float(v)).collect();
        if !prefix.is_empty() {
            text.push_str(&format!("{prefix}\t{r}\t"));
        }
        text.push_str(&fields.join("\t"));
        text.push('\n');
    }
}

/// The grid, tab-separated, one line per row (`nan` where no snippet has a value).
pub fn grid_tsv(pileup: &Pileup) -> String {
    let mut text = String::new();
    grid_lines(pileup, "", &mut text);
    text
}

/// Every group's grid, stacked: a header (`group`, `row`, then the columns' indices), then per
/// group (the one of all snippets last) its rows, each led by the group's label and row index.
pub fn groups_tsv(pileups: &Pileups) -> String {
    let size = pileups.all().data.ncols();
    let columns: Vec<String> = (0..size).map(|c| c.to_string()).collect();
    let mut text = format!("group\trow\t{}\n", columns.join("\t"));
    for pileup in &pileups.groups {
        grid_lines(pileup, &pileup.key.to_string(), &mut text);
    }
    text
}

/// One line per group (the one of all snippets last): its label, `n` (snippets piled up),
/// `control_n` (with shifted controls), then its scores (the same names for every group).
pub fn scores_tsv(rows: &[super::scores::GroupScores<'_>]) -> String {
    let controls = rows.iter().any(|(p, _)| p.control_n.is_some());
    let names: Vec<&str> = rows
        .first()
        .map(|(_, s)| s.iter().map(|(n, _)| n.as_str()).collect())
        .unwrap_or_default();
    let mut text = format!(
        "group\tn{}\t{}\n",
        if controls { "\tcontrol_n" } else { "" },
        names.join("\t")
    );
    for (pileup, scores) in rows {
        text.push_str(&format!("{}\t{}", pileup.key, pileup.n));
        if controls {
            text.push_str(&format!("\t{}", pileup.control_n.unwrap_or(0)));
        }
        for (_, value) in scores {
            text.push_str(&format!("\t{}", python_float(*value)));
        }
        text.push('\n');
    }
    text
}

/// The arrays of `PREFIX.npz`: `data` (groups x N x N), `num` (the same, finite values per
/// pixel), `n`, `control_n` (with shifts) and `group` (labels), the group of all last.
pub fn pileup_arrays(pileups: &Pileups) -> Vec<NpyArray> {
    let groups = &pileups.groups;
    let size = pileups.all().data.nrows();
    let shape = vec![groups.len(), size, size];
    let mut arrays = vec![
        NpyArray {
            name: "data".into(),
            shape: shape.clone(),
            data: NpyData::F64(groups.iter().flat_map(|p| p.data.iter().copied()).collect()),
        },
        NpyArray {
            name: "num".into(),
            shape,
            data: NpyData::I64(
                groups
                    .iter()
                    .flat_map(|p| p.num.iter().map(|&k| k as i64))
                    .collect(),
            ),
        },
        NpyArray {
            name: "n".into(),
            shape: vec![groups.len()],
            data: NpyData::I64(groups.iter().map(|p| p.n as i64).collect()),
        },
    ];
    if groups.iter().any(|p| p.control_n.is_some()) {
        arrays.push(NpyArray {
            name: "control_n".into(),
            shape: vec![groups.len()],
            data: NpyData::I64(
                groups
                    .iter()
                    .map(|p| p.control_n.unwrap_or(0) as i64)
                    .collect(),
            ),
        });
    }
    arrays.push(NpyArray {
        name: "group".into(),
        shape: vec![groups.len()],
        data: NpyData::Text(groups.iter().map(|p| p.key.to_string()).collect()),
    });
    arrays
}
