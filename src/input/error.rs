//! [`InputError`]: what is wrong with a file the user handed in.

/// A problem with an input file: which file, where in it (when the parser
/// knows), and what. Shown as one line, `file:line:column: message`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{origin}{}: {message}", location.map_or(String::new(), |(line, column)| format!(":{line}:{column}")))]
pub struct InputError {
    /// The file (or built-in text) the problem is in.
    pub origin: String,
    /// 1-based line and column, where known.
    pub location: Option<(usize, usize)>,
    /// What is wrong, naming the field.
    pub message: String,
}

impl InputError {
    /// A problem with no location in the text (a cross-field check, a file
    /// that cannot be read).
    pub fn new(origin: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            origin: origin.into(),
            location: None,
            message: message.into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_line_with_and_without_a_location() {
        let located = InputError {
            location: Some((3, 14)),
            ..InputError::new("f.ron", "field `mass`: must be > 0")
        };
        assert_eq!(located.to_string(), "f.ron:3:14: field `mass`: must be > 0");
        assert_eq!(InputError::new("f.ron", "empty").to_string(), "f.ron: empty");
    }
}
