//! A tiny SVG text writer: elements with escaped attributes ([`crate::xml::escape`]), compact numbers.

use crate::geom::Point;
use crate::xml::escape;
use std::fmt::Write;

/// Writes numbers with a fixed number of decimals, trailing zeros dropped (`1.50` → `1.5`, `-0` → `0`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Num {
    decimals: usize,
}

impl Num {
    /// Enough decimals to resolve `resolution` (a positive length or angle), at most 9.
    pub(crate) fn resolving(resolution: f64) -> Num {
        let d = if resolution.is_finite() && resolution > 0.0 { (-resolution.log10()).ceil() } else { 3.0 };
        Num { decimals: d.clamp(0.0, 9.0) as usize }
    }
    pub(crate) const fn with_decimals(decimals: usize) -> Num {
        Num { decimals }
    }
    /// Appends `v` to `out`.
    pub(crate) fn put(&self, out: &mut String, v: f64) {
        match self.units(v) {
            Some(units) => self.put_units(out, v.is_sign_negative(), units),
            None => self.put_exact(out, v),
        }
    }

    /// `|v|` in units of the last decimal, rounded to the nearest, when that is surely what exact
    /// decimal rounding of `v` gives; `None` otherwise. Scaling by 10^decimals (exact as a double)
    /// rounds the product by at most half an ulp, a relative 2⁻⁵³, so the nearest integer is the
    /// exact product's unless the product lies within that error of a half: such near-ties (and exact
    /// ties, which [`Num::put_exact`] rounds its own way), huge and non-finite values return `None`.
    fn units(&self, v: f64) -> Option<u64> {
        let scale = *POWERS_OF_TEN.get(self.decimals)? as f64;
        let x = v.abs() * scale;
        // Below 2⁵² (so not a NaN either), every count of units is a whole double.
        if x.is_nan() || x >= 4_503_599_627_370_496.0 {
            return None;
        }
        let floor = x.floor();
        let fraction = x - floor;
        if (fraction - 0.5).abs() <= x * f64::EPSILON * 2.0 {
            return None;
        }
        Some(floor as u64 + u64::from(fraction > 0.5))
    }

    /// Appends the number `units` × 10^−decimals, negative when `negative` (unless it is zero), in
    /// the form [`Num::put_exact`] writes.
    fn put_units(&self, out: &mut String, negative: bool, units: u64) {
        if units == 0 {
            out.push('0');
            return;
        }
        // Written from the last digit back: a sign, 16 whole digits, a point and 15 decimals at most.
        let mut text = [0u8; 40];
        let mut at = text.len();
        let mut put = |byte: u8| {
            at -= 1;
            text[at] = byte;
        };
        let scale = POWERS_OF_TEN[self.decimals];
        let mut fraction = units % scale;
        if fraction != 0 {
            let mut digits = self.decimals;
            while fraction % 10 == 0 {
                fraction /= 10;
                digits -= 1;
            }
            for _ in 0..digits {
                put(b'0' + (fraction % 10) as u8);
                fraction /= 10;
            }
            put(b'.');
        }
        let mut whole = units / scale;
        loop {
            put(b'0' + (whole % 10) as u8);
            whole /= 10;
            if whole == 0 {
                break;
            }
        }
        if negative {
            put(b'-');
        }
        out.push_str(std::str::from_utf8(&text[at..]).unwrap_or_default());
    }

    /// Appends `v` through the standard library's exact formatting, trailing zeros dropped.
    fn put_exact(&self, out: &mut String, v: f64) {
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
    pub(crate) fn f(&self, v: f64) -> String {
        let mut s = String::new();
        self.put(&mut s, v);
        s
    }
    /// Appends `x,y`.
    pub(crate) fn put_point(&self, out: &mut String, p: Point) {
        self.put(out, p.x);
        out.push(',');
        self.put(out, p.y);
    }
    /// Points as an SVG `points` list: `x,y x,y ...`.
    pub(crate) fn points(&self, points: impl IntoIterator<Item = Point>) -> String {
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

/// 10⁰ to 10¹⁵: every one exact as a double, and any count of units below 2⁵² splits into whole
/// units and at most 15 decimals.
const POWERS_OF_TEN: [u64; 16] = {
    let mut powers = [1; 16];
    let mut i = 1;
    while i < 16 {
        powers[i] = powers[i - 1] * 10;
        i += 1;
    }
    powers
};

/// Appends what is written to it to a string, XML-escaped.
struct Escaping<'a>(&'a mut String);

impl Write for Escaping<'_> {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        self.0.push_str(&escape(s));
        Ok(())
    }
}

/// One element being written: `Element::new("circle").attr("r", 2).empty(&mut out)`.
#[must_use = "an element is only written by empty, open or text"]
pub(crate) struct Element {
    tag: &'static str,
    head: String,
}

impl Element {
    pub(crate) fn new(tag: &'static str) -> Element {
        let mut head = String::with_capacity(64);
        head.push('<');
        head.push_str(tag);
        Element { tag, head }
    }
    /// Adds `name="value"`, escaping the value.
    pub(crate) fn attr(mut self, name: &str, value: impl std::fmt::Display) -> Element {
        self.head.push(' ');
        self.head.push_str(name);
        self.head.push_str("=\"");
        let _ = write!(Escaping(&mut self.head), "{value}");
        self.head.push('"');
        self
    }
    /// Adds the attribute only when `value` is `Some`.
    pub(crate) fn attr_opt(self, name: &str, value: Option<impl std::fmt::Display>) -> Element {
        match value {
            Some(v) => self.attr(name, v),
            None => self,
        }
    }
    /// Writes `<tag .../>`.
    pub(crate) fn empty(self, out: &mut String) {
        out.push_str(&self.head);
        out.push_str("/>\n");
    }
    /// Writes `<tag ...>`; the caller writes the children and [`close`]s it.
    pub(crate) fn open(self, out: &mut String) {
        out.push_str(&self.head);
        out.push_str(">\n");
    }
    /// Writes `<tag ...>text</tag>` with the text escaped.
    pub(crate) fn text(self, text: &str, out: &mut String) {
        out.push_str(&self.head);
        out.push('>');
        out.push_str(&escape(text));
        let _ = writeln!(out, "</{}>", self.tag);
    }
}

/// Writes `</tag>`.
pub(crate) fn close(out: &mut String, tag: &str) {
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

    /// The quick way of writing a number against the standard library's exact formatting, on values
    /// of every size and sign and on values at and near the halves between two roundings.
    #[test]
    fn quick_numbers_are_the_exact_ones() {
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = move || {
            // xorshift64*
            state ^= state >> 12;
            state ^= state << 25;
            state ^= state >> 27;
            state.wrapping_mul(0x2545_f491_4f6c_dd1d)
        };
        let mut quick_count = 0;
        for decimals in 0..=9 {
            let n = Num::with_decimals(decimals);
            let unit = 10f64.powi(-(decimals as i32));
            for i in 0..20_000 {
                let r = next();
                let magnitude = 10f64.powi((r % 13) as i32 - 6);
                let mut v = (next() >> 11) as f64 / (1u64 << 53) as f64 * magnitude;
                if i % 3 == 0 {
                    // A half between two roundings, and its neighbours a few ulps away.
                    let half = ((next() % 2_000_000) as f64 + 0.5) * unit;
                    v = f64::from_bits(half.to_bits().wrapping_add(next() % 7).wrapping_sub(3));
                }
                if r & (1 << 40) != 0 {
                    v = -v;
                }
                let (mut quick, mut exact) = (String::new(), String::new());
                n.put(&mut quick, v);
                n.put_exact(&mut exact, v);
                assert_eq!(quick, exact, "{v:e} with {decimals} decimals");
                quick_count += usize::from(n.units(v).is_some());
            }
        }
        // Most values take the quick way (the test would pass trivially if none did).
        assert!(quick_count > 100_000, "{quick_count}");
        for v in [0.0, -0.0, 0.5, 1.5, 2.5, -0.5, 1e300, -1e300, f64::MAX, f64::MIN_POSITIVE, 4.5e15, f64::NAN] {
            for decimals in [0, 3, 9] {
                let n = Num::with_decimals(decimals);
                let (mut quick, mut exact) = (String::new(), String::new());
                n.put(&mut quick, v);
                n.put_exact(&mut exact, v);
                assert_eq!(quick, exact, "{v:e} with {decimals} decimals");
            }
        }
    }

    #[test]
    fn escaping() {
        let mut out = String::new();
        Element::new("text").attr("x", 1).text("<&>", &mut out);
        assert_eq!(out, "<text x=\"1\">&lt;&amp;&gt;</text>\n");
        out.clear();
        Element::new("g").attr("id", "a<\"b\">&é").attr("n", 1.5).empty(&mut out);
        assert_eq!(out, "<g id=\"a&lt;&quot;b&quot;&gt;&amp;é\" n=\"1.5\"/>\n");
    }
}
