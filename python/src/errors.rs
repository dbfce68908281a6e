//! The library's errors as Python exceptions, each with the library's message: a file the
//! operating system refuses is an `OSError` (`FileNotFoundError`, `PermissionError`, … by its
//! kind), a file that is not a valid library is a `FormatError` (a `ValueError`), and every
//! other refusal (a value outside its domain, an unknown name, a record the file's writer
//! refuses) is a `ValueError`.

use bssrdf_zoo::bake::BakeError;
use bssrdf_zoo::embed::EmbedError;
use bssrdf_zoo::format::FormatError as FileError;
use pyo3::exceptions::{
    PyFileExistsError, PyFileNotFoundError, PyIsADirectoryError, PyNotADirectoryError, PyOSError,
    PyPermissionError, PyValueError,
};
use pyo3::PyErr;
use std::io::ErrorKind;

pyo3::create_exception!(
    bssrdf_zoo,
    FormatError,
    PyValueError,
    "A file that is not a valid bssrdf library file: the message names the check it failed."
);

/// An error of the file format: `OSError` (by kind) for the operating system's refusals,
/// `FormatError` for the file's content.
pub fn format(e: FileError) -> PyErr {
    let message = e.to_string();
    match &e {
        FileError::Io { source, .. } => match source.kind() {
            ErrorKind::NotFound => PyFileNotFoundError::new_err(message),
            ErrorKind::PermissionDenied => PyPermissionError::new_err(message),
            ErrorKind::AlreadyExists => PyFileExistsError::new_err(message),
            ErrorKind::IsADirectory => PyIsADirectoryError::new_err(message),
            ErrorKind::NotADirectory => PyNotADirectoryError::new_err(message),
            _ => PyOSError::new_err(message),
        },
        FileError::InvalidInput { .. } => PyValueError::new_err(message),
        _ => FormatError::new_err(message),
    }
}

/// An error of writing a file: `OSError` (by kind) for the operating system's refusals, and
/// `ValueError` for what the writer was given (a record the format cannot hold): nothing was
/// read, so no `FormatError`.
pub fn written(e: FileError) -> PyErr {
    match e {
        FileError::Io { .. } => format(e),
        _ => PyValueError::new_err(e.to_string()),
    }
}

/// An error of the handles: the file's (see [`format`]), a table the file describes badly
/// (`FormatError`), or a value (`ValueError`).
pub fn embed(e: EmbedError) -> PyErr {
    match e {
        EmbedError::Format(e) => format(e),
        EmbedError::Table { .. } | EmbedError::Sections { .. } => {
            FormatError::new_err(e.to_string())
        }
        _ => PyValueError::new_err(e.to_string()),
    }
}

/// An error of a bake: building or writing its library (see [`written`]), opening it (see
/// [`embed`]), else a value.
pub fn bake(e: BakeError) -> PyErr {
    match e {
        BakeError::Format(e) => written(e),
        BakeError::Embed(e) => embed(e),
        _ => PyValueError::new_err(e.to_string()),
    }
}

/// Any other error of the library: a value outside its domain.
pub fn value(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}
