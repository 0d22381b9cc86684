//! The dot caller's tables as cooltools writes them (`DataFrame.to_csv(sep="\t", index=False,
//! na_rep="nan")`): BEDPE columns first, floats in Python's shortest round-trip form.

use super::calls::{DotCalls, EnrichedPixel};
use crate::genome::BinTable;
use crate::genome::View;
use crate::io::output::python_float;

fn pixel_columns(text: &mut String, bins: &BinTable, pixel: &EnrichedPixel) {
    for bin in [pixel.bin1, pixel.bin2] {
        let b = bins.bin(bin);
        text.push_str(&format!(
            "{}\t{}\t{}\t",
            bins.chroms()[b.chrom_id].name,
            b.start,
            b.end
        ));
    }
    text.push_str(&pixel.count.to_string());
    for &x in pixel.la_exp.iter().chain(&pixel.qval) {
        text.push('\t');
        text.push_str(&python_float(x));
    }
}

fn header(calls: &DotCalls) -> String {
    let mut head = String::from("chrom1\tstart1\tend1\tchrom2\tstart2\tend2\tcount");
    for suffix in ["value", "qval"] {
        for name in &calls.kernels {
            head.push_str(&format!("\tla_exp.{name}.{suffix}"));
        }
    }
    head
}

/// The enriched pixels as `cooltools.dots(..., clustering_radius=None)` returns them: the BEDPE
/// columns, `count`, then `la_exp.{kernel}.value` and `la_exp.{kernel}.qval` (15 columns).
pub fn enriched_tsv(calls: &DotCalls, bins: &BinTable) -> String {
    let mut text = header(calls);
    text.push('\n');
    for pixel in &calls.enriched {
        pixel_columns(&mut text, bins, pixel);
        text.push('\n');
    }
    text
}

/// The dots as `cooltools.dots` returns them (22 columns): the 15 of [`enriched_tsv`], then
/// `region cstart1 cstart2 c_label c_size region1 region2`. `None` when no clustering was done.
/// Without any enriched pixel cooltools returns an empty table whose last seven columns come in
/// another order (`region region1 region2 c_label c_size cstart1 cstart2`): so does this.
pub fn dots_tsv(calls: &DotCalls, bins: &BinTable, view: &View) -> Option<String> {
    let (header, rows) = dots_rows(calls, bins, view)?;
    let mut text = header;
    text.push('\n');
    for row in rows {
        text.push_str(&row);
        text.push('\n');
    }
    Some(text)
}

/// [`dots_tsv`] as its header line and one line per dot (without line ends), in the dots' order.
pub fn dots_rows(calls: &DotCalls, bins: &BinTable, view: &View) -> Option<(String, Vec<String>)> {
    let dots = calls.dots.as_ref()?;
    let mut head = header(calls);
    if calls.enriched.is_empty() {
        head.push_str("\tregion\tregion1\tregion2\tc_label\tc_size\tcstart1\tcstart2");
        return Some((head, Vec::new()));
    }
    head.push_str("\tregion\tcstart1\tcstart2\tc_label\tc_size\tregion1\tregion2");
    let rows = dots
        .iter()
        .map(|dot| {
            let mut text = String::new();
            pixel_columns(&mut text, bins, &dot.pixel);
            let region = &view.regions()[dot.pixel.region].name;
            text.push_str(&format!(
                "\t{region}\t{}\t{}\t{}\t{}\t{region}\t{region}",
                python_float(dot.centroid[0]),
                python_float(dot.centroid[1]),
                dot.label,
                dot.size
            ));
            text
        })
        .collect();
    Some((head, rows))
}
