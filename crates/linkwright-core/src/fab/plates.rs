//! Spreading the printable parts over print beds: each part turned about the vertical to its smallest
//! footprint that fits the bed, then shelves filled tallest first, plate after plate.

use super::settings::Bed;
use super::solid::Mesh;
use crate::geom::{Point, Rigid, Vec2};
use serde::Serialize;

/// A part placed on a plate: its index, and the turn (degrees) and offset (mm) applied to its print mesh.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Placement {
    pub part: usize,
    pub turn_deg: f64,
    pub offset_mm: [f64; 2],
    /// Footprint on the bed, mm.
    pub size_mm: [f64; 2],
}

/// One print bed's worth of parts.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Plate {
    pub placements: Vec<Placement>,
}

/// The plates, and the parts too large for the bed in any turn.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Plates {
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
pub fn fits_bed(points_mm: &[Point], bed: &Bed) -> bool {
    let hull = super::shapes::convex_hull(points_mm);
    let (w_max, d_max) = (bed.width - 2.0 * bed.margin, bed.depth - 2.0 * bed.margin);
    (0..180).any(|step| {
        let (w, d, _) = footprint(&hull, (step as f64).to_radians());
        w <= w_max + 1e-9 && d <= d_max + 1e-9
    })
}

/// The direction of the long side of the smallest box around the points.
pub fn long_axis(points: &[Point]) -> Vec2 {
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
pub fn pack(meshes: &[&Mesh], scale: f64, bed: &Bed) -> Plates {
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
pub fn placed_mesh(mesh: &Mesh, scale: f64, p: &Placement) -> Mesh {
    let r = Rigid::new(p.turn_deg.to_radians(), Vec2::new(p.offset_mm[0], p.offset_mm[1]));
    mesh.mapped(
        |v| {
            let q = r.apply(Point::new(v[0] * scale, v[1] * scale));
            [q.x, q.y, v[2] * scale]
        },
        false,
    )
}
