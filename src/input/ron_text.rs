//! RON text to a typed value, with the parser's line and column in the error.

use ron::extensions::Extensions;
use serde::de::DeserializeOwned;

use super::InputError;

/// Parses `text` as RON; `origin` names it in errors (usually its path).
/// Value checks done while parsing (see `input/value_checks.rs`) come
/// back with the line and column of the offending value.
pub fn parse_ron<T: DeserializeOwned>(text: &str, origin: &str, extensions: Extensions) -> Result<T, InputError> {
    ron::Options::default()
        .with_default_extension(extensions)
        .from_str(text)
        .map_err(|e| InputError {
            origin: origin.to_owned(),
            location: Some((e.span.start.line, e.span.start.col)),
            message: e.code.to_string(),
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, serde::Deserialize)]
    #[expect(dead_code, reason = "only parsed")]
    struct Point {
        x: f32,
    }

    #[test]
    fn errors_carry_line_and_column() {
        let e = parse_ron::<Point>("(\n  x: \"one\",\n)", "p.ron", Extensions::empty()).unwrap_err();
        assert_eq!(e.location.map(|l| l.0), Some(2), "{e}");
        assert!(e.to_string().starts_with("p.ron:2:"), "{e}");
    }
}
