//! The safe-name rule for scene names and dataset `scene_id`s: they become file and folder
//! names (`<work>/<id>/`, `<out>/<id>.svg`) and CSV cells, so they may hold only ASCII
//! letters, digits, `_`, `-` and `.`, must not be empty and must not start with `.` (no
//! hidden files, no `..`). No path separator, comma, quote or newline can pass.

/// Longest accepted name, in bytes (file systems allow 255 per path component).
pub const MAX_NAME_LEN: usize = 200;

/// Checks `name` against the rule; the error says what is wrong (without the field name).
pub fn check(name: &str) -> Result<(), String> {
    if name.is_empty() {
        return Err("is empty; a name needs letters, digits, '_', '-' or '.'".into());
    }
    if name.len() > MAX_NAME_LEN {
        return Err(format!(
            "is {} bytes long; at most {MAX_NAME_LEN} are allowed (it names files)",
            name.len()
        ));
    }
    if name.starts_with('.') {
        return Err(format!(
            "`{name}` starts with '.' (it names files; no hidden or parent folders)"
        ));
    }
    if let Some(bad) = name
        .chars()
        .find(|&c| !(c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.')))
    {
        return Err(format!(
            "`{}` holds {bad:?}; only letters, digits, '_', '-' and '.' are allowed (it names files and CSV cells)",
            name.escape_debug()
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::check;

    #[test]
    fn accepts_plain_names() {
        for name in ["quick", "train_007", "a-b.c", "X1"] {
            assert!(check(name).is_ok(), "{name}");
        }
    }

    #[test]
    fn refuses_names_that_would_escape_or_corrupt_files() {
        for (name, why) in [
            ("", "empty"),
            ("../../x", "starts with '.'"),
            (".hidden", "starts with '.'"),
            ("a/b", "'/'"),
            ("a\\b", "'\\\\'"),
            ("a,b", "','"),
            ("a\nb", "'\\n'"),
            ("a\"b", "'\"'"),
            ("a b", "' '"),
        ] {
            let message = check(name).unwrap_err();
            assert!(message.contains(why), "{name:?}: {message}");
        }
        assert!(check(&"a".repeat(201)).unwrap_err().contains("201 bytes"));
    }
}
