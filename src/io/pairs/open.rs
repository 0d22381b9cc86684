//! Opening pairs files: plain text, gzip or BGZF (told apart by their first bytes, whatever
//! the name; BGZF, which every pairs file from pairtools or from here is, inflated on worker
//! threads by [`crate::io::open_text`]). Outputs are [`crate::io::output::Output`]s opened with
//! [`Output::open_blocked`](crate::io::output::Output::open_blocked): `.gz` names are BGZF, so
//! that tabix and pairix can index them.

use std::path::Path;

use super::records::PairsReader;
use crate::error::Result;
use crate::io::plumbing::input::open_text;

/// Open a pairs file (or `-`) and read its header.
pub fn open_pairs(path: &Path) -> Result<PairsReader> {
    let input = open_text(path)?;
    let name = if path == Path::new("-") {
        "<stdin>".to_string()
    } else {
        path.display().to_string()
    };
    PairsReader::new(input, &name)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::output::Output;
    use crate::io::plumbing::input::is_bgzf;
    use std::io::Read;

    #[test]
    fn gz_outputs_are_bgzf_that_gzip_and_we_read_back() {
        let folder = tempfile::tempdir().unwrap();
        let path = folder.path().join("out.pairs.gz");
        let mut output = Output::open_blocked(Some(&path), crate::io::output::BGZF_LEVEL).unwrap();
        output.write_all(b"#columns: a b\nx\ty\n").unwrap();
        output.finish().unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert!(is_bgzf(&bytes));
        // The BGZF end-of-file block: an empty block of 28 bytes.
        assert_eq!(
            &bytes[bytes.len() - 28..bytes.len() - 24],
            &[0x1f, 0x8b, 8, 4]
        );
        let mut text = String::new();
        flate2::read::MultiGzDecoder::new(&bytes[..])
            .read_to_string(&mut text)
            .unwrap();
        assert_eq!(text, "#columns: a b\nx\ty\n");
        let mut reader = open_pairs(&path).unwrap();
        assert_eq!(reader.header().columns(), ["a", "b"]);
        let mut record = crate::io::pairs::PairRecord::default();
        assert!(reader.read_record(&mut record).unwrap());
        assert_eq!(record.line(), b"x\ty");
    }

    #[test]
    fn an_output_dropped_before_finish_leaves_nothing() {
        let folder = tempfile::tempdir().unwrap();
        let path = folder.path().join("out.pairs");
        let mut output = Output::open_blocked(Some(&path), crate::io::output::BGZF_LEVEL).unwrap();
        output.write_all(b"half").unwrap();
        drop(output);
        assert_eq!(std::fs::read_dir(folder.path()).unwrap().count(), 0);
    }
}
