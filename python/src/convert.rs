//! What every part of the binding shares: the library's errors as Python exceptions, running the
//! library with the GIL released (and Ctrl-C honoured), vectors and matrices as numpy arrays,
//! and the tuple types of regions and named columns.

use contactmap::error::{Concern, Error};
use contactmap::io::tables::Column;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::{
    PyBrokenPipeError, PyFileExistsError, PyFileNotFoundError, PyInterruptedError,
    PyIsADirectoryError, PyKeyboardInterrupt, PyNotADirectoryError, PyOSError, PyPermissionError,
    PyValueError,
};
use pyo3::prelude::*;

create_exception!(
    contactmap,
    ContactmapError,
    PyValueError,
    "An input contactmap cannot use (a file, a region, a parameter): the command line's one-line message."
);

create_exception!(
    contactmap,
    FormatError,
    ContactmapError,
    "A file or data that does not follow its format, contradicts itself, or is in a layout this \
     version does not support (a ContactmapError, so a ValueError)."
);

/// The library's error as a Python exception, by what it is about: a parameter as
/// ContactmapError (a ValueError), corrupt or unsupported input as FormatError (a
/// ContactmapError), an operating-system error as the OSError subclass of its kind
/// (FileNotFoundError, PermissionError, IsADirectoryError ...), an interruption as
/// KeyboardInterrupt; always with the command line's message.
pub(crate) fn py_err(error: Error) -> PyErr {
    let message = error.to_string();
    match (error.concern(), &error) {
        (Concern::Io, Error::Io { source, .. }) => os_error(source.kind(), message),
        (Concern::Format | Concern::Unsupported, _) => FormatError::new_err(message),
        (Concern::Interrupted, _) => PyKeyboardInterrupt::new_err(message),
        _ => ContactmapError::new_err(message),
    }
}

/// The OSError subclass Python raises for an error of this kind.
fn os_error(kind: std::io::ErrorKind, message: String) -> PyErr {
    use std::io::ErrorKind;
    match kind {
        ErrorKind::NotFound => PyFileNotFoundError::new_err(message),
        ErrorKind::PermissionDenied => PyPermissionError::new_err(message),
        ErrorKind::AlreadyExists => PyFileExistsError::new_err(message),
        ErrorKind::IsADirectory => PyIsADirectoryError::new_err(message),
        ErrorKind::NotADirectory => PyNotADirectoryError::new_err(message),
        ErrorKind::BrokenPipe => PyBrokenPipeError::new_err(message),
        ErrorKind::Interrupted => PyInterruptedError::new_err(message),
        _ => PyOSError::new_err(message),
    }
}

/// Run `work` with the GIL released, on a thread of its own, while this thread watches for
/// Ctrl-C: on a signal whose handler raises (KeyboardInterrupt), the library is asked to stop
/// (`contactmap::interrupt`), its streaming loops return at their next block, and the
/// handler's exception is raised.
pub(crate) fn run<T: Send>(
    py: Python<'_>,
    work: impl FnOnce() -> Result<T, Error> + Send,
) -> PyResult<T> {
    let outcome = py.detach(|| {
        std::thread::scope(|scope| {
            let (done, result) = std::sync::mpsc::channel();
            scope.spawn(move || {
                let _ = done.send(std::panic::catch_unwind(std::panic::AssertUnwindSafe(work)));
            });
            loop {
                match result.recv_timeout(std::time::Duration::from_millis(50)) {
                    Ok(outcome) => return Ok(outcome),
                    Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {
                        if let Err(signal) = Python::attach(|py| py.check_signals()) {
                            contactmap::interrupt::request();
                            let _ = result.recv();
                            contactmap::interrupt::clear();
                            return Err(signal);
                        }
                    }
                    Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
                        return Ok(Err(Box::new("the worker thread ended without a result")
                            as Box<dyn std::any::Any + Send>));
                    }
                }
            }
        })
    })?;
    match outcome {
        Ok(result) => result.map_err(py_err),
        Err(panic) => {
            let message = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic".to_string());
            Err(pyo3::panic::PanicException::new_err(message))
        }
    }
}

pub(crate) fn vec1<'py, T: numpy::Element>(
    py: Python<'py>,
    values: Vec<T>,
) -> Bound<'py, PyArray1<T>> {
    PyArray1::from_vec(py, values)
}

/// A 2-D array as numpy's, without a copy (the library's ndarray and rust-numpy's are two
/// versions: the array's vector is handed over and viewed in its shape).
pub(crate) fn array2<'py, T: numpy::Element + Clone>(
    py: Python<'py>,
    array: ndarray::Array2<T>,
) -> Bound<'py, PyArray2<T>> {
    let (rows, cols) = array.dim();
    let array = if array.is_standard_layout() {
        array
    } else {
        array.as_standard_layout().into_owned()
    };
    let (values, _) = array.into_raw_vec_and_offset();
    vec1(py, values)
        .reshape([rows, cols])
        .expect("a vector of rows x cols values takes that shape")
}

/// A view region from Python: (chrom, start, end, name).
pub(crate) type RegionTuple = (String, u64, u64, Option<String>);

/// A named column: (name, numpy array).
pub(crate) type NamedColumn<'py> = (String, Bound<'py, PyAny>);

pub(crate) fn column<'py>(py: Python<'py>, values: Column<'_>) -> Bound<'py, PyAny> {
    match values {
        Column::Integer(v) => vec1(py, v.to_vec()).into_any(),
        Column::Real(v) => vec1(py, v.to_vec()).into_any(),
    }
}
