//! Output paths checked before the work starts ([`check_output`]): a wrong extension or an
//! unwritable directory is reported at once, not after minutes of rendering or fitting.

use crate::error::{Error, Result};
use std::path::Path;

/// Checks an output path before any work: its extension is one of `allowed` (lowercase,
/// without the dot; compared case-insensitively), it is not an existing directory, and its
/// directory (`.` for a bare name) takes a new file. `flag` names the option the path came
/// from (`--output`) for the message.
///
/// Writability is tested by creating and removing a temporary file there
/// ([`tempfile::NamedTempFile::new_in`]), the same operation the atomic writer
/// ([`super::replace_via_temp`]) starts with; nothing is left behind. Fails with a one-line
/// error naming the path, the flag and the expected extensions, or the directory and the
/// OS error.
pub fn check_output(path: &Path, allowed: &[&str], flag: &str) -> Result<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !ext.as_deref().is_some_and(|e| allowed.contains(&e)) {
        let list = allowed
            .iter()
            .map(|e| format!(".{e}"))
            .collect::<Vec<_>>()
            .join(" or ");
        return Err(Error::format(
            path,
            format!("{flag}: wrong output format: the file name must end in {list}"),
        ));
    }
    if path.is_dir() {
        return Err(Error::format(
            path,
            format!("{flag}: is a directory, not a file name"),
        ));
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    tempfile::NamedTempFile::new_in(dir).map_err(|e| {
        let e = super::atomic::without_temporary_path(e);
        Error::format(
            path,
            format!("{flag}: cannot create a file in {}: {e}", dir.display()),
        )
    })?;
    Ok(())
}
