//! Typed errors for the library.
//!
//! Every variant that comes from a file carries the path and, where it makes sense, the line, the
//! dataset or the record that was wrong, so that the one line the binary prints tells a user which
//! file to look at and what was expected there.

use std::path::PathBuf;

/// The library's result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Everything that can go wrong in `contactmap`.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// An operating-system error while reading or writing a file.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },

    /// A file whose content does not follow its format.
    #[error("{path}: {message}")]
    Format {
        /// The file.
        path: PathBuf,
        /// What was found and what was expected, including the dataset or record where it applies.
        message: String,
    },

    /// A text file with a bad line.
    #[error("{path}:{line}: {message}")]
    Parse {
        /// The file ("-" for standard input).
        path: PathBuf,
        /// 1-based line number.
        line: u64,
        /// What was found and what was expected.
        message: String,
    },

    /// An error reported by libhdf5.
    #[error("{path}: HDF5 {context}: {message}")]
    Hdf5 {
        /// The file.
        path: PathBuf,
        /// What we were doing (the dataset or attribute).
        context: String,
        /// libhdf5's message.
        message: String,
    },

    /// A region string that cannot be parsed or names something the matrix does not have.
    #[error("region '{region}': {message}")]
    Region {
        /// The region as the user wrote it.
        region: String,
        /// What is wrong with it.
        message: String,
    },

    /// A parameter outside its accepted range, named as its `*Params` field names it
    /// (`n_eigs`): the command line prints it as its option (`--n-eigs`), Python as the keyword.
    #[error("{name} {value}: {expected}")]
    Parameter {
        /// The parameter's field name.
        name: &'static str,
        /// The value given, as text.
        value: String,
        /// What is accepted.
        expected: String,
    },

    /// A value the caller gave (an argument, an option or a combination of them) that cannot be
    /// used, where it is not one named field ([`Error::Parameter`]): a window that is not a
    /// multiple of the bin size, two options that exclude each other, a name that is not known.
    #[error("{0}")]
    Argument(String),

    /// Input data that contradicts itself or the other inputs (a bin table that does not tile
    /// its chromosomes, a pixel past the last bin, two maps with other bins), where the file it
    /// came from is not known; [`Error::in_file`] names the file.
    #[error("{0}")]
    Data(String),

    /// Input in a format version, layout or type this version cannot read or write (a .hic
    /// version, a dtype, a cooler layout): the input is not wrong, only not supported.
    #[error("{0}")]
    Unsupported(String),

    /// Work stopped on request ([`crate::interrupt::request`]: Ctrl-C in Python).
    #[error("interrupted")]
    Interrupted,

    /// Anything else a library function cannot use (the few messages that are not clearly one
    /// of the above).
    #[error("{0}")]
    Invalid(String),
}

/// What an error is about, for hosts that map errors to their own kinds (the binary's exit
/// codes, Python's exception classes).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Concern {
    /// A value or combination the caller gave ([`Error::Parameter`], [`Error::Argument`],
    /// [`Error::Region`], [`Error::Invalid`]).
    Parameter,
    /// Input that does not follow its format or contradicts itself ([`Error::Format`],
    /// [`Error::Parse`], [`Error::Hdf5`], [`Error::Data`]).
    Format,
    /// Input in a layout or version not supported ([`Error::Unsupported`]).
    Unsupported,
    /// The operating system refused a read or a write ([`Error::Io`]).
    Io,
    /// Stopped on request ([`Error::Interrupted`]).
    Interrupted,
}

impl Error {
    /// A [`Error::Parameter`]: `name` (the field) was given `value`; `expected` says what is
    /// accepted.
    ///
    /// ```
    /// let error = contactmap::Error::parameter("n_eigs", 0, "at least 1");
    /// assert_eq!(error.to_string(), "n_eigs 0: at least 1");
    /// ```
    pub fn parameter(
        name: &'static str,
        value: impl std::fmt::Display,
        expected: impl Into<String>,
    ) -> Self {
        Error::Parameter {
            name,
            value: value.to_string(),
            expected: expected.into(),
        }
    }

    /// An I/O error on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }

    /// A format error in `path`.
    pub fn format(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        Error::Format {
            path: path.into(),
            message: message.into(),
        }
    }

    /// A parse error at `line` (1-based) of `path`.
    pub fn parse(path: impl Into<PathBuf>, line: u64, message: impl Into<String>) -> Self {
        Error::Parse {
            path: path.into(),
            line,
            message: message.into(),
        }
    }

    /// A libhdf5 error while doing `context` in `path`.
    pub fn hdf5(path: impl Into<PathBuf>, context: impl Into<String>, err: hdf5::Error) -> Self {
        Error::Hdf5 {
            path: path.into(),
            context: context.into(),
            message: err.to_string(),
        }
    }

    /// A region error.
    pub fn region(region: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Region {
            region: region.into(),
            message: message.into(),
        }
    }

    /// Name `path` in an [`Error::Invalid`] or [`Error::Data`] message (`path: message`; data
    /// becomes an [`Error::Format`] of that file), for checks that do not know which file their
    /// input came from; every other error already names its file and is returned unchanged.
    ///
    /// ```
    /// use contactmap::Error;
    ///
    /// let error = Error::Data("bin 3: bins are not sorted by chromosome".into());
    /// let named = error.in_file(std::path::Path::new("a.cool"));
    /// assert!(matches!(named, Error::Format { .. }));
    /// assert_eq!(named.to_string(), "a.cool: bin 3: bins are not sorted by chromosome");
    /// ```
    pub fn in_file(self, path: &std::path::Path) -> Self {
        match self {
            Error::Invalid(message) => Error::Invalid(format!("{}: {message}", path.display())),
            Error::Data(message) => Error::format(path, message),
            other => other,
        }
    }

    /// What the error is about: the binary and the Python binding map it to an exit code and an
    /// exception class.
    ///
    /// ```
    /// use contactmap::error::{Concern, Error};
    ///
    /// assert_eq!(Error::parameter("n_eigs", 0, "at least 1").concern(), Concern::Parameter);
    /// assert_eq!(Error::format("a.cool", "no bins").concern(), Concern::Format);
    /// assert_eq!(Error::Interrupted.concern(), Concern::Interrupted);
    /// ```
    pub fn concern(&self) -> Concern {
        match self {
            Error::Parameter { .. }
            | Error::Argument(_)
            | Error::Region { .. }
            | Error::Invalid(_) => Concern::Parameter,
            Error::Format { .. } | Error::Parse { .. } | Error::Hdf5 { .. } | Error::Data(_) => {
                Concern::Format
            }
            Error::Unsupported(_) => Concern::Unsupported,
            Error::Io { .. } => Concern::Io,
            Error::Interrupted => Concern::Interrupted,
        }
    }

    /// True when the error is a closed output pipe (`contactmap dump ... | head`), which the
    /// binary treats as success.
    pub fn is_broken_pipe(&self) -> bool {
        matches!(self, Error::Io { source, .. } if source.kind() == std::io::ErrorKind::BrokenPipe)
    }
}
