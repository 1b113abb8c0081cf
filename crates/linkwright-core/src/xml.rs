//! XML text: what the SVG pictures, the assembly sheet and the 3MF and SVG part files share.

use std::borrow::Cow;

/// Escapes text for XML content and attribute values (`&`, `<`, `>`, `"`, `'`), and drops the
/// characters XML 1.0 forbids even escaped (the C0 controls but tab, line feed and carriage return,
/// and U+FFFE, U+FFFF), so a name holding them still gives a well-formed document.
pub(crate) fn escape(text: &str) -> Cow<'_, str> {
    // A byte scan: every character escaped or dropped is ASCII or starts with the byte 0xEF (U+F000 to
    // U+FFFF), and UTF-8 never uses ASCII bytes inside others.
    let special = |b: u8| {
        matches!(b, b'&' | b'<' | b'>' | b'"' | b'\'' | 0xEF) || (b < 0x20 && !matches!(b, b'\t' | b'\n' | b'\r'))
    };
    if !text.bytes().any(special) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if !allowed_in_xml(c) => {}
            c => out.push(c),
        }
    }
    Cow::Owned(out)
}

/// Whether XML 1.0 allows `c` in a document (its production `Char`; Rust strings hold no surrogates).
fn allowed_in_xml(c: char) -> bool {
    !matches!(c, '\u{0}'..='\u{8}' | '\u{b}' | '\u{c}' | '\u{e}'..='\u{1f}' | '\u{fffe}' | '\u{ffff}')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escaping() {
        assert_eq!(escape("a<b & 'c' \"d\">"), "a&lt;b &amp; &apos;c&apos; &quot;d&quot;&gt;");
        assert!(matches!(escape("plain"), Cow::Borrowed(_)));
        assert_eq!(escape("a\0b\u{1}\u{1b}c\td\u{fffe}"), "abc\td");
    }
}
