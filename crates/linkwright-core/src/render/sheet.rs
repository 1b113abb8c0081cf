//! What both drawings share: the sizes, the sampled configurations, the body frames and the view box.

use super::style::Style;
use super::svg::Num;
use super::RenderInput;
use crate::geom::{Aabb, Point, Rigid, Vec2};
use crate::kinematics::BodyFrames;
use crate::mechanism::{PartKind, Topology};

/// A drawing in the making: the input and everything derived from it once.
pub(crate) struct Sheet<'a> {
    pub input: &'a RenderInput<'a>,
    pub style: Style,
    /// Formats lengths (about 10⁻⁴ of the scale).
    pub num: Num,
    pub body_frames: BodyFrames,
    /// Trace rows drawn (joint paths, animation frames), in order; `[0]` for an empty trace, whose only
    /// configuration is the mechanism at its first pose.
    pub rows: Vec<usize>,
    /// The part of the world shown, without the title band.
    pub world: Aabb,
    /// Height of the title band above the world, drawing units.
    pub band: f64,
    /// Width of the view box (at least the world's, more when the title is wider).
    pub width: f64,
    /// Legend notes after the body colours.
    notes: &'static [&'static str],
    /// Lines of text under the drawing.
    pub footer: Vec<String>,
}

/// The text lines of the title band.
pub(crate) struct Title {
    pub name: String,
    pub subtitle: String,
}

impl<'a> Sheet<'a> {
    /// Prepares a drawing that samples at most `max_rows` trace rows, with `notes` in its legend.
    pub(crate) fn new(input: &'a RenderInput<'a>, max_rows: usize, notes: &'static [&'static str]) -> Sheet<'a> {
        let problem = input.problem;
        let style = Style::for_scale(problem.scale);
        let num = Num::resolving(1e-4 * problem.scale);
        let first_poses: Vec<Rigid> = problem.bodies.iter().map(|b| b.poses[0]).collect();
        let body_frames = BodyFrames::new(input.mechanism, &first_poses);
        let rows = if input.trace.is_empty() { vec![0] } else { sample(input.trace.len(), max_rows) };
        let mut sheet = Sheet {
            input,
            style,
            num,
            body_frames,
            rows,
            world: Aabb { min: Point::ORIGIN, max: Point::ORIGIN },
            band: 0.0,
            width: 0.0,
            notes,
            footer: Vec::new(),
        };
        sheet.frame();
        sheet
    }

    /// The sheet with `groups` of text under the drawing: each group starts a line and wraps at the
    /// sheet's width, its items spaced apart.
    pub(crate) fn with_footer(mut self, groups: Vec<Vec<String>>) -> Sheet<'a> {
        let font = self.style.font;
        let room = self.width - self.style.margin;
        let gap = "   ";
        for group in groups {
            let mut line = String::new();
            for item in group {
                let wider = format!("{line}{}{item}", if line.is_empty() { "" } else { gap });
                if !line.is_empty() && Self::text_width(wider.chars().count(), font) > room {
                    self.footer.push(std::mem::replace(&mut line, item));
                } else {
                    line = wider;
                }
            }
            self.footer.push(line);
        }
        self
    }

    /// Height of the text under the drawing, drawing units.
    pub(crate) fn footer_height(&self) -> f64 {
        if self.footer.is_empty() {
            0.0
        } else {
            (self.footer.len() as f64 + 0.5) * self.line_height()
        }
    }

    /// The joints in trace row `s` (the first-pose joints when the trace is empty).
    pub(crate) fn row(&self, s: usize) -> &[Point] {
        if self.input.trace.is_empty() {
            &self.input.mechanism.joints
        } else {
            self.input.trace.row(s)
        }
    }

    /// Every row of the trace (not only the sampled ones).
    pub(crate) fn all_rows(&self) -> impl Iterator<Item = &[Point]> + '_ {
        let n = self.input.trace.len().max(1);
        (0..n).map(move |s| self.row(s))
    }

    pub(crate) fn topology(&self) -> &Topology {
        &self.input.mechanism.topology
    }

    /// Body `b`'s `body_to_world` in configuration `row`; bodies the mechanism does not carry stay at
    /// their first pose.
    pub(crate) fn body_pose(&self, b: usize, row: &[Point]) -> Rigid {
        if b < self.body_frames.body_count() {
            self.body_frames.pose(b, row)
        } else {
            self.input.problem.bodies[b].poses[0]
        }
    }

    /// The valid `pose_steps` entries, with the pose index each belongs to.
    pub(crate) fn pose_steps(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        let n = self.input.trace.len();
        self.input.pose_steps.iter().copied().enumerate().filter(move |&(_, s)| s < n)
    }

    /// True when part `part` is the crank: the link that carries both driver joints.
    pub(crate) fn is_crank(&self, part: usize) -> bool {
        let t = self.topology();
        let p = &t.parts[part];
        p.kind == PartKind::Link && p.joints.contains(&t.driver_pivot) && p.joints.contains(&t.driver_tip)
    }

    /// Joints that move (not carried by the ground).
    pub(crate) fn moving_joints(&self) -> Vec<usize> {
        let fixed = self.topology().fixed_joints();
        (0..self.topology().joint_count()).filter(|j| !fixed.contains(j)).collect()
    }

    /// The slider guide's ends: the extreme positions of the slider joint along its line.
    pub(crate) fn guide(&self) -> Option<(Point, Point)> {
        let line = self.input.mechanism.slider?;
        let j = self.topology().slider_joint?;
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for row in self.all_rows() {
            let s = (row[j] - line.point).dot(line.direction);
            lo = lo.min(s);
            hi = hi.max(s);
        }
        let ext = self.style.joint * 3.0;
        Some((line.point + line.direction * (lo - ext), line.point + line.direction * (hi + ext)))
    }

    /// The scene name and a line about the mechanism.
    pub(crate) fn title(&self) -> Title {
        let problem = self.input.problem;
        let name = if problem.name.trim().is_empty() { "untitled scene".to_string() } else { problem.name.clone() };
        let mut subtitle = self.topology().mechanism_type.linkage_label(self.topology().body_count);
        let thetas = &self.input.trace.thetas;
        if let (Some(a), Some(b)) = (thetas.first(), thetas.last()) {
            subtitle.push_str(&format!(" · crank {:.1}° → {:.1}°", a.to_degrees(), b.to_degrees()));
        }
        match problem.path() {
            Some(path) => subtitle.push_str(if path.closed { " · a closed path" } else { " · an open path" }),
            None => subtitle.push_str(&format!(" · {} poses", problem.pose_count)),
        }
        Title { name, subtitle }
    }

    /// Rough width of `chars` characters at font size `font` (no font metrics here).
    pub(crate) fn text_width(chars: usize, font: f64) -> f64 {
        chars as f64 * font * 0.56
    }

    /// Height of one legend line.
    pub(crate) fn line_height(&self) -> f64 {
        self.style.font * 1.4
    }

    /// The legend entries: `(colour, label)`, the bodies' colours then the notes (colour `None`).
    pub(crate) fn legend(&self) -> Vec<(Option<&'static str>, String)> {
        let bodies = self.input.problem.bodies.iter().enumerate();
        let mut items: Vec<_> = bodies.map(|(b, body)| (Some(Style::body_colour(b)), body.name.clone())).collect();
        items.extend(self.notes.iter().map(|n| (None, n.to_string())));
        items
    }

    /// Side of a legend colour swatch.
    pub(crate) fn swatch(&self) -> f64 {
        self.style.font * 0.8
    }

    /// How far the legend entry `(colour, label)` advances the pen.
    pub(crate) fn legend_advance(&self, colour: Option<&str>, label: &str) -> f64 {
        let swatch = if colour.is_some() { self.swatch() * 1.4 } else { 0.0 };
        swatch + Self::text_width(label.chars().count(), self.style.font) + self.style.font * 1.2
    }

    /// Fits the view to everything drawn, with a margin and a title band on top.
    fn frame(&mut self) {
        let problem = self.input.problem;
        let mut points: Vec<Point> = Vec::new();
        for poly in problem.fixed.iter().chain([&problem.region]).chain(&problem.avoid) {
            points.extend_from_slice(poly.vertices());
        }
        for body in &problem.bodies {
            for pose in &body.poses {
                points.extend(body.outline.vertices().iter().map(|&p| pose.apply(p)));
            }
        }
        for row in self.all_rows() {
            points.extend_from_slice(row);
        }
        for &s in &self.rows {
            for (b, body) in problem.bodies.iter().enumerate() {
                let pose = self.body_pose(b, self.row(s));
                points.extend(body.outline.vertices().iter().map(|&p| pose.apply(p)));
            }
        }
        for (_, s) in self.pose_steps() {
            for (b, body) in problem.bodies.iter().enumerate() {
                let pose = self.body_pose(b, self.row(s));
                points.extend(body.outline.vertices().iter().map(|&p| pose.apply(p)));
            }
        }
        if let Some((a, b)) = self.guide() {
            points.extend([a, b]);
        }
        let bb = Aabb::around(points.into_iter().filter(|p| p.is_finite()))
            .unwrap_or(Aabb { min: Point::ORIGIN, max: Point::new(1.0, 1.0) });
        // Ground symbols reach about three joint radii below their pivots.
        let pad = self.style.margin + 3.0 * self.style.joint;
        let mut world = Aabb { min: bb.min - Vec2::new(pad, pad), max: bb.max + Vec2::new(pad, pad) };
        let title = self.title();
        let legend: f64 = self.legend().iter().map(|(c, l)| self.legend_advance(*c, l)).sum();
        let text_width = [
            Self::text_width(title.name.chars().count(), self.style.title_font),
            Self::text_width(title.subtitle.chars().count(), self.style.font),
            legend,
        ]
        .into_iter()
        .fold(0.0, f64::max)
            + self.style.margin;
        self.band = self.style.title_font * 1.4 + 2.0 * self.line_height();
        self.width = world.width().max(text_width);
        world.max.x = world.min.x + self.width;
        self.world = world;
    }

    /// Pixels per drawing unit: the longer side of the picture is [`PIXELS`] wide.
    pub(crate) fn pixels_per_unit(&self) -> f64 {
        PIXELS / self.width.max(self.height())
    }

    /// Height of the picture, drawing units: the title band, the world and the footer.
    fn height(&self) -> f64 {
        self.band + self.world.height() + self.footer_height()
    }

    /// The picture's size in pixels (its view box is `0 0 width height`).
    pub(crate) fn size(&self) -> (f64, f64) {
        let k = self.pixels_per_unit();
        (self.width * k, self.height() * k)
    }

    /// The world point `p` in picture coordinates (pixels, y down).
    pub(crate) fn screen(&self, p: Point) -> (f64, f64) {
        let k = self.pixels_per_unit();
        ((p.x - self.world.min.x) * k, (self.world.max.y + self.band - p.y) * k)
    }

    /// The transform from world coordinates to picture coordinates, as an SVG `transform`. Text is
    /// written in picture coordinates instead, so it stays upright and its sizes are plain pixels (tiny
    /// font sizes in drawing units render badly in some viewers).
    pub(crate) fn world_transform(&self) -> String {
        let k = self.pixels_per_unit();
        let (tx, ty) = self.screen(Point::ORIGIN);
        let n = Num::with_decimals(6);
        format!("matrix({},0,0,{},{},{})", n.f(k), n.f(-k), n.f(tx), n.f(ty))
    }
}

/// The longest side of the picture, pixels.
pub(crate) const PIXELS: f64 = 1000.0;

/// Formats picture coordinates (pixels).
pub(crate) const SCREEN: Num = Num::with_decimals(2);

/// At most `max` indices spread evenly over `0..len`, always with the first and the last.
pub(crate) fn sample(len: usize, max: usize) -> Vec<usize> {
    let max = max.max(2);
    if len <= max {
        return (0..len).collect();
    }
    let mut out: Vec<usize> =
        (0..max).map(|i| ((i as f64) * (len - 1) as f64 / (max - 1) as f64).round() as usize).collect();
    out.dedup();
    out
}
