//! The animated picture: the scene and the input poses stand still while the bodies and the linkage
//! move along the trace, forward then back, looping (SVG's SMIL animation, no script).

use super::layers::{self, polygon};
use super::sheet::Sheet;
use super::style::Style;
use super::svg::{close, Element, Num};
use super::RenderInput;
use crate::geom::Point;
use crate::mechanism::PartKind;
use std::f64::consts::PI;
use std::fmt::Write;

/// Most configurations (frames) one way; the file stays small and the motion smooth.
pub(crate) const MAX_FRAMES: usize = 180;

/// The shortest time one way, seconds.
const MIN_SECONDS: f64 = 0.1;

/// The animation as SVG text: the motion takes `seconds` forward (clamped to at least 0.1 s), as long
/// back, and repeats forever; the crank turns at constant speed. Without animation support (a static
/// renderer), the picture shows the linkage at the first configuration of the trace.
pub fn animation_svg(input: &RenderInput, seconds: f64) -> String {
    let notes: &'static [&'static str] = match input.problem.path() {
        Some(path) if path.closed => &["1: where the body starts", "the crank turns round and round"],
        Some(_) => &["1: where the body starts", "the motion plays forward and back"],
        None => &["1…N: input poses", "the motion plays forward and back"],
    };
    let sheet = Sheet::new(input, MAX_FRAMES, notes);
    let clock = Clock::new(&sheet, seconds);
    let mut out = String::new();
    layers::open_document(&sheet, &mut out);
    layers::open_world(&sheet, &mut out);
    layers::backdrop(&sheet, &mut out);
    layers::onion_skins(&sheet, &mut out);
    layers::joint_paths(&sheet, &mut out);
    layers::drawn_and_traced_path(&sheet, &mut out);
    layers::slider_guide(&sheet, &mut out);
    moving_bodies(&sheet, &clock, &mut out);
    links(&sheet, &clock, &mut out);
    slider(&sheet, &clock, &mut out);
    layers::ground_symbols(&sheet, &mut out);
    joints(&sheet, &clock, &mut out);
    close(&mut out, "g");
    layers::pose_numbers(&sheet, &mut out);
    layers::title(&sheet, &mut out);
    close(&mut out, "svg");
    out
}

/// Timing shared by every animated attribute: frames forward, then back to the first; or, for a
/// closed path (the crank turning whole turns), forward only, over and over.
struct Clock {
    /// `None` when there is nothing to animate (fewer than two frames).
    key_times: Option<String>,
    dur: String,
    /// Whether the frames play back after forward.
    back: bool,
}

impl Clock {
    fn new(sheet: &Sheet, seconds: f64) -> Clock {
        let seconds = if seconds.is_finite() { seconds.max(MIN_SECONDS) } else { MIN_SECONDS };
        let back = !sheet.input.problem.path().is_some_and(|p| p.closed);
        let dur = format!("{}s", Num::with_decimals(3).f(if back { 2.0 * seconds } else { seconds }));
        let m = sheet.rows.len();
        if m < 2 || sheet.input.trace.is_empty() {
            return Clock { key_times: None, dur, back };
        }
        // Time is proportional to the crank angle travelled, so the crank turns at constant speed.
        let thetas = &sheet.input.trace.thetas;
        let mut travelled = Vec::with_capacity(m);
        let mut sum = 0.0;
        for (i, &s) in sheet.rows.iter().enumerate() {
            if i > 0 {
                sum += (thetas[s] - thetas[sheet.rows[i - 1]]).abs();
            }
            travelled.push(sum);
        }
        let fraction: Vec<f64> = travelled
            .iter()
            .enumerate()
            .map(|(i, t)| if sum > 0.0 { t / sum } else { i as f64 / (m - 1) as f64 })
            .collect();
        let key = Num::with_decimals(5);
        let times: Vec<String> = if back {
            let forward = fraction.iter().map(|f| key.f(f / 2.0));
            forward.chain(fraction[..m - 1].iter().rev().map(|f| key.f(1.0 - f / 2.0))).collect()
        } else {
            fraction.iter().map(|&f| key.f(f)).collect()
        };
        Clock { key_times: Some(times.join(";")), dur, back }
    }

    /// Writes an animation of `attribute` through `forward` (one value per sampled frame), forward then
    /// back. `transform` names the `animateTransform` type, `None` for a plain `animate`.
    fn animate(&self, attribute: &str, transform: Option<&str>, forward: &Frames, out: &mut String) {
        let Some(key_times) = &self.key_times else { return };
        if forward.ends.is_empty() {
            return;
        }
        let mut values = String::with_capacity(2 * forward.text.len());
        values.push_str(&forward.text);
        for i in (0..forward.ends.len() - 1).rev().filter(|_| self.back) {
            values.push(';');
            values.push_str(forward.value(i));
        }
        let tag = if transform.is_some() { "animateTransform" } else { "animate" };
        Element::new(tag)
            .attr("attributeName", attribute)
            .attr_opt("type", transform)
            .attr("dur", &self.dur)
            .attr("repeatCount", "indefinite")
            .attr("keyTimes", key_times)
            .attr("values", values)
            .empty(out);
    }
}

/// Values, one per sampled frame, in one text separated by `;`.
struct Frames {
    text: String,
    /// Where each value ends in `text`.
    ends: Vec<usize>,
}

impl Frames {
    fn value(&self, i: usize) -> &str {
        let start = if i == 0 { 0 } else { self.ends[i - 1] + 1 };
        &self.text[start..self.ends[i]]
    }
}

/// One value per sampled frame, each written by `value` from the frame's joints.
fn per_frame(sheet: &Sheet, value: impl Fn(&[Point], &mut String)) -> Frames {
    let mut frames = Frames { text: String::new(), ends: Vec::with_capacity(sheet.rows.len()) };
    for (i, &s) in sheet.rows.iter().enumerate() {
        if i > 0 {
            frames.text.push(';');
        }
        value(sheet.row(s), &mut frames.text);
        frames.ends.push(frames.text.len());
    }
    frames
}

/// Each body in a translating group around a rotating group, both animated, holding the outline and
/// the joint bracket in body coordinates.
fn moving_bodies(sheet: &Sheet, clock: &Clock, out: &mut String) {
    let n = &sheet.num;
    let topo = sheet.topology();
    let first = sheet.row(sheet.rows[0]);
    for (b, body) in sheet.input.problem.bodies.iter().enumerate() {
        let colour = Style::body_colour(b);
        let start = sheet.body_pose(b, first);
        // Unwrapped angles, so a body turning past ±180° keeps turning the same way.
        let mut angles: Vec<f64> = Vec::with_capacity(sheet.rows.len());
        for &s in &sheet.rows {
            let a = sheet.body_pose(b, sheet.row(s)).angle();
            let a = match angles.last() {
                Some(&prev) => prev + wrap(a - prev),
                None => a,
            };
            angles.push(a);
        }
        Element::new("g")
            .attr("transform", format!("translate({})", n.points([Point::ORIGIN + start.translation()])))
            .open(out);
        clock.animate(
            "transform",
            Some("translate"),
            &per_frame(sheet, |row, out| n.put_point(out, Point::ORIGIN + sheet.body_pose(b, row).translation())),
            out,
        );
        Element::new("g").attr("transform", format!("rotate({:.2})", angles[0].to_degrees())).open(out);
        let mut degrees = Frames { text: String::new(), ends: Vec::with_capacity(angles.len()) };
        for (i, a) in angles.iter().enumerate() {
            if i > 0 {
                degrees.text.push(';');
            }
            let _ = write!(degrees.text, "{:.2}", a.to_degrees());
            degrees.ends.push(degrees.text.len());
        }
        clock.animate("transform", Some("rotate"), &degrees, out);
        polygon(sheet, &body.outline, "body", Some(colour), out);
        if b < topo.body_count {
            let to_body = body.poses[0].inverse();
            let joints: Vec<Point> =
                topo.body_part(b).joints.iter().map(|&j| to_body.apply(sheet.input.mechanism.joints[j])).collect();
            layers::bracket(sheet, &joints, colour, out);
        }
        close(out, "g");
        close(out, "g");
    }
}

/// The angle `a` brought into (−π, π].
fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(2.0 * PI);
    if w > PI {
        w - 2.0 * PI
    } else {
        w
    }
}

/// Every link, its ends (or corners) animated.
fn links(sheet: &Sheet, clock: &Clock, out: &mut String) {
    let n = &sheet.num;
    let first = sheet.row(sheet.rows[0]);
    for (i, part) in sheet.topology().parts.iter().enumerate() {
        if part.kind != PartKind::Link {
            continue;
        }
        layers::link(sheet, i, first).open(out);
        if let [a, b] = part.joints[..] {
            clock.animate("x1", None, &per_frame(sheet, |row, out| n.put(out, row[a].x)), out);
            clock.animate("y1", None, &per_frame(sheet, |row, out| n.put(out, row[a].y)), out);
            clock.animate("x2", None, &per_frame(sheet, |row, out| n.put(out, row[b].x)), out);
            clock.animate("y2", None, &per_frame(sheet, |row, out| n.put(out, row[b].y)), out);
            close(out, "line");
        } else {
            let corners = |row: &[Point], out: &mut String| {
                for (k, &j) in part.joints.iter().enumerate() {
                    if k > 0 {
                        out.push(' ');
                    }
                    n.put_point(out, row[j]);
                }
            };
            clock.animate("points", None, &per_frame(sheet, corners), out);
            close(out, "polygon");
        }
    }
}

/// The slider block, riding with the slider joint.
fn slider(sheet: &Sheet, clock: &Clock, out: &mut String) {
    let mechanism = sheet.input.mechanism;
    let (Some(line), Some(j)) = (mechanism.slider, mechanism.topology.slider_joint) else { return };
    let n = &sheet.num;
    let at = sheet.row(sheet.rows[0])[j];
    Element::new("g").attr("transform", format!("translate({})", n.points([at]))).open(out);
    clock.animate("transform", Some("translate"), &per_frame(sheet, |row, out| n.put_point(out, row[j])), out);
    layers::slider_block(sheet, line.direction).empty(out);
    close(out, "g");
}

/// Ground joints standing still, moving joints animated.
fn joints(sheet: &Sheet, clock: &Clock, out: &mut String) {
    let n = &sheet.num;
    let first = sheet.row(sheet.rows[0]);
    let fixed = sheet.topology().fixed_joints();
    for (j, &p) in first.iter().enumerate() {
        if fixed.contains(&j) {
            layers::joint(sheet, p).empty(out);
        } else {
            layers::joint(sheet, p).open(out);
            clock.animate("cx", None, &per_frame(sheet, |row, out| n.put(out, row[j].x)), out);
            clock.animate("cy", None, &per_frame(sheet, |row, out| n.put(out, row[j].y)), out);
            close(out, "circle");
        }
    }
}
