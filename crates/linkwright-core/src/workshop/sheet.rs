//! The workshop's assembly sheet: every bolt's stack side by side (what it passes through, from the
//! head to the nut, to scale), the layers of each face, and the numbered steps.

use super::report::{number, Workshop};
use crate::fab::Face;
use std::fmt::Write as _;

/// Width of one bolt's column, mm on the sheet.
const COLUMN: f64 = 62.0;
/// The tallest stack is drawn this tall, mm on the sheet (never larger than 2:1).
const TALLEST: f64 = 110.0;
/// Height of a line of text, mm on the sheet.
const LINE: f64 = 6.0;

/// The sheet as SVG, millimetres.
pub(crate) fn assembly_svg(w: &Workshop) -> String {
    let tallest = w.bolts.iter().map(|b| b.stack.iter().map(|s| s.thickness_mm).sum::<f64>()).fold(1.0, f64::max);
    let scale = (TALLEST / tallest).min(2.0);
    let columns_w = COLUMN * w.bolts.len().max(1) as f64;
    let stacks_top = 24.0;
    let stacks_bottom = stacks_top + TALLEST + 30.0;
    let mut lines: Vec<(bool, String)> = Vec::new();
    lines.push((true, "Layers".into()));
    for l in &w.layers {
        lines.push((
            false,
            format!(
                "{} face, layer {} ({} mm thick, {:.1} mm from the face): {}",
                if l.face == Face::Front { "front" } else { "back" },
                l.layer,
                number(l.thickness_mm),
                l.from_face_mm,
                l.parts.join(", ")
            ),
        ));
    }
    lines.push((true, "Assembly".into()));
    lines.extend(w.steps.iter().enumerate().map(|(k, s)| (false, format!("{}. {s}", k + 1))));
    if !w.notes.is_empty() {
        lines.push((true, "Notes".into()));
        lines.extend(w.notes.iter().map(|n| (false, format!("• {n}"))));
    }
    let longest = lines.iter().map(|(_, l)| l.chars().count()).max().unwrap_or(0) as f64;
    let width = (columns_w + 20.0).max(20.0 + 2.1 * longest).max(300.0);
    let height = stacks_bottom + LINE * (lines.len() as f64 + 2.0);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width:.1}mm\" height=\"{height:.1}mm\" viewBox=\"0 0 {width:.2} {height:.2}\">"
    );
    s.push_str(
        "<style>text{font:4px sans-serif;fill:#222}.t{font-weight:bold;font-size:5px}.s{font-size:3px}rect{stroke:#333;stroke-width:0.15}</style>\n",
    );
    let _ = writeln!(
        s,
        "<text class=\"t\" x=\"10\" y=\"10\">{}: full size in {}, {} bolts, safety factor {} (each bolt's stack, head at the bottom, ×{:.2})</text>",
        esc(&w.scene),
        w.material.id(),
        w.bolt.size,
        w.settings.safety_factor,
        scale
    );
    for (c, b) in w.bolts.iter().enumerate() {
        let spec = b.bolt.spec();
        let x = 10.0 + COLUMN * c as f64;
        let mut y = stacks_top + TALLEST + 4.0;
        // The head, then every item upwards, then the nut.
        let _ = writeln!(
            s,
            "<rect x=\"{:.2}\" y=\"{:.2}\" width=\"14\" height=\"{:.2}\" fill=\"#555\"/>",
            x + 3.0,
            y,
            (spec.head_mm * scale).max(0.5)
        );
        for item in &b.stack {
            let h = (item.thickness_mm * scale).max(0.4);
            y -= h;
            let (fill, inset) = match item.item {
                "washer" => ("#999", 2.0),
                "spacer" => ("#cde", 4.0),
                "block" => ("#c9a66b", 0.0),
                "body" => ("#f4d58d", 0.0),
                _ => ("#e76f51", 0.0),
            };
            let _ = writeln!(
                s,
                "<rect x=\"{:.2}\" y=\"{:.2}\" width=\"{:.2}\" height=\"{h:.2}\" fill=\"{fill}\"/>",
                x + inset,
                y,
                20.0 - 2.0 * inset
            );
            if let Some(name) = &item.name {
                let _ = writeln!(
                    s,
                    "<text class=\"s\" x=\"{:.2}\" y=\"{:.2}\">{} {} mm</text>",
                    x + 21.0,
                    y + 0.5 * h + 1.0,
                    esc(name),
                    number(item.thickness_mm)
                );
            }
        }
        let nut = (spec.nut_mm * scale).max(0.5);
        let _ = writeln!(
            s,
            "<rect x=\"{:.2}\" y=\"{:.2}\" width=\"14\" height=\"{nut:.2}\" fill=\"#555\"/>",
            x + 3.0,
            y - nut
        );
        let _ = writeln!(
            s,
            "<text x=\"{x:.2}\" y=\"{:.2}\">{}{}</text><text class=\"s\" x=\"{x:.2}\" y=\"{:.2}\">{} × {:.0}, {} face</text>",
            stacks_top + TALLEST + 4.0 + spec.head_mm * scale + 5.0,
            esc(&b.at),
            if b.count > 1 { format!(" (×{})", b.count) } else { String::new() },
            stacks_top + TALLEST + 4.0 + spec.head_mm * scale + 9.0,
            b.bolt,
            b.length_mm,
            if b.face == Face::Front { "front" } else { "back" }
        );
    }
    let mut y = stacks_bottom + LINE;
    for (title, line) in &lines {
        let _ =
            writeln!(s, "<text{} x=\"10\" y=\"{y:.2}\">{}</text>", if *title { " class=\"t\"" } else { "" }, esc(line));
        y += LINE;
    }
    s.push_str("</svg>\n");
    s
}

fn esc(s: &str) -> std::borrow::Cow<'_, str> {
    crate::xml::escape(s)
}
