//! Short forms of user input for error and warning lines: a hostile file or flag may hold
//! megabytes where a name or number was expected, and a message quoting it must stay one line.

/// At most 60 characters of `s` for an error line, with "… (N characters)" when it was longer.
pub fn abbreviate(s: &str) -> String {
    const MAX: usize = 60;
    match s.char_indices().nth(MAX) {
        Some((i, _)) => format!("{}… ({} characters)", &s[..i], s.chars().count()),
        None => s.to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_input_is_cut_at_sixty_characters_and_counted() {
        assert_eq!(abbreviate("short"), "short");
        let long = "é".repeat(100);
        let a = abbreviate(&long);
        assert!(
            a.starts_with(&"é".repeat(60)) && a.ends_with("… (100 characters)"),
            "{a}"
        );
    }
}
