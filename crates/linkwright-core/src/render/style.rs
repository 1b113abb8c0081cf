//! Sizes and colours of the drawings, every size a fraction of the scene's scale so that any drawing
//! unit works.

use super::svg::Num;
use std::fmt::Write;

/// Colours of the moving bodies, cycled (none is the region's blue or the avoid regions' red).
const BODY_COLOURS: [&str; 7] = ["#e67e22", "#2e9e4f", "#8e5cc2", "#a0522d", "#d6489b", "#1aa3b8", "#a6a61e"];
/// Colours of the joint paths, cycled.
const PATH_COLOURS: [&str; 8] =
    ["#1b9e77", "#d95f02", "#7570b3", "#e7298a", "#66a61e", "#c79a00", "#a6761d", "#555555"];

/// Every size used in a drawing, in drawing units.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Style {
    /// Thin strokes: outlines, joint paths.
    pub thin: f64,
    /// Width of a binary link.
    pub link: f64,
    /// Radius of a joint circle.
    pub joint: f64,
    /// Font size of joint labels.
    pub small_font: f64,
    /// Font size of pose numbers and the legend.
    pub font: f64,
    /// Font size of the title.
    pub title_font: f64,
    /// Empty space around the drawing.
    pub margin: f64,
    /// Length of a dash.
    pub dash: f64,
}

impl Style {
    /// Sizes for a scene whose drawn extent has diagonal `scale`.
    pub(crate) fn for_scale(scale: f64) -> Style {
        let s = if scale.is_finite() && scale > 0.0 { scale } else { 1.0 };
        Style {
            thin: 0.0022 * s,
            link: 0.011 * s,
            joint: 0.0085 * s,
            small_font: 0.019 * s,
            font: 0.023 * s,
            title_font: 0.032 * s,
            margin: 0.045 * s,
            dash: 0.012 * s,
        }
    }

    pub(crate) fn body_colour(body: usize) -> &'static str {
        BODY_COLOURS[body % BODY_COLOURS.len()]
    }
    /// The body's colour darkened, for text that must read on the body's own fill.
    pub(crate) fn body_text_colour(body: usize) -> String {
        let hex = Self::body_colour(body);
        let channel =
            |i: usize| u8::from_str_radix(&hex[i..i + 2], 16).map_or(0, |c| (f64::from(c) * 0.6).round() as u8);
        format!("#{:02x}{:02x}{:02x}", channel(1), channel(3), channel(5))
    }
    pub(crate) fn path_colour(joint: usize) -> &'static str {
        PATH_COLOURS[joint % PATH_COLOURS.len()]
    }

    /// The `<style>` sheet shared by both drawings (its class names are what the tests count). Lengths
    /// are in drawing units, except text, which is written in pixels (`pixels` per drawing unit).
    pub(crate) fn css(&self, num: &Num, pixels: f64) -> String {
        // In SVG a CSS px is one user unit of the element's coordinate system; font sizes need the unit.
        let f = |v: f64| format!("{}px", num.f(v));
        let px = |v: f64| format!("{}px", Num::with_decimals(2).f(v * pixels));
        let (t, l, j, d) = (self.thin, self.link, self.joint, self.dash);
        let mut css = String::new();
        let mut rule = |selector: &str, body: String| {
            let _ = writeln!(css, "{selector}{{{body}}}");
        };
        rule(".fixed", format!("fill:#c4c4c4;stroke:#6b6b6b;stroke-width:{}", f(t)));
        rule(
            ".region",
            format!(
                "fill:#2b6cb0;fill-opacity:.04;stroke:#2b6cb0;stroke-width:{};stroke-dasharray:{},{}",
                f(t * 1.3),
                num.f(d),
                num.f(d * 0.6)
            ),
        );
        rule(".avoid", format!("fill:url(#hatch);stroke:#d62728;stroke-width:{}", f(t)));
        rule(".pose", format!("fill-opacity:.1;stroke-opacity:.75;stroke-width:{}", f(t)));
        rule(
            ".reached",
            format!("fill:none;stroke-width:{};stroke-dasharray:{},{}", f(t * 1.4), num.f(d * 0.7), num.f(d * 0.45)),
        );
        rule(".body", format!("fill-opacity:.8;stroke:#333;stroke-width:{}", f(t)));
        rule(
            ".bracket",
            format!(
                "fill-opacity:.3;stroke-opacity:.9;stroke-width:{};stroke-linecap:round;stroke-linejoin:round",
                f(l * 0.6)
            ),
        );
        rule(
            ".link",
            format!(
                "fill:none;stroke:#3d4a5c;stroke-opacity:.9;stroke-width:{};stroke-linecap:round;stroke-linejoin:round",
                f(l)
            ),
        );
        rule(
            ".ternary",
            format!(
                "fill:#3d4a5c;fill-opacity:.5;stroke:#3d4a5c;stroke-opacity:.9;stroke-width:{};stroke-linejoin:round",
                f(l * 0.6)
            ),
        );
        rule(".crank", "stroke:#b03a2e".to_string());
        rule(".path", format!("fill:none;stroke-opacity:.85;stroke-width:{};stroke-linejoin:round", f(t)));
        // A path scene's curve: drawn, wide and pale under the tracer's own, thin and dark.
        rule(
            ".drawn-path",
            format!(
                "fill:none;stroke:#e3a21a;stroke-opacity:.55;stroke-width:{};stroke-linecap:round;stroke-linejoin:round",
                f(t * 5.0)
            ),
        );
        rule(".traced-path", format!("fill:none;stroke:#7a4a00;stroke-width:{};stroke-linejoin:round", f(t * 1.3)));
        rule(".guide", format!("stroke:#7a7a7a;stroke-width:{};stroke-linecap:round", f(j * 2.6)));
        rule(".guide-core", format!("stroke:#f2f2f2;stroke-width:{};stroke-linecap:round", f(j * 1.8)));
        rule(".slider", format!("fill:#d9d9d9;stroke:#333;stroke-width:{}", f(t)));
        rule(".ground", format!("fill:#d0d0d0;stroke:#333;stroke-width:{};stroke-linejoin:round", f(t)));
        rule(".ground-line", format!("fill:none;stroke:#333;stroke-width:{};stroke-linecap:round", f(t)));
        rule(".joint", format!("fill:#fff;stroke:#222;stroke-width:{}", f(t * 1.3)));
        rule(
            "text",
            format!(
                "font-family:sans-serif;font-size:{};fill:#222;paint-order:stroke;stroke:#fff;stroke-width:{};stroke-linejoin:round",
                px(self.font),
                px(self.font * 0.2)
            ),
        );
        rule(".joint-label", format!("font-size:{}", px(self.small_font)));
        rule(".pose-label", "font-weight:bold;text-anchor:middle".to_string());
        rule(".title", format!("font-size:{};font-weight:bold", px(self.title_font)));
        rule(".legend", "stroke:none".to_string());
        css
    }
}
