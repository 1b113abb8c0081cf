//! Curves as polylines: resampling by arc length, the nearest point of a polyline, and the distance
//! between a drawn curve and a traced one (what a path design is judged by).

use super::{Aabb, Point, Vec2};

/// The length of `points` as a polyline, closed back to its first point when `closed`.
pub(crate) fn length(points: &[Point], closed: bool) -> f64 {
    edges(points, closed).map(|(p, q)| p.distance(q)).sum()
}

/// The polyline's edges, with the closing one when `closed`.
fn edges(points: &[Point], closed: bool) -> impl Iterator<Item = (Point, Point)> + '_ {
    let n = points.len();
    let count = if closed && n > 2 { n } else { n.saturating_sub(1) };
    (0..count).map(move |i| (points[i], points[(i + 1) % n]))
}

/// `m` points evenly spaced by arc length along `points` (`m ≥ 2`): an open polyline from its first
/// point to its last, a closed one from its first point round (the last sample one step short of
/// the first again). Into `out`, cleared first; a polyline of zero length gives `m` copies of its
/// first point.
pub(crate) fn resample_into(points: &[Point], closed: bool, m: usize, out: &mut Vec<Point>) {
    out.clear();
    let total = length(points, closed);
    if points.is_empty() {
        return;
    }
    if total.is_nan() || total <= 0.0 {
        out.resize(m, points[0]);
        return;
    }
    let step = if closed { total / m as f64 } else { total / (m - 1) as f64 };
    let mut target = 0.0;
    let mut walked = 0.0;
    for (p, q) in edges(points, closed) {
        let edge = p.distance(q);
        while out.len() < m && target <= walked + edge {
            let t = if edge > 0.0 { (target - walked) / edge } else { 0.0 };
            out.push(p.lerp(q, t.clamp(0.0, 1.0)));
            target = step * out.len() as f64;
        }
        walked += edge;
    }
    // Rounding may leave the last sample of an open polyline unplaced: it is the end.
    let last = if closed { points[0] } else { points[points.len() - 1] };
    out.resize(m, last);
}

/// `m` points evenly spaced by arc length along `points` (see [`resample_into`]).
pub(crate) fn resample(points: &[Point], closed: bool, m: usize) -> Vec<Point> {
    let mut out = Vec::with_capacity(m);
    resample_into(points, closed, m, &mut out);
    out
}

/// `points` with each replaced by the mean of itself and its `half` neighbours on either side (an
/// open polyline's ends keep their place, and near them the window shrinks to stay centred).
pub(crate) fn smoothed(points: &[Point], closed: bool, half: usize) -> Vec<Point> {
    let n = points.len();
    if half == 0 || n < 3 {
        return points.to_vec();
    }
    (0..n)
        .map(|i| {
            let h = if closed { half.min((n - 1) / 2) } else { half.min(i).min(n - 1 - i) };
            let (mut x, mut y) = (0.0, 0.0);
            for k in 0..=2 * h {
                let p = points[(i + n + k - h) % n];
                x += p.x;
                y += p.y;
            }
            let m = (2 * h + 1) as f64;
            Point::new(x / m, y / m)
        })
        .collect()
}

/// The point of the polyline `points` (closed when `closed`) nearest to `p`, its distance, and the
/// edge it is on (from vertex `edge` to the next).
pub fn nearest(p: Point, points: &[Point], closed: bool) -> (f64, Point, usize) {
    if points.len() == 1 {
        return (p.distance(points[0]), points[0], 0);
    }
    let mut best = (f64::INFINITY, p, 0);
    for (i, (a, b)) in edges(points, closed).enumerate() {
        let ab: Vec2 = b - a;
        let len_sq = ab.norm_sq();
        let t = if len_sq > 0.0 { ((p - a).dot(ab) / len_sq).clamp(0.0, 1.0) } else { 0.0 };
        let q = a + ab * t;
        let d = p.distance(q);
        if d < best.0 {
            best = (d, q, i);
        }
    }
    best
}

/// The diagonal of the points' bounding box: the size every path distance is a fraction of.
pub(crate) fn size(points: &[Point]) -> f64 {
    Aabb::around(points.iter().copied()).map_or(0.0, |bb| bb.diagonal())
}

/// How far a traced curve is from the drawn one, both ways: every point of each within `max` of the
/// other.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PathError {
    /// The largest distance between a point of one curve and the other (their Hausdorff distance),
    /// scene units.
    pub max: f64,
    /// `max` as a fraction of the drawn curve's size (its bounding box's diagonal).
    pub max_rel: f64,
    /// The mean distance, over points spaced evenly along each curve, to the other, scene units.
    pub mean: f64,
    /// `mean` as a fraction of the drawn curve's size.
    pub mean_rel: f64,
    /// The point of the drawn curve nearest to where the two are farthest apart (world coordinates).
    pub at: Point,
    /// Of the points the tracer must pass exactly, the one the traced curve passes farthest from
    /// (none when the path has no exact points).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exact: Option<ExactMiss>,
}

/// How far the traced curve passes from a point of the drawn one it must pass exactly.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ExactMiss {
    /// The point, an index into the drawn curve's points (from 0).
    pub point: usize,
    /// The distance from it to the traced curve, scene units.
    pub distance: f64,
    /// `distance` as a fraction of the drawn curve's size.
    pub distance_rel: f64,
}

/// Points per curve [`path_error`] measures at: dense enough that the distance between them is a
/// fraction of a percent of any curve drawn with a few dozen points.
const MEASURE_POINTS: usize = 400;

/// The distance between the `drawn` curve and the `traced` one (both polylines, closed when
/// `closed`), measured at [`MEASURE_POINTS`] points spaced evenly along each, and how far the traced
/// curve passes from each of the drawn points listed `exact`.
pub(crate) fn path_error(drawn: &[Point], exact: &[usize], traced: &[Point], closed: bool) -> PathError {
    let size = size(drawn);
    let drawn_points = resample(drawn, closed, MEASURE_POINTS);
    let traced_points = resample(traced, closed, MEASURE_POINTS);
    let (mut max, mut at, mut sum) = (0.0, drawn_points[0], 0.0);
    for &p in &drawn_points {
        let (d, _, _) = nearest(p, traced, closed);
        sum += d;
        if d > max {
            (max, at) = (d, p);
        }
    }
    for &q in &traced_points {
        let (d, on_drawn, _) = nearest(q, drawn, closed);
        sum += d;
        if d > max {
            (max, at) = (d, on_drawn);
        }
    }
    let mean = sum / (2 * MEASURE_POINTS) as f64;
    let rel = |x: f64| if size > 0.0 { x / size } else { 0.0 };
    let exact = exact
        .iter()
        .filter_map(|&i| drawn.get(i).map(|&p| (i, nearest(p, traced, closed).0)))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(point, distance)| ExactMiss { point, distance, distance_rel: rel(distance) });
    PathError { max, max_rel: rel(max), mean, mean_rel: rel(mean), at, exact }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn circle(r: f64, n: usize) -> Vec<Point> {
        (0..n)
            .map(|i| {
                let v = Vec2::from_angle(std::f64::consts::TAU * i as f64 / n as f64) * r;
                Point::new(v.x, v.y)
            })
            .collect()
    }

    #[test]
    fn resampling_spaces_points_evenly_along_a_square() {
        let square = vec![Point::new(0.0, 0.0), Point::new(2.0, 0.0), Point::new(2.0, 2.0), Point::new(0.0, 2.0)];
        let closed = resample(&square, true, 8);
        let want = [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (2.0, 1.0), (2.0, 2.0), (1.0, 2.0), (0.0, 2.0), (0.0, 1.0)];
        for (p, (x, y)) in closed.iter().zip(want) {
            assert!(p.distance(Point::new(x, y)) < 1e-12, "{p:?} against ({x}, {y})");
        }
        let open = resample(&square, false, 4);
        let want = [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)];
        for (p, (x, y)) in open.iter().zip(want) {
            assert!(p.distance(Point::new(x, y)) < 1e-12, "{p:?} against ({x}, {y})");
        }
    }

    #[test]
    fn smoothing_keeps_a_line_and_its_ends_and_flattens_a_zigzag() {
        let zigzag: Vec<Point> = (0..9).map(|i| Point::new(i as f64, if i % 2 == 0 { 0.0 } else { 1.0 })).collect();
        let s = smoothed(&zigzag, false, 1);
        assert_eq!((s[0], s[8]), (zigzag[0], zigzag[8]), "the ends stay");
        for p in &s[1..8] {
            assert!((p.y - 0.5).abs() <= 1.0 / 6.0 + 1e-12, "{p:?}: the mean of three alternating heights");
        }
        let line: Vec<Point> = (0..9).map(|i| Point::new(i as f64, 2.0 * i as f64)).collect();
        assert_eq!(smoothed(&line, false, 2), line);
    }

    #[test]
    fn two_concentric_circles_are_their_radii_apart() {
        // Radii 1 and 1.1: every point of one is 0.1 from the other (less the chords' sag, at most
        // 1 − cos(π/720) of a radius with 720 vertices).
        let (drawn, traced) = (circle(1.0, 720), circle(1.1, 720));
        let e = path_error(&drawn, &[], &traced, true);
        assert!((e.max - 0.1).abs() < 1e-4 && (e.mean - 0.1).abs() < 1e-4, "{e:?}");
        assert!((e.max_rel - 0.1 / 8f64.sqrt()).abs() < 1e-4, "the size is the box's diagonal, 2√2: {e:?}");
    }

    #[test]
    fn the_exact_point_passed_farthest_is_the_one_reported() {
        // Drawn: three corners of a unit square about the origin and a point a little inside the
        // fourth. Traced: a circle of radius 1.2 about the origin, so each point is 1.2 less its own
        // distance from the origin away from it.
        let drawn = vec![Point::new(0.5, 0.5), Point::new(-0.5, 0.5), Point::new(-0.5, -0.5), Point::new(0.5, -0.4)];
        let traced = circle(1.2, 3600);
        let e = path_error(&drawn, &[1, 3], &traced, true);
        let x = e.exact.expect("exact points listed");
        assert_eq!(x.point, 3, "(0.5, −0.4) is nearer the centre, so farther from the circle: {x:?}");
        let want = 1.2 - (0.25f64 + 0.16).sqrt();
        assert!((x.distance - want).abs() < 1e-6, "{x:?} against {want}");
        assert!((x.distance_rel - x.distance / size(&drawn)).abs() < 1e-15, "relative to the drawn curve's size");
        assert!(path_error(&drawn, &[], &traced, true).exact.is_none());
    }

    #[test]
    fn a_traced_curve_that_runs_past_the_drawn_one_is_as_far_as_its_farthest_point() {
        // Drawn: the segment (0,0)–(1,0). Traced: on it, then up to (1, 0.5). The traced end is 0.5
        // from the drawn segment, though every drawn point lies on the traced curve.
        let drawn = vec![Point::new(0.0, 0.0), Point::new(1.0, 0.0)];
        let traced = vec![Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(1.0, 0.5)];
        let e = path_error(&drawn, &[], &traced, false);
        assert!((e.max - 0.5).abs() < 1e-12, "{e:?}");
        assert!(e.at.distance(Point::new(1.0, 0.0)) < 1e-12, "{e:?}");
    }
}
