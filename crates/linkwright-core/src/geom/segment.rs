//! Segment predicates: the distance from a point to a segment and whether two segments cross, the
//! building blocks of the polygon and obstacle tests.

use super::vector::Point;

/// Distance from `p` to the segment `a`–`b`.
pub(crate) fn point_segment_distance(p: Point, a: Point, b: Point) -> f64 {
    point_segment_distance_sq(p, a, b).sqrt()
}

/// Squared distance from `p` to the segment `a`–`b` (no square root, for comparisons in hot loops).
pub(crate) fn point_segment_distance_sq(p: Point, a: Point, b: Point) -> f64 {
    let ab = b - a;
    let len_sq = ab.norm_sq();
    if len_sq == 0.0 {
        return (p - a).norm_sq();
    }
    let t = ((p - a).dot(ab) / len_sq).clamp(0.0, 1.0);
    (p - (a + ab * t)).norm_sq()
}

/// How two segments meet, ignoring contacts within `tol` of an endpoint (touching is not crossing).
///
/// Returns true when the open segments cross at a single point that lies farther than `tol` from every
/// endpoint, which is what "one edge passes through another" means for penetration tests.
pub(crate) fn segments_cross(a0: Point, a1: Point, b0: Point, b1: Point, tol: f64) -> bool {
    let da = a1 - a0;
    let db = b1 - b0;
    let denom = da.cross(db);
    let la = da.norm();
    let lb = db.norm();
    if la == 0.0 || lb == 0.0 || denom.abs() <= 1e-12 * la * lb {
        return false;
    }
    let w = b0 - a0;
    let t = w.cross(db) / denom;
    let u = w.cross(da) / denom;
    let ta = tol / la;
    let tb = tol / lb;
    t > ta && t < 1.0 - ta && u > tb && u < 1.0 - tb
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::testing;

    #[test]
    fn crossing_segments_cross_and_touching_do_not() {
        let p = Point::new;
        assert!(segments_cross(p(0., 0.), p(2., 2.), p(0., 2.), p(2., 0.), 1e-9));
        // T-junction: one segment ends on the other.
        assert!(!segments_cross(p(0., 0.), p(2., 0.), p(1., 0.), p(1., 1.), 1e-9));
        // Collinear overlap is touching, not crossing.
        assert!(!segments_cross(p(0., 0.), p(2., 0.), p(1., 0.), p(3., 0.), 1e-9));
    }

    #[test]
    fn point_segment_distance_is_euclidean() {
        let p = Point::new;
        testing::assert_close(point_segment_distance(p(1., 1.), p(0., 0.), p(2., 0.)), 1.0, 1e-15);
        testing::assert_close(point_segment_distance(p(3., 4.), p(0., 0.), p(0., 0.)), 5.0, 1e-15);
        testing::assert_close(point_segment_distance(p(-3., 4.), p(0., 0.), p(2., 0.)), 5.0, 1e-15);
    }
}
