//! Spreading the printable parts over print beds: each part turned about the vertical to its smallest
//! footprint that fits the bed, then shelves filled tallest first, plate after plate.

use super::settings::Bed;
use super::solid::Mesh;
use crate::geom::{Point, Rigid, Vec2};
use serde::Serialize;

/// A part placed on a plate: its index, and the turn (degrees) and offset (mm) applied to its print mesh.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub(crate) struct Placement {
    pub part: usize,
    pub turn_deg: f64,
    pub offset_mm: [f64; 2],
    /// Footprint on the bed, mm.
    pub size_mm: [f64; 2],
}

/// One print bed's worth of parts.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub(crate) struct Plate {
    pub placements: Vec<Placement>,
}

/// The plates, and the parts too large for the bed in any turn.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub(crate) struct Plates {
    pub plates: Vec<Plate>,
    pub oversized: Vec<usize>,
}

/// The footprint (width, depth) of points turned by `turn` radians, and its lower-left corner.
fn footprint(pts: &[Point], turn: f64) -> (f64, f64, Point) {
    let r = Rigid::new(turn, Vec2::ZERO);
    let bb = crate::geom::Aabb::around(pts.iter().map(|&p| r.apply(p)))
        .unwrap_or(crate::geom::Aabb { min: Point::ORIGIN, max: Point::ORIGIN });
    (bb.width(), bb.height(), bb.min)
}

/// Whether a part whose outline has these points (millimetres) fits the bed in some turn.
pub(crate) fn fits_bed(points_mm: &[Point], bed: &Bed) -> bool {
    misfit(points_mm, 0.0, bed).is_none()
}

/// What it would take for a part that does not fit the bed to fit.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Misfit {
    /// The part's smallest footprint (in its best turn), mm.
    pub footprint_mm: [f64; 2],
    /// The side of the smallest square bed (with the bed's margins) the part fits, mm.
    pub square_bed_mm: f64,
    /// The largest factor the scene may be scaled by for the part to fit this bed (the print sizes, such
    /// as the width of links, do not scale).
    pub max_scale: f64,
}

/// `None` when the part fits the bed in some turn, else what it would take. The part is the convex
/// hull of discs of radius `grow_mm` around `core_mm` (a link or connector: its joints and post; a body:
/// its outline with `grow_mm` 0).
pub(crate) fn misfit(core_mm: &[Point], grow_mm: f64, bed: &Bed) -> Option<Misfit> {
    let hull = super::shapes::convex_hull(core_mm);
    let (w_max, d_max) = (bed.width - 2.0 * bed.margin, bed.depth - 2.0 * bed.margin);
    let g = 2.0 * grow_mm;
    // A part of diameter D fits a D × D square in any turn.
    let diameter = hull.iter().flat_map(|a| hull.iter().map(move |b| a.distance(*b))).fold(0.0, f64::max);
    if diameter + g <= w_max.min(d_max) {
        return None;
    }
    let turns = || (0..180).map(|step| footprint(&hull, (step as f64).to_radians()));
    if turns().any(|(w, d, _)| w + g <= w_max + 1e-9 && d + g <= d_max + 1e-9) {
        return None;
    }
    let (mut area, mut footprint_mm, mut side, mut max_scale) = (f64::INFINITY, [0.0; 2], f64::INFINITY, 0.0f64);
    for (w, d, _) in turns() {
        if (w + g) * (d + g) < area {
            area = (w + g) * (d + g);
            footprint_mm = [(w + g).max(d + g), (w + g).min(d + g)];
        }
        side = side.min((w + g).max(d + g) + 2.0 * bed.margin);
        let fit = |room: f64, size: f64| if size <= 0.0 { f64::INFINITY } else { ((room - g) / size).max(0.0) };
        max_scale = max_scale.max(fit(w_max, w).min(fit(d_max, d)));
    }
    Some(Misfit { footprint_mm, square_bed_mm: side, max_scale })
}

/// The direction of the long side of the smallest box around the points.
pub(crate) fn long_axis(points: &[Point]) -> Vec2 {
    let hull = super::shapes::convex_hull(points);
    let mut best = (f64::INFINITY, Vec2::new(1.0, 0.0));
    for step in 0..180 {
        let turn = (step as f64).to_radians();
        let (w, d, _) = footprint(&hull, turn);
        if w * d < best.0 {
            // The box's x axis, turned back into the part's frame.
            let x = Vec2::from_angle(-turn);
            best = (w * d, if w >= d { x } else { x.perp() });
        }
    }
    best.1
}

/// Packs the print meshes (millimetres after `scale`) of `parts` onto beds.
pub(crate) fn pack(meshes: &[&Mesh], scale: f64, bed: &Bed) -> Plates {
    let (w_max, d_max) = (bed.width - 2.0 * bed.margin, bed.depth - 2.0 * bed.margin);
    let mut items: Vec<(usize, f64, f64, f64, Point)> = Vec::new();
    let mut oversized = Vec::new();
    for (k, m) in meshes.iter().enumerate() {
        let pts: Vec<Point> = m.vertices.iter().map(|v| Point::new(v[0] * scale, v[1] * scale)).collect();
        let hull = super::shapes::convex_hull(&pts);
        let mut best: Option<(f64, f64, f64, f64, Point)> = None;
        for step in 0..180 {
            let turn = (step as f64).to_radians();
            let (w, d, min) = footprint(&hull, turn);
            let fits = w <= w_max + 1e-9 && d <= d_max + 1e-9;
            // Prefer fitting, then the smaller area, then lying along x.
            let key = w * d + if w >= d { 0.0 } else { 1e-6 };
            if fits && best.is_none_or(|b| key < b.0) {
                best = Some((key, turn, w, d, min));
            }
        }
        match best {
            Some((_, turn, w, d, min)) => items.push((k, turn, w, d, min)),
            None => oversized.push(k),
        }
    }
    // Tallest first onto shelves, first plate with room.
    items.sort_by(|a, b| b.3.total_cmp(&a.3).then(a.0.cmp(&b.0)));
    struct Shelf {
        y: f64,
        height: f64,
        x: f64,
    }
    let mut plates: Vec<(Plate, Vec<Shelf>, f64)> = Vec::new();
    for (k, turn, w, d, min) in items {
        let mut placed = false;
        for (plate, shelves, used_y) in plates.iter_mut() {
            let mut spot = None;
            for s in shelves.iter_mut() {
                if d <= s.height + 1e-9 && s.x + w <= w_max + 1e-9 {
                    spot = Some((s.x, s.y));
                    s.x += w + bed.spacing;
                    break;
                }
            }
            if spot.is_none() && *used_y + d <= d_max + 1e-9 {
                spot = Some((0.0, *used_y));
                shelves.push(Shelf { y: *used_y, height: d, x: w + bed.spacing });
                *used_y += d + bed.spacing;
            }
            if let Some((x, y)) = spot {
                plate.placements.push(place(k, turn, w, d, min, x, y, bed));
                placed = true;
                break;
            }
        }
        if !placed {
            let mut plate = Plate::default();
            plate.placements.push(place(k, turn, w, d, min, 0.0, 0.0, bed));
            plates.push((plate, vec![Shelf { y: 0.0, height: d, x: w + bed.spacing }], d + bed.spacing));
        }
    }
    Plates { plates: plates.into_iter().map(|p| p.0).collect(), oversized }
}

#[allow(clippy::too_many_arguments, reason = "a private helper of pack")]
fn place(k: usize, turn: f64, w: f64, d: f64, min: Point, x: f64, y: f64, bed: &Bed) -> Placement {
    Placement {
        part: k,
        turn_deg: turn.to_degrees(),
        offset_mm: [bed.margin + x - min.x, bed.margin + y - min.y],
        size_mm: [w, d],
    }
}

/// The print mesh of a placement in bed coordinates (mm).
pub(crate) fn placed_mesh(mesh: &Mesh, scale: f64, p: &Placement) -> Mesh {
    let r = Rigid::new(p.turn_deg.to_radians(), Vec2::new(p.offset_mm[0], p.offset_mm[1]));
    mesh.mapped(
        |v| {
            let q = r.apply(Point::new(v[0] * scale, v[1] * scale));
            [q.x, q.y, v[2] * scale]
        },
        false,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bar_too_long_for_the_bed_says_what_bed_and_scale_would_take_it() {
        let bed = Bed::default();
        let bar = |len: f64| [Point::ORIGIN, Point::new(len, 0.0)];
        // Laid across the diagonal, a 270 mm bar fits the 210 mm square area.
        assert!(misfit(&bar(270.0), 5.0, &bed).is_none());
        let m = misfit(&bar(400.0), 5.0, &bed).expect("too long");
        assert!((m.footprint_mm[0] - 410.0).abs() < 1e-9 && (m.footprint_mm[1] - 10.0).abs() < 1e-9, "{m:?}");
        let side = m.square_bed_mm;
        assert!(misfit(&bar(400.0), 5.0, &Bed { width: side + 1e-6, depth: side + 1e-6, ..bed.clone() }).is_none());
        assert!(misfit(&bar(400.0), 5.0, &Bed { width: side - 1.0, depth: side - 1.0, ..bed.clone() }).is_some());
        // Scaled by the factor given (the width stays), it fits.
        assert!(misfit(&bar(400.0 * m.max_scale * 0.999), 5.0, &bed).is_none());
        assert!(misfit(&bar(400.0 * m.max_scale * 1.01), 5.0, &bed).is_some());
    }
}
