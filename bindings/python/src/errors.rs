//! The library's errors as Python exceptions, with the library's messages (those the command
//! line prints): files that cannot be read or written are `OSError`s, everything else about the
//! input is a `ValueError`.

use pyo3::PyErr;
use pyo3::create_exception;
use pyo3::exceptions::{PyOSError, PyValueError};
use voussoir::io::IoError;

create_exception!(
    voussoir,
    InputError,
    PyValueError,
    "Bad input: a file, block, face or setting voussoir cannot use (the message names it)."
);
create_exception!(voussoir, FileError, PyOSError, "A file voussoir cannot read or write (the message names it).");

/// Any library error that is about the input: an [`InputError`] with its message, prefixed by
/// the scene's source as the command line does.
pub fn input(source: &str, e: impl std::fmt::Display) -> PyErr {
    InputError::new_err(format!("{source}: {e}"))
}

/// A settings value Python passed that the library does not take.
pub fn setting(e: impl std::fmt::Display) -> PyErr {
    InputError::new_err(e.to_string())
}

/// A reader's or writer's error: [`FileError`] when the file could not be read or written,
/// else [`InputError`] (the message names the file either way).
pub fn io(e: IoError) -> PyErr {
    match e {
        IoError::Read { .. } | IoError::Write { .. } => FileError::new_err(e.to_string()),
        _ => InputError::new_err(e.to_string()),
    }
}
