//! Messages as one printable line of bounded length, whatever the user's
//! input put into them: a file name with a newline, a field name of a
//! hundred thousand characters.

/// Longest run of non-blank characters kept whole; longer ones keep their
/// start and end around a note of how much was cut.
const MAX_WORD: usize = 120;

/// Longest message kept whole.
const MAX_LINE: usize = 2000;

/// `text` as one line: control characters (newlines, tabs, escape
/// sequences) written as escapes, every run of non-blank characters longer
/// than 120 characters and the whole line beyond 2000 cut in the middle.
pub fn printable(text: &str) -> String {
    let escaped: String = text
        .chars()
        .map(|c| match c {
            ' ' => " ".to_owned(),
            c if c.is_control() || c.is_whitespace() => c.escape_default().to_string(),
            c => c.to_string(),
        })
        .collect();
    let words: Vec<String> = escaped.split(' ').map(|word| cut(word, MAX_WORD)).collect();
    cut(&words.join(" "), MAX_LINE)
}

/// `text` whole if at most `max` characters, else its start and end around
/// `…[N characters cut]…`.
fn cut(text: &str, max: usize) -> String {
    let count = text.chars().count();
    if count <= max {
        return text.to_owned();
    }
    let keep = max / 2;
    let head: String = text.chars().take(keep).collect();
    let tail: String = text.chars().skip(count - keep / 2).collect();
    let omitted = count - keep - keep / 2;
    format!("{head}…[{omitted} characters cut]…{tail}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_plain_messages_are_unchanged() {
        let line = "f.ron:1:10: field `mass`: must be > 0, got -1";
        assert_eq!(printable(line), line);
    }

    #[test]
    fn control_characters_become_escapes() {
        assert_eq!(
            printable("bad\nname.ron: cannot read\t\u{1b}[31m"),
            "bad\\nname.ron: cannot read\\t\\u{1b}[31m"
        );
    }

    #[test]
    fn long_echoes_are_cut_keeping_both_ends() {
        let field = format!("start{}end", "x".repeat(100_000));
        let line = printable(&format!("f.ron:1:2: Unexpected field named `{field}` in `Scenario`"));
        assert!(line.len() < 300, "{} bytes", line.len());
        assert!(
            line.starts_with("f.ron:1:2: Unexpected field named `startxxx"),
            "{line}"
        );
        assert!(line.contains("characters cut]"), "{line}");
        assert!(line.ends_with("xxend` in `Scenario`"), "{line}");
        let many_words = "word ".repeat(10_000);
        assert!(printable(&many_words).chars().count() < 2100);
    }
}
