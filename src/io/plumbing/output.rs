//! Where text output goes (stdout, a file, a gzip file), how numbers are printed, and the
//! check that keeps a command from writing over its own inputs.
//!
//! Files are written under a temporary name and renamed when the command succeeds, so a failed
//! command never leaves a half-written output behind (the temporary is created exclusively, see
//! [`crate::io::plumbing::atomic`]). Special files (`/dev/null`, a named pipe,
//! `/dev/stdout`) are written in place: a rename would replace them.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use flate2::Compression;
use flate2::write::GzEncoder;

use crate::error::{Error, Result};
use crate::io::plumbing::atomic::Temporary;
use crate::io::plumbing::tables::write_u64;

/// An output text stream: stdout, or a (possibly gzip-compressed) file committed on `finish`.
pub struct Output {
    /// `None` once finished.
    target: Option<Target>,
    label: String,
}

enum Target {
    Stdout(BufWriter<std::io::Stdout>),
    /// `tmp` is the temporary file renamed onto the output on success (removed when dropped
    /// before); `None` when writing in place.
    File {
        writer: BufWriter<File>,
        tmp: Option<Temporary>,
    },
    Gzip {
        writer: Box<BufWriter<GzEncoder<File>>>,
        tmp: Option<Temporary>,
    },
    /// BGZF, deflated on worker threads.
    Bgzf {
        writer: Box<noodles::bgzf::io::MultithreadedWriter<File>>,
        tmp: Option<Temporary>,
    },
}

const BUFFER_BYTES: usize = 1 << 20;

/// The default BGZF compression level (libdeflate's scale). bgzip's default, zlib's 6, is run
/// by htslib with libdeflate as libdeflate's 7; at 6 the files are 0.8% larger and deflating
/// costs 14% less (pairs of the 10 M-pair benchmark).
pub const BGZF_LEVEL: u8 = 6;

/// Threads deflating a BGZF output, at least (else one per core): on few cores more threads
/// than cores keep the cores busy while the others wait (on two cores the pipe
/// `pairs parse | pairs sort | pairs dedup` of the 10 M-pair benchmark, whose dedup writes three
/// BGZF files, took a median 13.8 s with two per file and 13.2 s with four).
const MIN_DEFLATERS: usize = 4;

fn deflaters() -> std::num::NonZero<usize> {
    crate::io::plumbing::input::worker_count()
        .max(std::num::NonZero::new(MIN_DEFLATERS).expect("MIN_DEFLATERS is not zero"))
}

impl Output {
    /// Open `path` (`-` or `None` for stdout; a `.gz` suffix compresses).
    pub fn open(path: Option<&Path>) -> Result<Output> {
        Output::open_as(path, None)
    }

    /// Open `path` as [`Output::open`] does, but a `.gz` file is BGZF (block gzip, deflated on
    /// worker threads by libdeflate at `level`, 0 to 12; [`BGZF_LEVEL`] is the default): any gzip
    /// reader reads it, and tabix / pairix can index it (pairs).
    pub fn open_blocked(path: Option<&Path>, level: u8) -> Result<Output> {
        Output::open_as(path, Some(level))
    }

    fn open_as(path: Option<&Path>, blocked: Option<u8>) -> Result<Output> {
        let Some(path) = path.filter(|p| !is_stdout(Some(p))) else {
            return Ok(Output {
                target: Some(Target::Stdout(BufWriter::with_capacity(
                    BUFFER_BYTES,
                    std::io::stdout(),
                ))),
                label: "<stdout>".into(),
            });
        };
        let (file, tmp) = if crate::io::plumbing::atomic::is_special_file(path) {
            let file = File::options()
                .write(true)
                .open(path)
                .map_err(|e| Error::io(path, e))?;
            (file, None)
        } else {
            let (tmp, file) = Temporary::create(path)?;
            (file, Some(tmp))
        };
        let label = path.display().to_string();
        let gz = path.extension().is_some_and(|e| e == "gz");
        let target = if let Some(level) = blocked.filter(|_| gz) {
            let level =
                noodles::bgzf::io::writer::CompressionLevel::new(level).ok_or_else(|| {
                    Error::Invalid(format!(
                        "compression level {level} is not one of libdeflate's (0 to 12)"
                    ))
                })?;
            Target::Bgzf {
                writer: Box::new(
                    noodles::bgzf::io::multithreaded_writer::Builder::default()
                        .set_worker_count(deflaters())
                        .set_compression_level(level)
                        .build_from_writer(file),
                ),
                tmp,
            }
        } else if gz {
            Target::Gzip {
                writer: Box::new(BufWriter::with_capacity(
                    BUFFER_BYTES,
                    GzEncoder::new(file, Compression::new(6)),
                )),
                tmp,
            }
        } else {
            Target::File {
                writer: BufWriter::with_capacity(BUFFER_BYTES, file),
                tmp,
            }
        };
        Ok(Output {
            target: Some(target),
            label,
        })
    }

    /// Write bytes.
    pub fn write_all(&mut self, bytes: &[u8]) -> Result<()> {
        let result = match &mut self.target {
            Some(Target::Stdout(w)) => w.write_all(bytes),
            Some(Target::File { writer, .. }) => writer.write_all(bytes),
            Some(Target::Gzip { writer, .. }) => writer.write_all(bytes),
            Some(Target::Bgzf { writer, .. }) => writer.write_all(bytes),
            None => Ok(()),
        };
        result.map_err(|e| Error::io(&self.label, e))
    }

    /// Push what is buffered for standard output through (a stream of results, one per input,
    /// reaches a pipe as each is done); files are only complete at [`Output::finish`].
    pub fn flush(&mut self) -> Result<()> {
        match &mut self.target {
            Some(Target::Stdout(w)) => w.flush().map_err(|e| Error::io(&self.label, e)),
            _ => Ok(()),
        }
    }

    /// Flush and, for files, rename the temporary file into place.
    pub fn finish(mut self) -> Result<()> {
        let label = self.label.clone();
        let io = |e| Error::io(&label, e);
        let Some(target) = self.target.take() else {
            return Ok(());
        };
        match target {
            Target::Stdout(mut w) => w.flush().map_err(io),
            Target::File { writer, tmp } => {
                let file = writer.into_inner().map_err(|e| io(e.into_error()))?;
                match tmp {
                    Some(tmp) => {
                        file.sync_all().map_err(io)?;
                        drop(file);
                        tmp.persist()
                    }
                    None => Ok(()),
                }
            }
            Target::Gzip { writer, tmp } => {
                let encoder = writer.into_inner().map_err(|e| io(e.into_error()))?;
                drop(encoder.finish().map_err(io)?);
                match tmp {
                    Some(tmp) => tmp.persist(),
                    None => Ok(()),
                }
            }
            Target::Bgzf { mut writer, tmp } => {
                // Joins the workers and writes the end-of-file block.
                drop(writer.finish().map_err(io)?);
                match tmp {
                    Some(tmp) => tmp.persist(),
                    None => Ok(()),
                }
            }
        }
    }
}

/// A printf-style float format, the subset `cooler dump --float-format` users write:
/// `[.P](g|e|f)`, e.g. `g` (the default, 6 significant digits), `.12g`, `.3f`, `.4e`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FloatFormat {
    precision: usize,
    style: u8,
}

impl Default for FloatFormat {
    fn default() -> Self {
        FloatFormat {
            precision: 6,
            style: b'g',
        }
    }
}

impl std::str::FromStr for FloatFormat {
    type Err = String;

    fn from_str(text: &str) -> std::result::Result<Self, String> {
        let spec = text.strip_prefix('%').unwrap_or(text);
        let bad = || format!("'{text}' is not a float format (expected e.g. g, .12g, .3f, .4e)");
        let style = *spec.as_bytes().last().ok_or_else(bad)?;
        if !matches!(style, b'g' | b'e' | b'f') {
            return Err(bad());
        }
        let body = &spec[..spec.len() - 1];
        let precision = if body.is_empty() {
            6
        } else {
            body.strip_prefix('.')
                .ok_or_else(bad)?
                .parse::<usize>()
                .map_err(|_| bad())?
        };
        if precision > 40 {
            return Err(bad());
        }
        Ok(FloatFormat { precision, style })
    }
}

impl FloatFormat {
    /// Append `value` formatted as C's printf would.
    pub fn write(&self, value: f64, out: &mut Vec<u8>) {
        use std::io::Write as _;
        if !value.is_finite() {
            let text = if value.is_nan() {
                "nan"
            } else if value > 0.0 {
                "inf"
            } else {
                "-inf"
            };
            out.extend_from_slice(text.as_bytes());
            return;
        }
        match self.style {
            b'f' => {
                let _ = write!(out, "{:.*}", self.precision, value);
            }
            b'e' => write_exponent(out, &format!("{:.*e}", self.precision, value), false),
            _ => write_general(out, value, self.precision),
        }
    }
}

/// `%g`: `%e` or `%f` by the exponent, trailing zeros removed.
fn write_general(out: &mut Vec<u8>, value: f64, precision: usize) {
    let precision = precision.max(1);
    if value == 0.0 {
        out.extend_from_slice(if value.is_sign_negative() {
            b"-0"
        } else {
            b"0"
        });
        return;
    }
    let scientific = format!("{:.*e}", precision - 1, value);
    let exponent: i64 = scientific
        .rsplit_once('e')
        .and_then(|(_, e)| e.parse().ok())
        .unwrap_or(0);
    if exponent < -4 || exponent >= precision as i64 {
        write_exponent(out, &scientific, true);
    } else {
        let fixed = format!("{:.*}", (precision as i64 - 1 - exponent) as usize, value);
        out.extend_from_slice(strip_zeros(&fixed).as_bytes());
    }
}

/// Rewrite Rust's `1.5e5` as C's `1.5e+05`, optionally removing trailing zeros of the mantissa.
fn write_exponent(out: &mut Vec<u8>, rust: &str, strip: bool) {
    let (mantissa, exponent) = rust.split_once('e').unwrap_or((rust, "0"));
    let mantissa = if strip {
        strip_zeros(mantissa)
    } else {
        mantissa
    };
    let exponent: i64 = exponent.parse().unwrap_or(0);
    out.extend_from_slice(mantissa.as_bytes());
    let sign = if exponent < 0 { '-' } else { '+' };
    let _ = std::io::Write::write_fmt(out, format_args!("e{sign}{:02}", exponent.abs()));
}

fn strip_zeros(text: &str) -> &str {
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.')
    } else {
        text
    }
}

/// `value` as Python's `repr` writes a float: the shortest digits that read back to it, fixed
/// notation for exponents -4 to 15 (`60000.0`, `0.0001`), scientific otherwise (`1e-05`,
/// `1.5e+16`).
///
/// ```
/// use contactmap::io::output::python_float;
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
        let mut out = Vec::new();
        write_exponent(&mut out, &format!("{value:e}"), false);
        String::from_utf8(out).expect("ASCII digits")
    }
}

/// True when an output option means standard output: absent, or `-`.
pub fn is_stdout(path: Option<&Path>) -> bool {
    path.is_none_or(|p| p.as_os_str() == "-")
}

/// Refuse a command line whose outputs would replace one of its inputs, or one another, before
/// anything is read or written: one error, the input untouched.
///
/// `inputs` are the files read (a matrix URI's file, `io::split_uri(uri).0`; `-` and files that do not exist
/// are skipped); `outputs` are the files the command will write (`None` and `-`, standard output,
/// skipped). An output is an input when both name the same
/// file: the same path, a symbolic or hard link to it, or another spelling of its path. Each
/// output's folder must exist ([`crate::io::plumbing::atomic::check_output_folder`]), so that a long run
/// does not end on an output it cannot write.
pub fn refuse_overwrites(inputs: &[&Path], outputs: &[Option<&Path>]) -> Result<()> {
    let outputs: Vec<&Path> = outputs
        .iter()
        .flatten()
        .copied()
        .filter(|path| {
            !is_stdout(Some(path)) && !crate::io::plumbing::atomic::is_special_file(path)
        })
        .collect();
    for output in &outputs {
        for file in inputs {
            if file.as_os_str() != "-" && crate::io::plumbing::atomic::same_file(output, file) {
                let relation = if file == output {
                    "is"
                } else {
                    "is the same file as"
                };
                return Err(Error::Argument(format!(
                    "the output '{}' {relation} the input '{}': writing it would destroy the \
                     input; choose another output path (nothing was written)",
                    output.display(),
                    file.display()
                )));
            }
        }
    }
    for (k, first) in outputs.iter().enumerate() {
        if let Some(second) = outputs[..k].iter().find(|other| same_path(first, other)) {
            let also = if second == first {
                String::new()
            } else {
                format!(" (also as '{}')", second.display())
            };
            return Err(Error::Argument(format!(
                "'{}' is named for two outputs{also}: give each output its own path (nothing \
                 was written)",
                first.display()
            )));
        }
    }
    for output in &outputs {
        crate::io::plumbing::atomic::check_output_folder(output)?;
    }
    Ok(())
}

/// Whether two output paths name one file: the same existing file, or, for files still to be
/// written, the same name in the same folder.
fn same_path(a: &Path, b: &Path) -> bool {
    if crate::io::plumbing::atomic::same_file(a, b) {
        return true;
    }
    let folder = |p: &Path| {
        let parent = match p.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent,
            _ => Path::new("."),
        };
        std::fs::canonicalize(parent).ok()
    };
    a.file_name() == b.file_name() && a.file_name().is_some() && folder(a) == folder(b)
}

/// Write `bytes` whole to `path` (`None` or `-`: standard output; a file under a temporary name,
/// renamed when complete; `.gz` compresses).
pub fn write_whole(path: Option<&Path>, bytes: &[u8]) -> Result<()> {
    let mut out = Output::open(path)?;
    out.write_all(bytes)?;
    out.finish()
}

/// [`write_whole`] to the file `path`.
pub fn write_text_file(path: impl AsRef<Path>, text: impl AsRef<[u8]>) -> Result<()> {
    write_whole(Some(path.as_ref()), text.as_ref())
}

/// Append an integer-valued count (as `i64`), or a real one with `format`.
pub fn write_count(out: &mut Vec<u8>, value: f64, integer: bool, format: &FloatFormat) {
    if integer {
        if value < 0.0 {
            out.push(b'-');
        }
        write_u64(out, value.abs() as u64);
    } else {
        format.write(value, out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn g(value: f64, spec: &str) -> String {
        let mut out = Vec::new();
        spec.parse::<FloatFormat>().unwrap().write(value, &mut out);
        String::from_utf8(out).unwrap()
    }

    /// Expected strings are what C's printf (Python's `'%g' % x`) prints.
    #[test]
    fn float_formats_match_printf() {
        assert_eq!(g(0.000123456789, "g"), "0.000123457");
        assert_eq!(g(0.0000123456789, "g"), "1.23457e-05");
        assert_eq!(g(123456.0, "g"), "123456");
        assert_eq!(g(1234567.0, "g"), "1.23457e+06");
        assert_eq!(g(1.0, "g"), "1");
        assert_eq!(g(0.5, "g"), "0.5");
        assert_eq!(g(100.0, "g"), "100");
        assert_eq!(g(-2.5e-300, "g"), "-2.5e-300");
        assert_eq!(g(0.1 + 0.2, ".17g"), "0.30000000000000004");
        assert_eq!(g(1.0 / 3.0, ".12g"), "0.333333333333");
        assert_eq!(g(2.5, ".3f"), "2.500");
        assert_eq!(g(12345.678, ".2e"), "1.23e+04");
        assert_eq!(g(0.0, "g"), "0");
        assert!("x".parse::<FloatFormat>().is_err());
        assert!(".q2g".parse::<FloatFormat>().is_err());
    }

    #[test]
    fn integers_print_as_decimal() {
        let mut out = Vec::new();
        write_u64(&mut out, 0);
        out.push(b' ');
        write_u64(&mut out, 18_446_744_073_709_551_615);
        out.push(b' ');
        write_count(&mut out, -12.0, true, &FloatFormat::default());
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "0 18446744073709551615 -12"
        );
    }
}
