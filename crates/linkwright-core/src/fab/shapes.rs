//! Small exact 2D helpers of fabrication: convex hulls, rounded outlines (hulls of discs), distances
//! between the convex cores of rounded parts, and depth inside regions with holes.

use crate::geom::{point_segment_distance, segments_cross, Point, Vec2};

/// The convex hull of `points`, counter-clockwise, without collinear points (Andrew's monotone chain).
pub(crate) fn convex_hull(points: &[Point]) -> Vec<Point> {
    let mut pts: Vec<Point> = points.iter().copied().filter(|p| p.is_finite()).collect();
    pts.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    pts.dedup_by(|a, b| a.distance(*b) <= 1e-12);
    if pts.len() < 3 {
        return pts;
    }
    let mut hull: Vec<Point> = Vec::with_capacity(2 * pts.len());
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &Point>> =
            if pass == 0 { Box::new(pts.iter()) } else { Box::new(pts.iter().rev()) };
        for &p in iter {
            while hull.len() >= start + 2 {
                let (a, b) = (hull[hull.len() - 2], hull[hull.len() - 1]);
                if (b - a).cross(p - a) <= 0.0 {
                    hull.pop();
                } else {
                    break;
                }
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// The outline of the convex hull of discs of radius `r` around `centres`, counter-clockwise, with
/// every vertex on one of the circles (so the outline lies inside the exact rounded shape).
pub(crate) fn rounded_outline(centres: &[Point], r: f64, segments: usize) -> Vec<Point> {
    let mut samples = Vec::with_capacity(centres.len() * segments);
    for &c in centres {
        for i in 0..segments {
            let a = std::f64::consts::TAU * i as f64 / segments as f64;
            samples.push(c + Vec2::from_angle(a) * r);
        }
    }
    convex_hull(&samples)
}

/// A circle as a polygon of `segments` vertices on it, counter-clockwise from angle 0.
pub(crate) fn circle(c: Point, r: f64, segments: usize) -> Vec<Point> {
    (0..segments).map(|i| c + Vec2::from_angle(std::f64::consts::TAU * i as f64 / segments as f64) * r).collect()
}

/// A stadium (rounded slot) around the segment `a`–`b`, counter-clockwise, vertices on its arcs.
pub(crate) fn stadium(a: Point, b: Point, r: f64, segments: usize) -> Vec<Point> {
    rounded_outline(&[a, b], r, segments)
}

/// Distance between two convex point sets given by their vertices (a point, a segment or a convex
/// polygon in any order of up to a few vertices): 0 when they overlap.
pub(crate) fn core_distance(a: &[Point], b: &[Point]) -> f64 {
    if a.is_empty() || b.is_empty() {
        return f64::INFINITY;
    }
    // Cores of up to three points (every member's) need no hull: a triangle is made counter-clockwise.
    let mut buf_a = [Point::ORIGIN; 3];
    let mut buf_b = [Point::ORIGIN; 3];
    let owned_a;
    let owned_b;
    let ha: &[Point] = if a.len() <= 3 {
        small_ccw(a, &mut buf_a)
    } else {
        owned_a = convex_hull(a);
        &owned_a
    };
    let hb: &[Point] = if b.len() <= 3 {
        small_ccw(b, &mut buf_b)
    } else {
        owned_b = convex_hull(b);
        &owned_b
    };
    if (ha.len() >= 3 && hb.iter().any(|&p| inside_convex(ha, p)))
        || (hb.len() >= 3 && ha.iter().any(|&p| inside_convex(hb, p)))
    {
        return 0.0;
    }
    let na = if ha.len() <= 2 { ha.len().saturating_sub(1).max(1) } else { ha.len() };
    let nb = if hb.len() <= 2 { hb.len().saturating_sub(1).max(1) } else { hb.len() };
    let edge = |h: &[Point], i: usize| (h[i], h[(i + 1) % h.len()]);
    let mut d = f64::INFINITY;
    for i in 0..na {
        let (a0, a1) = edge(ha, i);
        for j in 0..nb {
            let (b0, b1) = edge(hb, j);
            if segments_cross(a0, a1, b0, b1, 0.0) {
                return 0.0;
            }
            d = d
                .min(point_segment_distance(a0, b0, b1))
                .min(point_segment_distance(a1, b0, b1))
                .min(point_segment_distance(b0, a0, a1))
                .min(point_segment_distance(b1, a0, a1));
        }
    }
    d
}

/// Up to three points as a convex polygon: a triangle counter-clockwise (collinear ones as their two
/// extreme points), two points or one as they are.
fn small_ccw<'a>(p: &[Point], buf: &'a mut [Point; 3]) -> &'a [Point] {
    let n = p.len().min(3);
    buf[..n].copy_from_slice(&p[..n]);
    if n == 3 {
        let area = (buf[1] - buf[0]).cross(buf[2] - buf[0]);
        if area < 0.0 {
            buf.swap(1, 2);
        } else if area == 0.0 {
            // Collinear: keep the two farthest apart.
            let (i, j) = [(0, 1), (0, 2), (1, 2)]
                .into_iter()
                .max_by(|x, y| buf[x.0].distance(buf[x.1]).total_cmp(&buf[y.0].distance(buf[y.1])))
                .unwrap_or((0, 1));
            let (pi, pj) = (buf[i], buf[j]);
            buf[0] = pi;
            buf[1] = pj;
            return &buf[..2];
        }
    }
    &buf[..n]
}

/// Distance from a point to a convex core (0 inside).
pub(crate) fn point_core_distance(p: Point, core: &[Point]) -> f64 {
    core_distance(&[p], core)
}

fn inside_convex(ccw: &[Point], p: Point) -> bool {
    let n = ccw.len();
    (0..n).all(|i| (ccw[(i + 1) % n] - ccw[i]).cross(p - ccw[i]) >= 0.0)
}

/// A region: outer contours and holes together, read with the even-odd rule.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Region {
    pub contours: Vec<Vec<Point>>,
}

impl Region {
    pub(crate) fn contains(&self, p: Point) -> bool {
        // Even-odd over every contour's edges at once.
        let mut inside = false;
        for c in &self.contours {
            let n = c.len();
            for i in 0..n {
                let (a, b) = (c[i], c[(i + 1) % n]);
                if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) {
                    inside = !inside;
                }
            }
        }
        inside
    }
    /// Distance from `p` to the nearest boundary, positive inside and negative outside.
    pub(crate) fn depth(&self, p: Point) -> f64 {
        let d = self.boundary_distance(p);
        if self.contains(p) {
            d
        } else {
            -d
        }
    }
    /// Whether `p` lies inside, at least `d` from the boundary (stops at the first edge too close).
    pub(crate) fn deeper_than(&self, p: Point, d: f64) -> bool {
        self.contains(p)
            && self.contours.iter().all(|c| {
                let n = c.len();
                (0..n).all(|i| point_segment_distance(p, c[i], c[(i + 1) % n]) >= d)
            })
    }
    pub(crate) fn boundary_distance(&self, p: Point) -> f64 {
        let mut d = f64::INFINITY;
        for c in &self.contours {
            let n = c.len();
            for i in 0..n {
                d = d.min(point_segment_distance(p, c[i], c[(i + 1) % n]));
            }
        }
        d
    }
    /// The boundary point nearest to `p` and the unit normal pointing into the region there.
    pub(crate) fn nearest_boundary(&self, p: Point) -> Option<(Point, Vec2)> {
        let mut best: Option<(f64, Point, Point, Point)> = None;
        for c in &self.contours {
            let n = c.len();
            for i in 0..n {
                let (a, b) = (c[i], c[(i + 1) % n]);
                let ab = b - a;
                let len_sq = ab.norm_sq();
                if len_sq <= 0.0 {
                    continue;
                }
                let t = ((p - a).dot(ab) / len_sq).clamp(0.0, 1.0);
                let q = a + ab * t;
                let d = q.distance(p);
                if best.is_none_or(|b| d < b.0) {
                    best = Some((d, q, a, b));
                }
            }
        }
        let (_, q, a, b) = best?;
        // The side of the edge the region is on: probe a little along both normals.
        let n = (b - a).perp().normalized();
        let eps = 1e-6 * (b - a).norm().max(1e-9);
        let inward = if self.contains(q + n * eps) { n } else { -n };
        Some((q, inward))
    }
    pub(crate) fn aabb(&self) -> Option<crate::geom::Aabb> {
        crate::geom::Aabb::around(self.contours.iter().flatten().copied())
    }
}

/// `subject` combined with `clip` by `rule`, both read even-odd: the pieces of positive area, each its
/// outline then its holes.
pub(crate) fn overlay(
    subject: &[Vec<Point>],
    clip: &[Vec<Point>],
    rule: i_overlay::core::overlay_rule::OverlayRule,
) -> Vec<Vec<Vec<Point>>> {
    use i_overlay::core::fill_rule::FillRule;
    use i_overlay::float::single::SingleFloatOverlay;
    let to = |c: &Vec<Point>| -> Vec<[f64; 2]> { c.iter().map(|p| [p.x, p.y]).collect() };
    let s: Vec<Vec<[f64; 2]>> = subject.iter().map(to).collect();
    let c: Vec<Vec<[f64; 2]>> = clip.iter().map(to).collect();
    s.overlay(&c, rule, FillRule::EvenOdd)
        .into_iter()
        .map(|shape| shape.into_iter().map(|c| c.into_iter().map(|[x, y]| Point::new(x, y)).collect()).collect())
        .filter(|c: &Vec<Vec<Point>>| !c.is_empty() && crate::geom::Polygon::new(c[0].clone()).area() > 0.0)
        .collect()
}

/// The union of a region (outline then holes) with discs, as one outline and its holes (the largest
/// piece when the union falls apart, which pads touching the region never make it do). Pockets the
/// discs close off outside the region (two pads meeting beside a thin bar) are filled: only what
/// remains of the region's own holes stays open.
pub(crate) fn union_with_discs(contours: &[Vec<Point>], discs: &[(Point, f64)], segments: usize) -> Vec<Vec<Point>> {
    use i_overlay::core::fill_rule::FillRule;
    use i_overlay::core::overlay_rule::OverlayRule;
    use i_overlay::float::simplify::SimplifyShape;
    use i_overlay::float::single::SingleFloatOverlay;
    if discs.is_empty() {
        return contours.to_vec();
    }
    let to = |c: &[Point]| -> Vec<[f64; 2]> { c.iter().map(|p| [p.x, p.y]).collect() };
    let subject: Vec<Vec<[f64; 2]>> = contours.iter().map(|c| to(c)).collect();
    // The discs merged first (non-zero: where two overlap is inside both), then read even-odd with the
    // region and its holes.
    let discs: Vec<Vec<[f64; 2]>> = discs.iter().map(|&(c, r)| to(&circle(c, r, segments))).collect();
    let clip: Vec<Vec<[f64; 2]>> = discs.simplify_shape(FillRule::NonZero).into_iter().flatten().collect();
    let shapes = subject.overlay(&clip, OverlayRule::Union, FillRule::EvenOdd);
    let back = |c: Vec<[f64; 2]>| -> Vec<Point> { c.into_iter().map(|[x, y]| Point::new(x, y)).collect() };
    let mut best: Option<(f64, Vec<Vec<Point>>)> = None;
    for shape in shapes {
        let contours: Vec<Vec<Point>> = shape.into_iter().map(back).collect();
        let Some(outer) = contours.first() else { continue };
        let area = crate::geom::Polygon::new(outer.clone()).area();
        if best.as_ref().is_none_or(|b| area > b.0) {
            best = Some((area, contours));
        }
    }
    let Some((_, mut merged)) = best else { return contours.to_vec() };
    // A hole of the union is what is left of a hole of the region, or a pocket to fill.
    let holes: Vec<Vec<[f64; 2]>> = contours[1..].iter().map(|c| to(c)).collect();
    let outer = merged.remove(0);
    merged.retain(|h| {
        let pocket: Vec<Vec<[f64; 2]>> = vec![to(h)];
        let overlap = pocket.overlay(&holes, OverlayRule::Intersect, FillRule::EvenOdd);
        overlap.iter().flatten().any(|c| crate::geom::Polygon::new(back(c.clone())).area() > 0.0)
    });
    merged.insert(0, outer);
    merged
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::testing::assert_close;

    #[test]
    fn hull_and_core_distances() {
        let p = Point::new;
        let h = convex_hull(&[p(0., 0.), p(1., 0.), p(0.5, 0.2), p(1., 1.), p(0., 1.)]);
        assert_eq!(h.len(), 4);
        assert_close(core_distance(&[p(0., 0.), p(1., 0.)], &[p(0.5, 2.)]), 2.0, 1e-12);
        assert_close(core_distance(&[p(0., 0.), p(2., 2.)], &[p(0., 2.), p(2., 0.)]), 0.0, 0.0);
        let tri = [p(0., 0.), p(4., 0.), p(0., 4.)];
        assert_close(core_distance(&tri, &[p(1., 1.)]), 0.0, 0.0);
        assert_close(core_distance(&tri, &[p(3., 3.), p(5., 5.)]), 2f64.sqrt(), 1e-12);
    }

    #[test]
    fn overlapping_discs_merge_whole_into_a_region() {
        let p = Point::new;
        let square = vec![vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]];
        // Two discs bulging out of the top side and overlapping each other.
        let discs = [(p(3., 12.), 4.0), (p(7., 12.), 4.0)];
        let merged = Region { contours: union_with_discs(&square, &discs, 48) };
        assert_eq!(merged.contours.len(), 1);
        for (c, r) in discs {
            assert!(merged.depth(c) > r * (std::f64::consts::PI / 48.0).cos() - 1e-4, "{}", merged.depth(c));
        }
        assert!(merged.contains(p(5., 12.)), "the overlap of the discs is inside");
        // Two discs beside a side, meeting above it: the pocket they close off is filled; a hole of
        // the region stays open.
        let holed = vec![square[0].clone(), vec![p(4., 4.), p(4., 6.), p(6., 6.), p(6., 4.)]];
        let discs = [(p(2., 13.), 4.0), (p(8., 13.), 4.0)];
        let merged = Region { contours: union_with_discs(&holed, &discs, 48) };
        assert_eq!(merged.contours.len(), 2, "the square's hole only");
        assert!(merged.contains(p(5., 10.15)) && !merged.contains(p(5., 5.)), "the pocket is filled");
    }

    #[test]
    fn region_depth_and_inward_normal() {
        let p = Point::new;
        let r = Region {
            contours: vec![
                vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)],
                vec![p(4., 4.), p(6., 4.), p(6., 6.), p(4., 6.)],
            ],
        };
        assert_close(r.depth(p(2., 5.)), 2.0, 1e-12);
        assert!(r.depth(p(5., 5.)) < 0.0);
        let (q, n) = r.nearest_boundary(p(-1., 5.)).unwrap();
        assert_close(q.x, 0.0, 1e-12);
        assert_close(n.x, 1.0, 1e-12);
    }
}
