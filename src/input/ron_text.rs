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
        .map_err(|e| {
            let (line, column) = (e.span.start.line, e.span.start.col);
            let field = field_before(text, line, column);
            let code = plain(&e.code.to_string(), char_at(text, line, column), field.is_some());
            let message = match (
                code.strip_prefix("field `").and_then(|rest| rest.split_once("`: ")),
                field,
            ) {
                // Our own checks name their field already; a list's item
                // (`events[0]`) is named with the field the error is in.
                (Some((item, rest)), Some(field)) if item.ends_with(']') => {
                    format!("field `{item}.{field}`: {rest}")
                }
                (None, Some(field)) => format!("field `{field}`: {code}"),
                _ => code,
            };
            InputError {
                origin: origin.to_owned(),
                location: Some((line, column)),
                message,
            }
        })
}

/// The character at `line`:`column` (1-based) of `text`, if any.
fn char_at(text: &str, line: usize, column: usize) -> Option<char> {
    text.lines()
        .nth(line.checked_sub(1)?)?
        .chars()
        .nth(column.checked_sub(1)?)
}

/// RON's words for a required field a struct lacks, "Unexpected missing
/// field named `f` in `S`" (which read as though the field should not be
/// there), as "missing field `f` (`S` needs it)"; `None` for other messages.
fn missing(code: &str) -> Option<String> {
    const MISSING: &str = "Unexpected missing field named ";
    let start = code.find(MISSING)?;
    let rest = &code[start + MISSING.len()..];
    let (field, outer) = match rest.split_once(" in ") {
        Some((field, outer)) => (field, Some(outer)),
        None => (rest, None),
    };
    let said = match outer {
        Some(outer) => format!("missing field {field} ({outer} needs it)"),
        None => format!("missing field {field}"),
    };
    Some(format!("{}{said}", &code[..start]))
}

/// RON's message `code` in words that point at the mistake and advise
/// only what the file may hold; `in_value`: the error is in a field's value
/// on the line (`field: value`), else between fields or items. A second
/// value where one ends (`Swept | Discrete`, `Swept()`) is named as such, a
/// comma missing between fields as that; a number where a name belongs is
/// not advised to be written as a raw identifier (`r#3`), which no file
/// takes; a missing field is named with what needs it ([`missing`]).
fn plain(code: &str, at: Option<char>, in_value: bool) -> String {
    const RAW: &str = "Found invalid std identifier \"";
    if let Some(said) = missing(code) {
        return said;
    }
    if code.ends_with("Expected comma") {
        let found = at.map_or_else(|| "the end of the text".to_owned(), |c| format!("`{c}`"));
        let said = if in_value {
            format!("expected `,` or a closing bracket after the value, found {found} (a field holds one value)")
        } else {
            format!("expected `,` or a closing bracket, found {found} (is a `,` missing before it?)")
        };
        return code.replace("Expected comma", &said);
    }
    if let Some(start) = code.find(RAW) {
        let name_start = start + RAW.len();
        if let Some(name_len) = code[name_start..].find('"') {
            let name = &code[name_start..name_start + name_len];
            let advice = format!(", try the raw identifier `r#{name}` instead");
            let rest = code[name_start + name_len + 1..].replacen(&advice, "", 1);
            let said = if in_value {
                format!("`{name}` is not a name this field takes")
            } else {
                format!("`{name}` is not a name (letters, digits and `_`, not starting with a digit)")
            };
            return format!("{}{said}{rest}", &code[..start]);
        }
    }
    code.to_owned()
}

/// The field whose value holds `line`:`column` (1-based) of `text`, where
/// the value follows `field:` on that line: RON's own messages ("Integer is
/// out of bounds") do not say which field they mean.
fn field_before(text: &str, line: usize, column: usize) -> Option<&str> {
    let line_text = text.lines().nth(line.checked_sub(1)?)?;
    let (end, at) = line_text.char_indices().nth(column.checked_sub(1)?)?;
    // At a value (not at the end of a list or struct: a field missing).
    if ")]},".contains(at) {
        return None;
    }
    // Back over the value's start (a sign, digits), then `field:`.
    let before = line_text[..end]
        .trim_end()
        .trim_end_matches(|c: char| c.is_ascii_alphanumeric() || "._+-\"".contains(c))
        .trim_end()
        .strip_suffix(':')?
        .trim_end();
    let is_name = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let field = &before[before.rfind(|c: char| !is_name(c)).map_or(0, |at| at + 1)..];
    field
        .starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
        .then_some(field)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, serde::Deserialize)]
    #[expect(dead_code, reason = "only parsed")]
    struct Point {
        x: f32,
    }

    #[derive(Debug, serde::Deserialize)]
    #[expect(dead_code, reason = "only parsed")]
    enum Action {
        Launch { count: u32, mass: f32 },
    }

    #[test]
    fn a_missing_field_is_named_with_the_struct_that_needs_it() {
        let e = parse_ron::<Vec<Action>>("[Launch(count: 2)]", "a.ron", Extensions::empty()).unwrap_err();
        assert_eq!(e.message, "missing field `mass` (`Launch` needs it)", "{e}");
        let e = parse_ron::<Point>("()", "a.ron", Extensions::empty()).unwrap_err();
        assert!(e.message.starts_with("missing field `x`"), "{e}");
    }

    #[test]
    fn errors_name_the_field_whose_value_is_wrong() {
        for (text, field) in [
            ("[Launch(count: -1, mass: 1)]", Some("count")),
            ("[Launch(count: 99999999999, mass: 1)]", Some("count")),
            ("[Launch(count: 2,\n  mass: \"heavy\")]", Some("mass")),
            ("[Launch(count: 2, weight: 1)]", None),
        ] {
            let e = parse_ron::<Vec<Action>>(text, "a.ron", Extensions::empty()).unwrap_err();
            match field {
                Some(field) => assert!(e.message.starts_with(&format!("field `{field}`: ")), "{text}: {e}"),
                None => assert!(!e.message.starts_with("field"), "{text}: {e}"),
            }
        }
        // Columns count characters.
        assert_eq!(field_before("(é: 1, x: -1)", 1, 12), Some("x"));
        assert_eq!(field_before("(x: 1)", 9, 1), None);
    }

    #[derive(Debug, serde::Deserialize)]
    enum Detection {
        Swept,
        Discrete,
    }

    #[derive(Debug, serde::Deserialize)]
    #[expect(dead_code, reason = "only parsed")]
    struct Settings {
        detection: Detection,
        #[serde(default)]
        events: Vec<Settings>,
    }

    #[test]
    fn syntax_errors_name_the_field_and_advise_only_what_is_valid() {
        for (text, expected) in [
            (
                "(detection: Swept | Discrete)",
                "1:19: field `detection`: expected `,` or a closing bracket after the value, found `|`",
            ),
            (
                "(detection: Swept())",
                "1:18: field `detection`: expected `,` or a closing bracket after the value, found `(`",
            ),
            (
                "(detection: 3)",
                "1:13: field `detection`: `3` is not a name this field takes",
            ),
        ] {
            let e = parse_ron::<Settings>(text, "s.ron", Extensions::empty()).unwrap_err();
            assert!(e.to_string().starts_with(&format!("s.ron:{expected}")), "{text}: {e}");
            assert!(!e.to_string().contains("r#"), "{e}");
        }
        // Inside a list's item, the item and the field: as `Listed` says
        // an item's error (`field `events[0]`: …`).
        let listed = "field `events[0]`: Expected comma";
        assert_eq!(
            plain(listed, Some('('), true),
            "field `events[0]`: expected `,` or a closing bracket after the value, found `(` (a field holds one value)"
        );
        // A comma missing between fields on two lines, and a name that is
        // none: no advice about one value.
        let e =
            parse_ron::<Settings>("(\n  detection: Swept\n  events: [])", "s.ron", Extensions::empty()).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("s.ron:3:3: expected `,` or a closing bracket, found `e` (is a `,` missing before it?)"),
            "{e}"
        );
        assert_eq!(
            plain(
                "Found invalid std identifier \"my-field\", try the raw identifier `r#my-field` instead",
                None,
                false
            ),
            "`my-field` is not a name (letters, digits and `_`, not starting with a digit)"
        );
    }

    #[test]
    fn errors_carry_line_and_column() {
        let e = parse_ron::<Point>("(\n  x: \"one\",\n)", "p.ron", Extensions::empty()).unwrap_err();
        assert_eq!(e.location.map(|l| l.0), Some(2), "{e}");
        assert!(e.to_string().starts_with("p.ron:2:"), "{e}");
    }
}
