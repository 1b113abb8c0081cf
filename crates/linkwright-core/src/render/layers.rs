//! Drawing layers both pictures share: the document frame, the scene's fixed parts, the input poses,
//! the joint paths, the slider guide, the ground pivots, the labels and the title.
//!
//! World layers are written inside a group that flips y (`scale(1,-1)`), so their coordinates are world
//! coordinates, y up; text is written outside it at `(x, −y)`, so it stays upright.

use super::sheet::{Sheet, SCREEN};
use super::style::Style;
use super::svg::{close, Element};
use crate::geom::{Point, Polygon, Vec2};

/// Opens the document: root, title, style sheet, hatch pattern, white background.
pub(crate) fn open_document(sheet: &Sheet, out: &mut String) {
    let (w, h) = sheet.size();
    let n = &sheet.num;
    out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    Element::new("svg")
        .attr("xmlns", "http://www.w3.org/2000/svg")
        .attr("viewBox", format!("0 0 {} {}", SCREEN.f(w), SCREEN.f(h)))
        .attr("width", w.round())
        .attr("height", h.round())
        .open(out);
    let title = sheet.title();
    Element::new("title").text(&format!("{}: {}", title.name, title.subtitle), out);
    Element::new("style").text(&sheet.style.css(n, sheet.pixels_per_unit()), out);
    Element::new("defs").open(out);
    let hatch = sheet.style.dash * 0.8;
    Element::new("pattern")
        .attr("id", "hatch")
        .attr("patternUnits", "userSpaceOnUse")
        .attr("width", n.f(hatch))
        .attr("height", n.f(hatch))
        .attr("patternTransform", "rotate(45)")
        .open(out);
    Element::new("rect")
        .attr("width", n.f(hatch))
        .attr("height", n.f(hatch))
        .attr("fill", "#d62728")
        .attr("fill-opacity", ".08")
        .empty(out);
    Element::new("line")
        .attr("x1", n.f(hatch / 2.0))
        .attr("y1", 0)
        .attr("x2", n.f(hatch / 2.0))
        .attr("y2", n.f(hatch))
        .attr("stroke", "#d62728")
        .attr("stroke-opacity", ".6")
        .attr("stroke-width", n.f(sheet.style.thin))
        .empty(out);
    close(out, "pattern");
    close(out, "defs");
    Element::new("rect").attr("width", "100%").attr("height", "100%").attr("fill", "#fff").empty(out);
}

/// Opens the group the world layers go in: world coordinates, y up.
pub(crate) fn open_world(sheet: &Sheet, out: &mut String) {
    Element::new("g").attr("transform", sheet.world_transform()).open(out);
}

/// Writes a polygon with the given class and optional colour.
pub(crate) fn polygon(sheet: &Sheet, poly: &Polygon, class: &str, colour: Option<&str>, out: &mut String) {
    Element::new("polygon")
        .attr("class", class)
        .attr_opt("fill", colour)
        .attr_opt("stroke", colour)
        .attr("points", sheet.num.points(poly.vertices().iter().copied()))
        .empty(out);
}

/// The linkage region (dashed), the avoid regions (hatched) and the fixed bodies (grey).
pub(crate) fn backdrop(sheet: &Sheet, out: &mut String) {
    let problem = sheet.input.problem;
    polygon(sheet, &problem.region, "region", None, out);
    for a in &problem.avoid {
        polygon(sheet, a, "avoid", None, out);
    }
    for f in &problem.fixed {
        polygon(sheet, f, "fixed", None, out);
    }
}

/// Every moving body at each of its input poses, translucent (numbers come with [`pose_numbers`]).
pub(crate) fn onion_skins(sheet: &Sheet, out: &mut String) {
    for (b, body) in sheet.input.problem.bodies.iter().enumerate() {
        for pose in &body.poses {
            polygon(sheet, &body.outline.transformed(pose), "pose", Some(Style::body_colour(b)), out);
        }
    }
}

/// One thin polyline per moving joint through the sampled configurations.
pub(crate) fn joint_paths(sheet: &Sheet, out: &mut String) {
    if sheet.input.trace.is_empty() {
        return;
    }
    for j in sheet.moving_joints() {
        Element::new("polyline")
            .attr("class", "path")
            .attr("stroke", Style::path_colour(j))
            .attr("points", sheet.num.points(sheet.rows.iter().map(|&s| sheet.row(s)[j])))
            .empty(out);
    }
}

/// A path scene's drawn curve, and the curve its tracer traces through the sampled configurations.
pub(crate) fn drawn_and_traced_path(sheet: &Sheet, out: &mut String) {
    for (b, body) in sheet.input.problem.bodies.iter().enumerate() {
        let Some(path) = &body.path else { continue };
        Element::new(if path.closed { "polygon" } else { "polyline" })
            .attr("class", "drawn-path")
            .attr("points", sheet.num.points(path.points.iter().copied()))
            .empty(out);
        if sheet.input.trace.is_empty() {
            continue;
        }
        let traced = sheet.rows.iter().map(|&s| sheet.body_pose(b, sheet.row(s)).apply(path.tracer));
        Element::new("polyline").attr("class", "traced-path").attr("points", sheet.num.points(traced)).empty(out);
    }
}

/// The slot the slider joint runs in, between its extreme positions.
pub(crate) fn slider_guide(sheet: &Sheet, out: &mut String) {
    let Some((a, b)) = sheet.guide() else { return };
    for class in ["guide", "guide-core"] {
        let n = &sheet.num;
        Element::new("line")
            .attr("class", class)
            .attr("x1", n.f(a.x))
            .attr("y1", n.f(a.y))
            .attr("x2", n.f(b.x))
            .attr("y2", n.f(b.y))
            .empty(out);
    }
}

/// A ground symbol under every joint carried by the ground: a triangle standing on a hatched base.
pub(crate) fn ground_symbols(sheet: &Sheet, out: &mut String) {
    let h = sheet.style.joint * 2.2;
    let n = &sheet.num;
    for &j in sheet.topology().fixed_joints() {
        let g = sheet.input.mechanism.joints[j];
        let at = |dx: f64, dy: f64| g + Vec2::new(dx * h, dy * h);
        Element::new("polygon")
            .attr("class", "ground")
            .attr("points", n.points([g, at(-0.75, -1.3), at(0.75, -1.3)]))
            .empty(out);
        let mut d = String::new();
        let mut segment = |p: Point, q: Point| {
            d.push('M');
            n.put_point(&mut d, p);
            d.push('L');
            n.put_point(&mut d, q);
        };
        segment(at(-1.1, -1.3), at(1.1, -1.3));
        for i in 0..5 {
            let x = -1.0 + 0.5 * i as f64;
            segment(at(x, -1.3), at(x - 0.4, -1.75));
        }
        Element::new("path").attr("class", "ground-line").attr("d", d).empty(out);
    }
}

/// A label at world point `p`, written in picture coordinates (call outside the world group).
pub(crate) fn label(sheet: &Sheet, p: Point, text: &str, class: &str, colour: Option<&str>, out: &mut String) {
    let (x, y) = sheet.screen(p);
    Element::new("text")
        .attr("class", class)
        .attr("x", SCREEN.f(x))
        .attr("y", SCREEN.f(y))
        // A style, not a fill attribute: the style sheet's text rule would win over an attribute.
        .attr_opt("style", colour.map(|c| format!("fill:{c}")))
        .text(text, out);
}

/// The number of every input pose (1-based, as a person counts) at the centroid of the body there.
pub(crate) fn pose_numbers(sheet: &Sheet, out: &mut String) {
    let font = sheet.style.font;
    for (b, body) in sheet.input.problem.bodies.iter().enumerate() {
        for (i, pose) in body.poses.iter().enumerate() {
            // Shifted down by a third of the font so the digits sit centred on the centroid.
            let c = body.outline.transformed(pose).centroid() - Vec2::new(0.0, font * 0.35);
            label(sheet, c, &(i + 1).to_string(), "pose-label", Some(&Style::body_text_colour(b)), out);
        }
    }
}

/// The title band: scene name, mechanism line, and the legend (body colours, then the sheet's notes).
pub(crate) fn title(sheet: &Sheet, out: &mut String) {
    let k = sheet.pixels_per_unit();
    let s = &sheet.style;
    let x = s.margin * 0.5 * k;
    let title = sheet.title();
    let mut y = s.title_font * 1.15 * k;
    Element::new("text").attr("class", "title").attr("x", SCREEN.f(x)).attr("y", SCREEN.f(y)).text(&title.name, out);
    y += sheet.line_height() * k;
    Element::new("text").attr("x", SCREEN.f(x)).attr("y", SCREEN.f(y)).text(&title.subtitle, out);
    y += sheet.line_height() * k;
    let mut pen = x;
    let swatch = sheet.swatch() * k;
    for (colour, text) in sheet.legend() {
        let advance = sheet.legend_advance(colour, &text) * k;
        let mut text_x = pen;
        if let Some(colour) = colour {
            Element::new("rect")
                .attr("class", "legend")
                .attr("x", SCREEN.f(pen))
                .attr("y", SCREEN.f(y - swatch * 0.9))
                .attr("width", SCREEN.f(swatch))
                .attr("height", SCREEN.f(swatch))
                .attr("fill", colour)
                .empty(out);
            text_x += swatch * 1.4;
        }
        Element::new("text").attr("x", SCREEN.f(text_x)).attr("y", SCREEN.f(y)).text(&text, out);
        pen += advance;
    }
}

/// The lines under the drawing ([`Sheet::with_footer`]).
pub(crate) fn footer(sheet: &Sheet, out: &mut String) {
    let k = sheet.pixels_per_unit();
    let x = sheet.style.margin * 0.5 * k;
    let top = sheet.band + sheet.world.height();
    for (i, line) in sheet.footer.iter().enumerate() {
        let y = (top + (i as f64 + 1.0) * sheet.line_height()) * k;
        Element::new("text").attr("class", "footer").attr("x", SCREEN.f(x)).attr("y", SCREEN.f(y)).text(line, out);
    }
}

/// Part `part` (a link) with its joints at `joints`: a thick line for a binary link (red for the
/// crank), a filled triangle or polygon for a ternary one. Returned unwritten, so the animation can add
/// children.
pub(crate) fn link(sheet: &Sheet, part: usize, joints: &[Point]) -> Element {
    let n = &sheet.num;
    let carried = &sheet.topology().parts[part].joints;
    if let [a, b] = carried[..] {
        let (a, b) = (joints[a], joints[b]);
        Element::new("line")
            .attr("class", if sheet.is_crank(part) { "link crank" } else { "link" })
            .attr("x1", n.f(a.x))
            .attr("y1", n.f(a.y))
            .attr("x2", n.f(b.x))
            .attr("y2", n.f(b.y))
    } else {
        Element::new("polygon").attr("class", "ternary").attr("points", n.points(carried.iter().map(|&j| joints[j])))
    }
}

/// A joint circle at `p`, returned unwritten.
pub(crate) fn joint(sheet: &Sheet, p: Point) -> Element {
    let n = &sheet.num;
    Element::new("circle")
        .attr("class", "joint")
        .attr("cx", n.f(p.x))
        .attr("cy", n.f(p.y))
        .attr("r", n.f(sheet.style.joint))
}

/// A body's joints joined (a line for two, a polygon for more), in whatever frame `joints` are given.
pub(crate) fn bracket(sheet: &Sheet, joints: &[Point], colour: &str, out: &mut String) {
    if joints.len() < 2 {
        return;
    }
    let tag = if joints.len() == 2 { "polyline" } else { "polygon" };
    Element::new(tag)
        .attr("class", "bracket")
        .attr("fill", colour)
        .attr("stroke", colour)
        .attr("points", sheet.num.points(joints.iter().copied()))
        .empty(out);
}

/// The block that slides on the guide, centred on the origin of the current frame, along `direction`.
pub(crate) fn slider_block(sheet: &Sheet, direction: Vec2) -> Element {
    let n = &sheet.num;
    let (w, h) = (sheet.style.joint * 4.4, sheet.style.joint * 2.8);
    Element::new("rect")
        .attr("class", "slider")
        .attr("x", n.f(-w / 2.0))
        .attr("y", n.f(-h / 2.0))
        .attr("width", n.f(w))
        .attr("height", n.f(h))
        .attr("transform", format!("rotate({:.2})", direction.angle().to_degrees()))
}
