//! Text on its way to a terminal. Names, keys and values quoted from files reach stdout and stderr,
//! where a control character (an escape sequence that clears the screen or moves the cursor, a
//! carriage return over a line already printed) would be obeyed: every one is shown escaped instead.

/// `text` with every control character escaped as Rust writes it (`\u{1b}`, `\n`, `\r`), so one
/// quoted field or message stays on its own line and moves nothing.
pub(crate) fn escaped(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if c.is_control() {
            out.extend(c.escape_debug());
        } else {
            out.push(c);
        }
    }
    out
}

/// `text` escaped line by line: the line breaks between the lines the CLI writes are kept, every
/// other control character is escaped ([`escaped`]).
pub(crate) fn lines(text: &str) -> String {
    text.split('\n').map(escaped).collect::<Vec<_>>().join("\n")
}

/// Prints `text` on stdout, with a line break, escaped ([`lines`]).
pub(crate) fn say(text: &str) {
    println!("{}", lines(text));
}

/// Prints `text` on stderr, with a line break, escaped ([`lines`]).
pub(crate) fn warn(text: &str) {
    eprintln!("{}", lines(text));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_characters_are_shown_not_obeyed() {
        assert_eq!(escaped("lid\u{1b}[2J\r\n\u{7}é"), "lid\\u{1b}[2J\\r\\n\\u{7}é");
        assert_eq!(lines("error: a\u{1b}[1A\nerror: b"), "error: a\\u{1b}[1A\nerror: b");
        assert_eq!(lines("plain text, 30°"), "plain text, 30°");
    }
}
