//! Exact part outlines for a laser cutter, CNC router or waterjet: a part is the convex hull of discs
//! of one radius around its holes' centres, so its outline is straight lines and arcs, and its holes
//! are circles (a slot is two lines and two arcs). They are written as such, DXF `LINE`, `ARC` and
//! `CIRCLE` entities and SVG arcs and circles, so the machine cuts true circles of the clearance
//! diameter. (The printed parts' profiles in `crate::fab` are faceted polylines of printed outlines
//! on a print sheet; a workshop's machine needs the exact geometry, on its stock sheet.)

use crate::geom::{Point, Vec2};
use serde::Serialize;
use std::f64::consts::TAU;
use std::fmt::Write as _;

/// A hole through a part, in the part's frame, millimetres.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Hole {
    /// A round hole for a bolt.
    Round {
        /// Its centre.
        centre: Point,
        /// Its diameter (the bolt's ISO 273 clearance hole).
        diameter_mm: f64,
        /// What the bolt is: a joint's name, or `fixing` for a bracket's bolts.
        purpose: String,
    },
    /// A slot the slider's bolt runs in.
    Slot {
        /// The centres of its two rounded ends.
        ends: [Point; 2],
        /// Its width (the bolt's clearance hole).
        width_mm: f64,
    },
}

/// A part's outline in its own frame, millimetres: the convex hull of discs of radius `radius_mm`
/// around `centres` (counter-clockwise, the first at the origin and the second on the +x axis), and
/// its holes.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Outline {
    /// The disc centres on the hull, counter-clockwise.
    pub centres: Vec<Point>,
    /// Half the part's width.
    pub radius_mm: f64,
    /// The holes.
    pub holes: Vec<Hole>,
}

/// One piece of a closed outline.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Piece {
    Line(Point, Point),
    /// Centre, radius, start and end angle (radians, counter-clockwise from start to end).
    Arc(Point, f64, f64, f64),
}

/// The pieces of the boundary of the hull of discs of radius `r` around `centres` (a convex polygon,
/// counter-clockwise), counter-clockwise.
fn pieces(centres: &[Point], r: f64) -> Vec<Piece> {
    match centres {
        [] => Vec::new(),
        [c] => vec![Piece::Arc(*c, r, 0.0, TAU)],
        _ => {
            let n = centres.len();
            let normal = |i: usize| {
                let e = (centres[(i + 1) % n] - centres[i]).normalized();
                Vec2::new(e.y, -e.x)
            };
            let mut out = Vec::with_capacity(2 * n);
            for i in 0..n {
                let (a, b, m) = (centres[i], centres[(i + 1) % n], normal(i));
                out.push(Piece::Line(a + m * r, b + m * r));
                let next = normal((i + 1) % n);
                let start = m.angle();
                let turn = (next.angle() - start).rem_euclid(TAU);
                out.push(Piece::Arc(b, r, start, start + turn));
            }
            out
        }
    }
}

/// The convex hull of `points`, counter-clockwise, without collinear points (Andrew's monotone chain).
fn hull(points: &[Point]) -> Vec<Point> {
    let mut pts: Vec<Point> = points.to_vec();
    pts.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    pts.dedup_by(|a, b| a.distance(*b) < 1e-9);
    if pts.len() < 3 {
        return pts;
    }
    let turn = |o: Point, a: Point, b: Point| (a - o).cross(b - o);
    let mut lower: Vec<Point> = Vec::new();
    for &p in &pts {
        while lower.len() >= 2 && turn(lower[lower.len() - 2], lower[lower.len() - 1], p) <= 1e-9 {
            lower.pop();
        }
        lower.push(p);
    }
    let mut upper: Vec<Point> = Vec::new();
    for &p in pts.iter().rev() {
        while upper.len() >= 2 && turn(upper[upper.len() - 2], upper[upper.len() - 1], p) <= 1e-9 {
            upper.pop();
        }
        upper.push(p);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

impl Outline {
    /// The outline of discs of `radius_mm` around `core` (millimetres, any frame), with `holes` in
    /// the same frame: moved so that `core[0]` is at the origin and `core[1]` on the +x axis.
    pub fn new(core: &[Point], radius_mm: f64, holes: Vec<Hole>) -> Outline {
        let origin = core.first().copied().unwrap_or(Point::ORIGIN);
        let x_axis = match core.get(1) {
            Some(&p) if p.distance(origin) > 1e-9 => (p - origin).normalized(),
            _ => Vec2::new(1.0, 0.0),
        };
        let to_local = |p: Point| {
            let v = p - origin;
            Point::new(v.dot(x_axis), x_axis.cross(v))
        };
        let local: Vec<Point> = core.iter().map(|&p| to_local(p)).collect();
        let holes = holes
            .into_iter()
            .map(|h| match h {
                Hole::Round { centre, diameter_mm, purpose } => {
                    Hole::Round { centre: to_local(centre), diameter_mm, purpose }
                }
                Hole::Slot { ends, width_mm } => Hole::Slot { ends: ends.map(to_local), width_mm },
            })
            .collect();
        Outline { centres: hull(&local), radius_mm, holes }
    }

    /// The bounding box's lower-left corner and its length (x) and width (y), mm.
    pub fn bounds(&self) -> (Point, [f64; 2]) {
        let r = self.radius_mm;
        let (mut lo, mut hi) =
            (Point::new(f64::INFINITY, f64::INFINITY), Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY));
        for c in &self.centres {
            lo = Point::new(lo.x.min(c.x - r), lo.y.min(c.y - r));
            hi = Point::new(hi.x.max(c.x + r), hi.y.max(c.y + r));
        }
        if self.centres.is_empty() {
            return (Point::ORIGIN, [0.0, 0.0]);
        }
        (lo, [hi.x - lo.x, hi.y - lo.y])
    }

    /// The area inside the outline, holes taken out, mm²: the hull's area, its perimeter times the
    /// radius and one full disc.
    pub fn area_mm2(&self) -> f64 {
        let c = &self.centres;
        let n = c.len();
        let (mut area, mut perimeter) = (0.0, 0.0);
        for i in 0..n {
            let (a, b) = (c[i], c[(i + 1) % n]);
            area += 0.5 * (a.x * b.y - b.x * a.y);
            perimeter += a.distance(b);
        }
        let r = self.radius_mm;
        let holes: f64 = self
            .holes
            .iter()
            .map(|h| match h {
                Hole::Round { diameter_mm, .. } => 0.25 * std::f64::consts::PI * diameter_mm * diameter_mm,
                Hole::Slot { ends, width_mm } => {
                    ends[0].distance(ends[1]) * width_mm + 0.25 * std::f64::consts::PI * width_mm * width_mm
                }
            })
            .sum();
        // A single pair of centres has a "perimeter" of twice its length, as the outline runs both ways.
        area.abs() + perimeter * r + std::f64::consts::PI * r * r - holes
    }

    /// The round holes' count.
    pub fn round_holes(&self) -> usize {
        self.holes.iter().filter(|h| matches!(h, Hole::Round { .. })).count()
    }
}

/// A named part on a profile sheet.
pub(crate) struct Placed<'a> {
    pub name: &'a str,
    pub outline: &'a Outline,
}

/// Gap between parts on a sheet, mm: room for the cutter and the clamps.
const GAP_MM: f64 = 10.0;
/// Rows of parts are at most this wide, mm: a 2440 × 1220 mm plywood sheet (2500 × 1250 mm metal
/// sheet) less its border.
const ROW_MM: f64 = 2400.0;
/// Height of the labels, mm.
const LABEL_MM: f64 = 6.0;

/// Where each part goes on the sheet: the offset of its frame's origin (mm, y up), and the sheet's
/// width and height.
fn arrange(parts: &[Placed]) -> (Vec<Vec2>, f64, f64) {
    let (mut x, mut y, mut row_h, mut width) = (GAP_MM, GAP_MM, 0.0f64, 0.0f64);
    let mut out = Vec::with_capacity(parts.len());
    for p in parts {
        let (lo, [w, h]) = p.outline.bounds();
        if x + w + GAP_MM > ROW_MM && x > GAP_MM {
            x = GAP_MM;
            y += row_h + GAP_MM + LABEL_MM;
            row_h = 0.0;
        }
        out.push(Vec2::new(x - lo.x, y + LABEL_MM - lo.y));
        x += w + GAP_MM;
        width = width.max(x);
        row_h = row_h.max(h);
    }
    (out, width.max(2.0 * GAP_MM), y + row_h + LABEL_MM + GAP_MM)
}

/// Every part on one SVG sheet at full size, millimetres: cuts as red hairlines (outlines, then holes
/// as circles and slots), names as blue text to engrave or skip.
pub(crate) fn profiles_svg(title: &str, parts: &[Placed]) -> String {
    let (offsets, w, h) = arrange(parts);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w:.2}mm\" height=\"{h:.2}mm\" viewBox=\"0 0 {w:.3} {h:.3}\">"
    );
    let _ = writeln!(s, "<title>{}</title>", esc(title));
    s.push_str(
        "<style>.cut{fill:none;stroke:#ff0000;stroke-width:0.1}.label{font:5px sans-serif;fill:#0000ff}</style>\n",
    );
    for (p, &off) in parts.iter().zip(&offsets) {
        // y up in the parts' frames, down in SVG.
        let at = |q: Point| Point::new(q.x + off.x, h - (q.y + off.y));
        let _ = writeln!(s, "<g id=\"{}\">", esc(p.name));
        let _ = writeln!(
            s,
            "<path class=\"cut\" d=\"{}\"/>",
            svg_path(&pieces(&p.outline.centres, p.outline.radius_mm), at)
        );
        for hole in &p.outline.holes {
            match hole {
                Hole::Round { centre, diameter_mm, .. } => {
                    let c = at(*centre);
                    let _ = writeln!(
                        s,
                        "<circle class=\"cut\" cx=\"{:.3}\" cy=\"{:.3}\" r=\"{:.3}\"/>",
                        c.x,
                        c.y,
                        0.5 * diameter_mm
                    );
                }
                Hole::Slot { ends, width_mm } => {
                    let _ = writeln!(
                        s,
                        "<path class=\"cut\" d=\"{}\"/>",
                        svg_path(&pieces(&hull(ends), 0.5 * width_mm), at)
                    );
                }
            }
        }
        let (lo, _) = p.outline.bounds();
        let label = at(Point::new(lo.x, lo.y - 1.5));
        let _ = writeln!(
            s,
            "<text class=\"label\" x=\"{:.2}\" y=\"{:.2}\">{}</text></g>",
            label.x,
            label.y + LABEL_MM - 1.5,
            esc(p.name)
        );
    }
    s.push_str("</svg>\n");
    s
}

/// An SVG path of closed `pieces`, each point mapped by `at` (which turns y down); arcs are split in
/// halves so that no arc needs the large-arc flag. A counter-clockwise arc with y up is still
/// counter-clockwise on the page, the negative-angle direction of SVG's y-down frame: sweep flag 0.
fn svg_path(pieces: &[Piece], at: impl Fn(Point) -> Point) -> String {
    let mut d = String::new();
    let point_on = |c: Point, r: f64, a: f64| c + Vec2::from_angle(a) * r;
    for (k, piece) in pieces.iter().enumerate() {
        let start = match *piece {
            Piece::Line(a, _) => a,
            Piece::Arc(c, r, a0, _) => point_on(c, r, a0),
        };
        if k == 0 {
            let p = at(start);
            let _ = write!(d, "M{:.3},{:.3} ", p.x, p.y);
        }
        match *piece {
            Piece::Line(_, b) => {
                let p = at(b);
                let _ = write!(d, "L{:.3},{:.3} ", p.x, p.y);
            }
            Piece::Arc(c, r, a0, a1) => {
                if a1 - a0 < 1e-12 {
                    continue;
                }
                for end in [0.5 * (a0 + a1), a1] {
                    let p = at(point_on(c, r, end));
                    let _ = write!(d, "A{r:.3},{r:.3} 0 0 0 {:.3},{:.3} ", p.x, p.y);
                }
            }
        }
    }
    d.push('Z');
    d
}

/// Every part as an ASCII DXF (R12), millimetres, placed as on the SVG sheet: each part's cuts on a
/// layer named after it (`LINE` and `ARC` for the outline and slots, `CIRCLE` for the holes), the
/// names as `TEXT` on the layer `LABELS`.
pub(crate) fn profiles_dxf(parts: &[Placed]) -> String {
    let (offsets, _, _) = arrange(parts);
    let mut s = String::new();
    let mut pair = |code: i32, value: &str| {
        let _ = write!(s, "{code}\n{value}\n");
    };
    for (code, value) in
        [(0, "SECTION"), (2, "HEADER"), (9, "$ACADVER"), (1, "AC1009"), (9, "$INSUNITS"), (70, "4"), (0, "ENDSEC")]
    {
        pair(code, value);
    }
    pair(0, "SECTION");
    pair(2, "ENTITIES");
    let num = |x: f64| format!("{x:.4}");
    for (p, &off) in parts.iter().zip(&offsets) {
        let layer = crate::fab::sanitize(p.name);
        let layer = if layer.is_empty() { "part".to_string() } else { layer };
        let at = |q: Point| q + off;
        let write_pieces = |pieces: &[Piece], pair: &mut dyn FnMut(i32, &str)| {
            for piece in pieces {
                match *piece {
                    Piece::Line(a, b) => {
                        let (a, b) = (at(a), at(b));
                        pair(0, "LINE");
                        pair(8, &layer);
                        for (code, v) in [(10, a.x), (20, a.y), (30, 0.0), (11, b.x), (21, b.y), (31, 0.0)] {
                            pair(code, &num(v));
                        }
                    }
                    Piece::Arc(c, r, a0, a1) => {
                        let c = at(c);
                        if a1 - a0 >= TAU - 1e-12 {
                            pair(0, "CIRCLE");
                            pair(8, &layer);
                            for (code, v) in [(10, c.x), (20, c.y), (30, 0.0), (40, r)] {
                                pair(code, &num(v));
                            }
                        } else if a1 - a0 > 1e-12 {
                            pair(0, "ARC");
                            pair(8, &layer);
                            for (code, v) in
                                [(10, c.x), (20, c.y), (30, 0.0), (40, r), (50, a0.to_degrees()), (51, a1.to_degrees())]
                            {
                                pair(code, &num(v));
                            }
                        }
                    }
                }
            }
        };
        write_pieces(&pieces(&p.outline.centres, p.outline.radius_mm), &mut pair);
        for hole in &p.outline.holes {
            match hole {
                Hole::Round { centre, diameter_mm, .. } => {
                    write_pieces(&[Piece::Arc(*centre, 0.5 * diameter_mm, 0.0, TAU)], &mut pair);
                }
                Hole::Slot { ends, width_mm } => write_pieces(&pieces(&hull(ends), 0.5 * width_mm), &mut pair),
            }
        }
        let (lo, _) = p.outline.bounds();
        let label = at(Point::new(lo.x, lo.y - LABEL_MM + 1.0));
        pair(0, "TEXT");
        pair(8, "LABELS");
        for (code, v) in [(10, label.x), (20, label.y), (30, 0.0), (40, LABEL_MM - 2.0)] {
            pair(code, &num(v));
        }
        pair(1, p.name);
    }
    pair(0, "ENDSEC");
    pair(0, "EOF");
    s
}

fn esc(s: &str) -> std::borrow::Cow<'_, str> {
    crate::xml::escape(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bar_is_a_stadium_in_its_own_frame() {
        let hole = |p: Point| Hole::Round { centre: p, diameter_mm: 9.0, purpose: "j".into() };
        let (a, b) = (Point::new(10.0, 10.0), Point::new(10.0, 310.0));
        let bar = Outline::new(&[a, b], 20.0, vec![hole(a), hole(b)]);
        assert_eq!(bar.centres.len(), 2);
        assert!(bar.centres[1].distance(Point::new(300.0, 0.0)) < 1e-9);
        let (lo, size) = bar.bounds();
        assert!(
            lo.distance(Point::new(-20.0, -20.0)) < 1e-9
                && (size[0] - 340.0).abs() < 1e-9
                && (size[1] - 40.0).abs() < 1e-9
        );
        let expected = 300.0 * 40.0 + std::f64::consts::PI * 400.0 - 2.0 * std::f64::consts::PI * 4.5 * 4.5;
        assert!((bar.area_mm2() - expected).abs() < 1e-6);
        let ps = pieces(&bar.centres, 20.0);
        // Two lines and two half-turns, the outline closing on itself.
        assert_eq!(ps.len(), 4);
        for (k, piece) in ps.iter().enumerate() {
            let end = match *piece {
                Piece::Line(_, q) => q,
                Piece::Arc(c, r, _, a1) => c + Vec2::from_angle(a1) * r,
            };
            let next = match ps[(k + 1) % ps.len()] {
                Piece::Line(p, _) => p,
                Piece::Arc(c, r, a0, _) => c + Vec2::from_angle(a0) * r,
            };
            assert!(end.distance(next) < 1e-9, "{k}");
        }
    }

    #[test]
    fn hulls_drop_inner_and_collinear_points() {
        let p = Point::new;
        let h = hull(&[p(0.0, 0.0), p(1.0, 0.0), p(2.0, 0.0), p(1.0, 1.0), p(1.0, 0.2)]);
        assert_eq!(h, vec![p(0.0, 0.0), p(2.0, 0.0), p(1.0, 1.0)]);
    }
}
