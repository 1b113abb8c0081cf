//! A tiny SVG text writer: elements with escaped attributes, compact numbers, XML escaping.

use crate::geom::Point;
use std::borrow::Cow;
use std::fmt::Write;

/// Escapes text for XML content and attribute values (`&`, `<`, `>`, `"`, `'`).
pub fn escape(text: &str) -> Cow<'_, str> {
    if !text.contains(['&', '<', '>', '"', '\'']) {
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
            c => out.push(c),
        }
    }
    Cow::Owned(out)
}

/// Writes numbers with a fixed number of decimals, trailing zeros dropped (`1.50` → `1.5`, `-0` → `0`).
#[derive(Clone, Copy, Debug)]
pub struct Num {
    decimals: usize,
}

impl Num {
    /// Enough decimals to resolve `resolution` (a positive length or angle), at most 9.
    pub fn resolving(resolution: f64) -> Num {
        let d = if resolution.is_finite() && resolution > 0.0 { (-resolution.log10()).ceil() } else { 3.0 };
        Num { decimals: d.clamp(0.0, 9.0) as usize }
    }
    pub const fn with_decimals(decimals: usize) -> Num {
        Num { decimals }
    }
    /// Appends `v` to `out`.
    pub fn put(&self, out: &mut String, v: f64) {
        let start = out.len();
        let _ = write!(out, "{:.*}", self.decimals, v);
        if self.decimals > 0 {
            let trimmed = out[start..].trim_end_matches('0').trim_end_matches('.').len();
            out.truncate(start + trimmed);
        }
        if &out[start..] == "-0" {
            out.truncate(start);
            out.push('0');
        }
    }
    /// `v` as text.
    pub fn f(&self, v: f64) -> String {
        let mut s = String::new();
        self.put(&mut s, v);
        s
    }
    /// Appends `x,y`.
    pub fn put_point(&self, out: &mut String, p: Point) {
        self.put(out, p.x);
        out.push(',');
        self.put(out, p.y);
    }
    /// Points as an SVG `points` list: `x,y x,y ...`.
    pub fn points(&self, points: impl IntoIterator<Item = Point>) -> String {
        let mut s = String::new();
        for (i, p) in points.into_iter().enumerate() {
            if i > 0 {
                s.push(' ');
            }
            self.put_point(&mut s, p);
        }
        s
    }
}

/// One element being written: `Element::new("circle").attr("r", 2).empty(&mut out)`.
#[must_use = "an element is only written by empty, open or text"]
pub struct Element {
    tag: &'static str,
    head: String,
}

impl Element {
    pub fn new(tag: &'static str) -> Element {
        let mut head = String::with_capacity(64);
        head.push('<');
        head.push_str(tag);
        Element { tag, head }
    }
    /// Adds `name="value"`, escaping the value.
    pub fn attr(mut self, name: &str, value: impl std::fmt::Display) -> Element {
        let value = value.to_string();
        let _ = write!(self.head, " {name}=\"{}\"", escape(&value));
        self
    }
    /// Adds the attribute only when `value` is `Some`.
    pub fn attr_opt(self, name: &str, value: Option<impl std::fmt::Display>) -> Element {
        match value {
            Some(v) => self.attr(name, v),
            None => self,
        }
    }
    /// Writes `<tag .../>`.
    pub fn empty(self, out: &mut String) {
        out.push_str(&self.head);
        out.push_str("/>\n");
    }
    /// Writes `<tag ...>`; the caller writes the children and [`close`]s it.
    pub fn open(self, out: &mut String) {
        out.push_str(&self.head);
        out.push_str(">\n");
    }
    /// Writes `<tag ...>text</tag>` with the text escaped.
    pub fn text(self, text: &str, out: &mut String) {
        out.push_str(&self.head);
        out.push('>');
        out.push_str(&escape(text));
        let _ = writeln!(out, "</{}>", self.tag);
    }
}

/// Writes `</tag>`.
pub fn close(out: &mut String, tag: &str) {
    let _ = writeln!(out, "</{tag}>");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_compact() {
        let n = Num::with_decimals(3);
        assert_eq!(n.f(1.5), "1.5");
        assert_eq!(n.f(2.0), "2");
        assert_eq!(n.f(-0.0001), "0");
        assert_eq!(n.f(-12.34567), "-12.346");
        assert_eq!(Num::with_decimals(0).f(120.0), "120");
        assert_eq!(Num::resolving(0.025).f(1.23456), "1.23");
    }

    #[test]
    fn escaping() {
        assert_eq!(escape("a<b & 'c' \"d\">"), "a&lt;b &amp; &apos;c&apos; &quot;d&quot;&gt;");
        assert!(matches!(escape("plain"), Cow::Borrowed(_)));
        let mut out = String::new();
        Element::new("text").attr("x", 1).text("<&>", &mut out);
        assert_eq!(out, "<text x=\"1\">&lt;&amp;&gt;</text>\n");
    }
}
