//! Where command output goes: the library's [`contactmap::io::output`], and the command line's
//! own helpers (the files named by option values, `--json` summaries).

use std::path::Path;

use contactmap::error::{Error, Result};
use contactmap::export::MatrixFormat;
pub use contactmap::io::output::{
    FloatFormat, Output, is_stdout, refuse_overwrites, write_text_file, write_whole,
};

/// Refuse an output that `command` (a simulator, `polymer-map`: they write .cool files only)
/// cannot write: standard output, or a name whose extension promises another format (`sim.hic`
/// would be a cooler named .hic, which Juicebox cannot open).
pub fn check_cool_output(command: &str, output: &Path) -> Result<()> {
    if output.as_os_str() == "-" {
        return Err(Error::Argument(format!(
            "{command} writes a .cool file: give a file name to -o, not '-'"
        )));
    }
    match MatrixFormat::from_extension(output) {
        Ok(MatrixFormat::Cool) | Err(_) => Ok(()),
        Ok(_) => Err(Error::Argument(format!(
            "{command} writes a .cool file, and '{}' names another format: write OUT.cool, then \
             `contactmap convert OUT.cool {}`",
            output.display(),
            output.display()
        ))),
    }
}

/// The file of a matrix URI (`file.mcool::/resolutions/N` -> `file.mcool`), for
/// [`refuse_overwrites`].
pub fn uri_file(uri: &str) -> &Path {
    Path::new(contactmap::io::split_uri(uri).0)
}

/// The file of a `FILE[:COLUMN]` option value, for [`refuse_overwrites`]: the whole value when
/// such a file exists, else the part before the last `:`.
pub fn column_file(argument: &str) -> &Path {
    match argument.rsplit_once(':') {
        Some((path, _)) if !Path::new(argument).exists() => Path::new(path),
        _ => Path::new(argument),
    }
}

/// Print `value` on standard output as indented JSON (a command's `--json` summary).
pub fn print_json(value: &serde_json::Value) -> Result<()> {
    let mut text = serde_json::to_string_pretty(value).unwrap_or_default();
    text.push('\n');
    let mut out = Output::open(None)?;
    out.write_all(text.as_bytes())?;
    out.finish()
}

/// The lock of a `--store` into the cooler at `uri`: the file must be a .cool / .mcool (else
/// the error says so, with `instead` as the advice), and is locked until the lock is dropped, so
/// that a second store into it refuses at once.
pub fn store_lock(uri: &str, instead: &str) -> Result<contactmap::io::WriteLock> {
    let (path, _) = contactmap::io::split_uri(uri);
    if contactmap::io::detect_kind(path)? != contactmap::io::FileKind::Hdf5 {
        return Err(contactmap::error::Error::Argument(format!(
            "{uri}: --store writes into .cool / .mcool files only{instead}"
        )));
    }
    contactmap::io::WriteLock::acquire(Path::new(path))
}
