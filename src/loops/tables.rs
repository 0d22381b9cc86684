//! The dot caller's tables as cooltools writes them (`DataFrame.to_csv(sep="\t", index=False,
//! na_rep="nan")`): BEDPE columns first, floats in Python's shortest round-trip form.

use super::{DotCalls, EnrichedPixel};
use crate::expected::View;
use crate::genome::BinTable;

/// `value` as Python's `repr` writes a float: the shortest digits that read back to it, fixed
/// notation for exponents -4 to 15 (`60000.0`, `0.0001`), scientific otherwise (`1e-05`,
/// `1.5e+16`).
///
/// ```
/// use contactmap::loops::tables::python_float;
/// assert_eq!(python_float(60000.0), "60000.0");
/// assert_eq!(python_float(1e-5), "1e-05");
/// assert_eq!(python_float(0.0001), "0.0001");
/// assert_eq!(python_float(8192.000000000007), "8192.000000000007");
/// assert_eq!(python_float(1.1543498344352284e-111), "1.1543498344352284e-111");
/// assert_eq!(python_float(2.5e16), "2.5e+16");
/// assert_eq!(python_float(f64::NAN), "nan");
/// ```
pub fn python_float(value: f64) -> String {
    if value.is_nan() {
        return "nan".into();
    }
    if value.is_infinite() {
        return if value > 0.0 { "inf" } else { "-inf" }.into();
    }
    if value == 0.0 {
        return if value.is_sign_negative() {
            "-0.0"
        } else {
            "0.0"
        }
        .into();
    }
    let sci = format!("{:e}", value.abs());
    let (mantissa, exp) = sci.split_once('e').expect("{:e} has an exponent");
    let exp: i32 = exp.parse().expect("an integer exponent");
    let digits: String = mantissa.chars().filter(|c| *c != '.').collect();
    let sign = if value < 0.0 { "-" } else { "" };
    if (-4..16).contains(&exp) {
        let body = if exp >= 0 {
            let int_len = exp as usize + 1;
            if digits.len() <= int_len {
                format!("{}{}.0", digits, "0".repeat(int_len - digits.len()))
            } else {
                format!("{}.{}", &digits[..int_len], &digits[int_len..])
            }
        } else {
            format!("0.{}{}", "0".repeat((-exp - 1) as usize), digits)
        };
        format!("{sign}{body}")
    } else {
        let frac = if digits.len() > 1 {
            format!("{}.{}", &digits[..1], &digits[1..])
        } else {
            digits.clone()
        };
        let esign = if exp < 0 { '-' } else { '+' };
        format!("{sign}{frac}e{esign}{:02}", exp.abs())
    }
}

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
    let dots = calls.dots.as_ref()?;
    let mut text = header(calls);
    if calls.enriched.is_empty() {
        text.push_str("\tregion\tregion1\tregion2\tc_label\tc_size\tcstart1\tcstart2\n");
        return Some(text);
    }
    text.push_str("\tregion\tcstart1\tcstart2\tc_label\tc_size\tregion1\tregion2\n");
    for dot in dots {
        pixel_columns(&mut text, bins, &dot.pixel);
        let region = &view.regions()[dot.pixel.region].name;
        text.push_str(&format!(
            "\t{region}\t{}\t{}\t{}\t{}\t{region}\t{region}\n",
            python_float(dot.centroid[0]),
            python_float(dot.centroid[1]),
            dot.label,
            dot.size
        ));
    }
    Some(text)
}
