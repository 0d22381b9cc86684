//! The text layouts ([`TextFormat`]) and their guess from a file name.

/// A text layout (see the [module documentation](crate::io::matrices::text) for the columns of each).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TextFormat {
    /// `chrom1 start1 end1 chrom2 start2 end2 count` (`cooler dump --join`).
    Bg2,
    /// `bin1_id bin2_id count`, 0-based bin ids (`cooler dump`), with a separate bin table.
    Coo,
    /// Read pairs (4DN `.pairs` or pair text), binned on the fly.
    Pairs,
    /// A square dense matrix, one row per line.
    Dense,
}

/// Guess the format from the file name (a trailing `.gz` is ignored): `.bg2` / `.bedpe` -> BG2,
/// `.pairs` / `.pairsam` -> pairs, `.coo` / `.pixels` -> COO, `.dense` / `.mat` / `.matrix` ->
/// dense.
pub fn guess_format(path: &str) -> Option<TextFormat> {
    let lower = path.to_ascii_lowercase();
    let name = lower.strip_suffix(".gz").unwrap_or(&lower);
    let (_, extension) = name.rsplit_once('.')?;
    match extension {
        "bg2" | "bedpe" => Some(TextFormat::Bg2),
        "pairs" | "pairsam" => Some(TextFormat::Pairs),
        "coo" | "pixels" => Some(TextFormat::Coo),
        "dense" | "mat" | "matrix" => Some(TextFormat::Dense),
        _ => None,
    }
}
