//! Cells and lines quoted in error messages are cut: a corrupt file can hold a cell of
//! megabytes, and an error must stay readable.

/// Characters of a quoted text kept in a message.
pub const EXCERPT_CHARS: usize = 80;

/// `text` as quoted in a message: whole if at most [`EXCERPT_CHARS`] characters long,
/// else its first [`EXCERPT_CHARS`] characters, `...` and its length in bytes.
pub fn excerpt(text: &str) -> String {
    match text.char_indices().nth(EXCERPT_CHARS) {
        None => text.to_owned(),
        Some((cut, _)) => format!("{}... ({} bytes)", &text[..cut], text.len()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_text_is_cut_short_text_kept() {
        assert_eq!(excerpt("0.5x"), "0.5x");
        let long = "é".repeat(500_000);
        let cut = excerpt(&long);
        assert!(cut.starts_with(&"é".repeat(EXCERPT_CHARS)));
        assert!(
            cut.ends_with("... (1000000 bytes)"),
            "{}",
            &cut[cut.len() - 30..]
        );
        assert_eq!(
            cut.chars().count(),
            EXCERPT_CHARS + " ... (1000000 bytes)".len() - 1
        );
    }
}
