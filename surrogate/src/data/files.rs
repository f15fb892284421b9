//! File access that names the file in every error.

use std::path::Path;

use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::error::{Result, SurrogateError};

/// The bytes of the file at `path`.
pub(crate) fn read(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).map_err(|source| SurrogateError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Writes `bytes` to `path` whole, replacing any file there ([`schema::write_atomic`]).
pub(crate) fn write(path: &Path, bytes: &[u8]) -> Result<()> {
    schema::write_atomic(path, bytes).map_err(|e| SurrogateError::Io {
        path: path.to_path_buf(),
        source: match e {
            schema::SchemaError::Write { source, .. } => source,
            other => std::io::Error::other(other.to_string()),
        },
    })
}

/// Removes the file at `path` if there is one.
pub(crate) fn remove_if_present(path: &Path) -> Result<()> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(SurrogateError::Io {
            path: path.to_path_buf(),
            source: e,
        }),
        _ => Ok(()),
    }
}

/// Creates the directory `path` and its missing parents.
pub(crate) fn create_dir_all(path: &Path) -> Result<()> {
    std::fs::create_dir_all(path).map_err(|source| SurrogateError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// `bytes`, read from `path`, parsed as JSON holding `what` (e.g. "a model sidecar"); the
/// error says what is wrong with the file ([`json_problem`]).
pub(crate) fn parse_json<T: DeserializeOwned>(path: &Path, bytes: &[u8], what: &str) -> Result<T> {
    parse_json_bytes(bytes, what).map_err(|detail| SurrogateError::UnreadableFile {
        path: path.to_path_buf(),
        detail,
    })
}

/// `bytes` parsed as JSON holding `what`, or what is wrong with them ([`json_problem`]).
pub(crate) fn parse_json_bytes<T: DeserializeOwned>(
    bytes: &[u8],
    what: &str,
) -> std::result::Result<T, String> {
    serde_json::from_slice(bytes).map_err(|e| json_problem(bytes, &e, what))
}

/// The file at `path` parsed as JSON holding `what`.
pub(crate) fn read_json<T: DeserializeOwned>(path: &Path, what: &str) -> Result<T> {
    parse_json(path, &read(path)?, what)
}

/// What is wrong with `bytes` that JSON parsing failed on with `e`, for a file that should
/// hold `what`: empty, cut short (the error is at the end of the bytes: a truncated file),
/// not JSON, or JSON of another shape (a missing field, a value of the wrong type).
pub(crate) fn json_problem(bytes: &[u8], e: &serde_json::Error, what: &str) -> String {
    use serde_json::error::Category;
    if bytes.iter().all(u8::is_ascii_whitespace) {
        return format!("is empty, where {what} belongs");
    }
    let text = String::from_utf8_lossy(bytes);
    let trimmed = text.trim_end();
    let end_line = trimmed.lines().count().max(1);
    let end_column = trimmed.rsplit('\n').next().map_or(0, |l| l.chars().count());
    let at_end = e.line() > end_line || (e.line() == end_line && e.column() >= end_column);
    match e.classify() {
        Category::Eof => format!(
            "ends in the middle of its JSON (line {}, column {}): a truncated copy of {what}?",
            e.line(),
            e.column()
        ),
        Category::Syntax if at_end => {
            format!("ends in the middle of its JSON ({e}): a truncated copy of {what}?")
        }
        Category::Syntax | Category::Io => format!("is not JSON ({e}), where {what} belongs"),
        Category::Data => format!(
            "is JSON but not {what}: {}",
            without_type_names(&e.to_string())
        ),
    }
}

/// Writes `value` to `path` as indented JSON.
pub(crate) fn write_json<T: Serialize>(path: &Path, value: &T) -> Result<()> {
    let json = serde_json::to_vec_pretty(value).map_err(|source| SurrogateError::Json {
        path: path.to_path_buf(),
        source,
    })?;
    write(path, &json)
}

/// serde's message without the crate's type names ("expected struct LearnerJson" reads
/// "expected an object"): they name code, not the file.
fn without_type_names(message: &str) -> String {
    match message.find("expected struct ") {
        Some(at) => {
            let rest = &message[at + "expected struct ".len()..];
            let name_end = rest.find(' ').unwrap_or(rest.len());
            format!("{}expected an object{}", &message[..at], &rest[name_end..])
        }
        None => message.to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn problem(text: &str) -> String {
        #[derive(serde::Deserialize, Debug)]
        #[allow(dead_code)]
        struct Shape {
            trees: Vec<u32>,
        }
        let e = serde_json::from_slice::<Shape>(text.as_bytes()).unwrap_err();
        json_problem(text.as_bytes(), &e, "a model")
    }

    #[test]
    fn a_bad_json_file_is_said_to_be_empty_truncated_not_json_or_of_another_shape() {
        assert_eq!(problem(""), "is empty, where a model belongs");
        assert_eq!(problem("  \n"), "is empty, where a model belongs");
        assert!(problem(r#"{"trees": [1, 2"#).starts_with("ends in the middle of its JSON"));
        assert!(problem(r#"{"trees": [1, 2e"#).starts_with("ends in the middle of its JSON"));
        assert!(problem("not json").starts_with("is not JSON (expected ident at line 1"));
        assert!(problem(r#"{"trees": [1] "x": 2}"#).starts_with("is not JSON"));
        assert_eq!(
            problem(r#"{"leaves": [1]}"#),
            "is JSON but not a model: missing field `trees` at line 1 column 15"
        );
        assert_eq!(
            problem("7"),
            "is JSON but not a model: invalid type: integer `7`, expected an object at line 1 column 1"
        );
    }
}
