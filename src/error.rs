//! The crate's error type. Every message names the file or field at fault and the problem,
//! in one line, so the command line can print it as it is.

use std::path::PathBuf;

/// Everything that can go wrong between reading input and writing output.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be read or written.
    #[error("{path}: {what}: {source}")]
    Io {
        path: PathBuf,
        what: &'static str,
        source: std::io::Error,
    },
    /// A file was read but its content is not valid.
    #[error("{path}: {message}")]
    Format { path: PathBuf, message: String },
    /// A complete one-line message from a module with its own error type (it already
    /// names its file).
    #[error("{0}")]
    Message(String),
    /// A field (scene key or command-line option) has a value outside its domain.
    #[error("{field}: {message}")]
    Field { field: String, message: String },
}

impl Error {
    pub fn io(path: impl Into<PathBuf>, what: &'static str, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            what,
            source,
        }
    }
    pub fn format(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        Error::Format {
            path: path.into(),
            message: message.into(),
        }
    }
    pub fn field(field: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Field {
            field: field.into(),
            message: message.into(),
        }
    }
}

pub type Result<T> = std::result::Result<T, Error>;

/// Why an input file was refused before (or while) reading it
/// ([`crate::image_io::read_regular_file`], [`crate::image_io::check_regular_file`]).
/// Shared by every reader, whatever its own error type: each wraps it unchanged, so the
/// message is the same one line naming the file wherever it comes from.
#[derive(Debug, thiserror::Error)]
pub enum FileError {
    /// The file could not be examined or read.
    #[error("{path}: cannot read {what}: {source}")]
    Io {
        path: PathBuf,
        what: &'static str,
        #[source]
        source: std::io::Error,
    },
    /// A directory, device (`/dev/zero`), FIFO or socket: it has no length to check and
    /// reading it may never end, so it is refused without being opened.
    #[error("{path}: {what} is not a regular file (a directory, device or FIFO)")]
    NotRegular { path: PathBuf, what: &'static str },
    /// Longer than the reader's stated limit.
    #[error("{path}: {what} is {len} bytes, over the {limit} byte limit")]
    TooLarge {
        path: PathBuf,
        what: &'static str,
        len: u64,
        limit: u64,
    },
}

impl From<FileError> for Error {
    fn from(e: FileError) -> Self {
        Error::Message(e.to_string())
    }
}

/// The prefix of the error a TOML reader gives a field stated where it does not belong
/// (`misplaced field `KEY`: why`, e.g. an `[env]` field of another method): [`toml_message`]
/// places it on the field's line and names the field there, as it does an unknown field.
pub const MISPLACED_FIELD: &str = "misplaced field `";

/// A TOML parse error as one line, `line N: FIELD: message`, for every TOML file brdfkit
/// reads (scenes, the golden manifest). N is the 1-based line of the error's span in `text`,
/// FIELD the dotted key written there (`render.width`, `light[1].color`; [`toml_field_at`]),
/// left out where the line names none.
///
/// An unknown field of an internally tagged table (`[material]`, `[[light]]`: serde reads
/// the whole table before its fields) comes with the span of the table, not of the key; the
/// line is then the first one of that table that writes the key (`unknown_key_line`).
pub fn toml_message(text: &str, e: &toml::de::Error) -> String {
    let msg = e.message().trim().replace('\n', " ");
    let Some(span) = e.span() else {
        return msg;
    };
    let at = span.start.min(text.len());
    let at = unknown_key_line(text, at, &msg).unwrap_or(at);
    let line = text[..at].matches('\n').count() + 1;
    // A field stated under another method: the message names the field's line and field
    // ([`MISPLACED_FIELD`]), so its own prefix goes.
    let msg = match msg.strip_prefix(MISPLACED_FIELD) {
        Some(rest) => rest.split_once("`: ").map_or(rest, |(_, m)| m).to_string(),
        None => msg,
    };
    match toml_field_at(text, at) {
        Some(field) => format!("line {line}: {field}: {msg}"),
        None => format!("line {line}: {msg}"),
    }
}

/// The byte offset of the line at or after the line of `from` that writes the key KEY of
/// an "unknown field `KEY`" message `msg`, within the table `from` is in (its header's
/// line repeated, as `[[light]]` is, continues it; another header ends it).
fn unknown_key_line(text: &str, from: usize, msg: &str) -> Option<usize> {
    let key = msg
        .strip_prefix("unknown field `")
        .or_else(|| msg.strip_prefix(MISPLACED_FIELD))?
        .split('`')
        .next()?;
    let mut offset = text[..from].rfind('\n').map_or(0, |i| i + 1);
    let mut header: Option<&str> = None;
    for line in text[offset..].split_inclusive('\n') {
        let t = line.trim();
        if t.starts_with('[') {
            match header {
                None => header = Some(t),
                Some(h) if h == t => {}
                Some(_) => return None,
            }
        } else if let Some(rest) = t
            .strip_prefix(key)
            .or_else(|| t.strip_prefix(&format!("\"{key}\"")))
        {
            if rest.trim_start().starts_with('=') {
                return Some(offset);
            }
        }
        offset += line.len();
    }
    None
}

/// The dotted field written on the line of byte `offset` in TOML `text`: the table of the
/// nearest header above (`[render]` gives `render`, the second `[[light]]` `light[1]`) and
/// the key the line assigns, or the table alone on a header line. `None` when neither is
/// there (a line before any header that assigns no key). Headers are found by their lines
/// (a line of a multi-line value that starts with `[` would be taken for one).
pub fn toml_field_at(text: &str, offset: usize) -> Option<String> {
    let offset = offset.min(text.len());
    let start = text[..offset].rfind('\n').map_or(0, |i| i + 1);
    let end = text[start..].find('\n').map_or(text.len(), |i| start + i);
    let line = text[start..end].trim();
    let mut table: Option<String> = None;
    let mut arrays: Vec<(&str, usize)> = Vec::new();
    for l in text[..end].lines().map(str::trim) {
        if let Some(name) = l.strip_prefix("[[").and_then(|r| r.split("]]").next()) {
            let name = name.trim();
            let index = match arrays.iter_mut().find(|(a, _)| *a == name) {
                Some((_, n)) => {
                    *n += 1;
                    *n
                }
                None => {
                    arrays.push((name, 0));
                    0
                }
            };
            table = Some(format!("{name}[{index}]"));
        } else if let Some(name) = l.strip_prefix('[').and_then(|r| r.split(']').next()) {
            table = Some(name.trim().to_string());
        }
    }
    if line.starts_with('[') {
        return table;
    }
    let key = line
        .split_once('=')
        .map(|(k, _)| k.trim())
        .filter(|k| !k.is_empty() && !k.starts_with('#'))
        .map(|k| k.trim_matches('"').to_string());
    match (table, key) {
        (Some(t), Some(k)) => Some(format!("{t}.{k}")),
        (t, k) => t.or(k),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn message(text: &str) -> String {
        let e = toml::from_str::<crate::scene::SceneFile>(text).unwrap_err();
        toml_message(text, &e)
    }

    #[test]
    fn an_unknown_field_is_reported_at_its_own_line_with_its_table() {
        // A plain table: toml points at the key.
        let m = message("[render]\nwidth = 10\nwidht = 100\n");
        assert!(
            m.starts_with("line 3: render.widht: unknown field `widht`"),
            "{m}"
        );
        // Internally tagged tables: toml points at the table, the key is looked up.
        let m = message("[material]\nkind = \"lambert\"\nalbedoo = [0.5, 0.5, 0.5]\n");
        assert!(
            m.starts_with("line 3: material.albedoo: unknown field `albedoo`"),
            "{m}"
        );
        let light = "[[light]]\nkind = \"point\"\nposition = [0.0, 1.0, 0.0]\n";
        let m = message(&format!(
            "{light}{light}colour = [1.0, 1.0, 1.0]\n[render]\nwidth = 10\n"
        ));
        assert!(
            m.starts_with("line 7: light[1].colour: unknown field `colour`"),
            "{m}"
        );
    }

    #[test]
    fn a_bad_value_names_its_line_and_field() {
        let m = message("# a scene\n[render]\nheight = 10\nwidth = \"wide\"\n");
        assert!(m.starts_with("line 4: render.width: "), "{m}");
        let m = message("[render]\nwidth = = 3\n");
        assert!(m.starts_with("line 2: render.width: "), "{m}");
    }
}
