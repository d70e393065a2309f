//! The input files, checked before any work: a missing one is its own error type.

/// An input file that is not there (or is a folder): its own type, so that a caller can tell it
/// from a refused setting (the Python package raises `FileNotFoundError` for it).
#[derive(Debug)]
pub struct MissingFile(pub String);

message_error!(MissingFile);

/// Checks that an input file is there, and is a file (a folder says so), before any work: a
/// [`MissingFile`] if not.
pub(crate) fn check_file(path: &std::path::Path) -> Result<(), crate::Error> {
    if path.is_file() {
        Ok(())
    } else if path.is_dir() {
        let message = format!("{}: is a folder, not a file", path.display());
        Err(Box::new(MissingFile(message)))
    } else {
        Err(Box::new(MissingFile(format!(
            "{}: no such file",
            path.display()
        ))))
    }
}
