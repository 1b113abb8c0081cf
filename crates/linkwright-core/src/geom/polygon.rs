//! Simple polygons: area, bounds, containment, distances and overlap.

use super::rigid::Rigid;
use super::segment::{point_segment_distance, point_segment_distance_sq, segments_cross};
use super::vector::Point;

/// An axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// The corner with the smallest coordinates.
    pub min: Point,
    /// The corner with the largest coordinates.
    pub max: Point,
}

impl Aabb {
    /// The box around `points`; `None` when there are none.
    ///
    /// # Examples
    ///
    /// ```
    /// use linkwright_core::geom::{Aabb, Point};
    ///
    /// let b = Aabb::around([Point::new(1.0, 2.0), Point::new(4.0, -2.0), Point::new(2.0, 0.0)]).unwrap();
    /// assert_eq!((b.min, b.max), (Point::new(1.0, -2.0), Point::new(4.0, 2.0)));
    /// assert_eq!((b.width(), b.height(), b.diagonal()), (3.0, 4.0, 5.0));
    /// assert!(Aabb::around([]).is_none());
    /// ```
    pub fn around(points: impl IntoIterator<Item = Point>) -> Option<Aabb> {
        let mut it = points.into_iter();
        let first = it.next()?;
        let mut b = Aabb { min: first, max: first };
        for p in it {
            b.include(p);
        }
        Some(b)
    }
    /// Grows the box to contain `p`.
    pub fn include(&mut self, p: Point) {
        self.min.x = self.min.x.min(p.x);
        self.min.y = self.min.y.min(p.y);
        self.max.x = self.max.x.max(p.x);
        self.max.y = self.max.y.max(p.y);
    }
    /// The smallest box containing both boxes.
    pub fn union(&self, o: &Aabb) -> Aabb {
        let mut b = *self;
        b.include(o.min);
        b.include(o.max);
        b
    }
    /// Extent along x.
    pub fn width(&self) -> f64 {
        self.max.x - self.min.x
    }
    /// Extent along y.
    pub fn height(&self) -> f64 {
        self.max.y - self.min.y
    }
    /// Length of the diagonal.
    pub fn diagonal(&self) -> f64 {
        (self.max - self.min).norm()
    }
    /// True when the boxes overlap by more than `tol` on both axes.
    pub fn overlaps(&self, o: &Aabb, tol: f64) -> bool {
        self.min.x < o.max.x - tol
            && o.min.x < self.max.x - tol
            && self.min.y < o.max.y - tol
            && o.min.y < self.max.y - tol
    }
    /// Whether `p` is inside the box or on its boundary.
    pub fn contains(&self, p: Point) -> bool {
        p.x >= self.min.x && p.x <= self.max.x && p.y >= self.min.y && p.y <= self.max.y
    }
    /// The distance between the two boxes (0 when they overlap).
    ///
    /// # Examples
    ///
    /// ```
    /// use linkwright_core::geom::{Aabb, Point};
    ///
    /// let unit = Aabb { min: Point::new(0.0, 0.0), max: Point::new(1.0, 1.0) };
    /// // Apart by 3 along x and 4 along y: the corners (1, 1) and (4, 5) are nearest.
    /// let far = Aabb { min: Point::new(4.0, 5.0), max: Point::new(6.0, 6.0) };
    /// assert_eq!(unit.gap(&far), 5.0);
    /// let overlapping = Aabb { min: Point::new(0.5, 0.5), max: Point::new(2.0, 2.0) };
    /// assert_eq!(unit.gap(&overlapping), 0.0);
    /// ```
    pub fn gap(&self, o: &Aabb) -> f64 {
        self.gap_sq(o).sqrt()
    }
    /// The squared [`Aabb::gap`].
    pub fn gap_sq(&self, o: &Aabb) -> f64 {
        let dx = (o.min.x - self.max.x).max(self.min.x - o.max.x).max(0.0);
        let dy = (o.min.y - self.max.y).max(self.min.y - o.max.y).max(0.0);
        dx * dx + dy * dy
    }
}

/// What makes a list of points not a usable simple polygon.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PolygonError {
    /// Fewer than three vertices (how many there are).
    #[error("has {0} vertices; a polygon needs at least 3")]
    TooFewVertices(usize),
    /// A coordinate of this vertex (0-based) is NaN or infinite.
    #[error("vertex {0} is not a finite number")]
    NonFinite(usize),
    /// The vertices lie on one line.
    #[error("has zero area (its vertices lie on one line)")]
    ZeroArea,
    /// These two edges (edge i runs from vertex i to the next) cross.
    #[error("crosses itself (edge {0} crosses edge {1})")]
    SelfIntersecting(usize, usize),
    /// Less area than a billionth of the square of its size (its bounding box's diagonal): a sliver
    /// no part can be made of, and whose edges no test can tell apart.
    #[error("is too thin: about {:.1e} wide for {size:.1e} long (an area of {area:.1e})", .area / .size)]
    TooThin {
        /// Its area.
        area: f64,
        /// Its size, the diagonal of its bounding box.
        size: f64,
    },
}

/// A simple polygon given by its vertices in order (either winding). The last vertex connects back to
/// the first.
#[derive(Clone, Debug, PartialEq)]
pub struct Polygon {
    vertices: Vec<Point>,
}

impl Polygon {
    /// A polygon from its vertices, unchecked: see [`Polygon::validate`].
    pub fn new(vertices: Vec<Point>) -> Self {
        Polygon { vertices }
    }
    /// The vertices, in order.
    pub fn vertices(&self) -> &[Point] {
        &self.vertices
    }
    /// The edges as `(start, end)` pairs.
    pub fn edges(&self) -> impl Iterator<Item = (Point, Point)> + '_ {
        let n = self.vertices.len();
        (0..n).map(move |i| (self.vertices[i], self.vertices[(i + 1) % n]))
    }
    /// Signed area: positive for counter-clockwise vertices.
    ///
    /// # Examples
    ///
    /// ```
    /// use linkwright_core::geom::{Point, Polygon};
    ///
    /// let corners = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(|(x, y)| Point::new(x, y));
    /// let counter_clockwise = Polygon::new(corners.to_vec());
    /// assert_eq!(counter_clockwise.signed_area(), 1.0);
    /// let clockwise = Polygon::new(corners.into_iter().rev().collect());
    /// assert_eq!(clockwise.signed_area(), -1.0);
    /// ```
    pub fn signed_area(&self) -> f64 {
        let n = self.vertices.len();
        let mut twice = 0.0;
        for i in 0..n {
            let a = self.vertices[i];
            let b = self.vertices[(i + 1) % n];
            twice += a.x * b.y - b.x * a.y;
        }
        twice / 2.0
    }
    /// The enclosed area, whatever the winding.
    ///
    /// # Examples
    ///
    /// ```
    /// use linkwright_core::geom::{Point, Polygon};
    ///
    /// // A right triangle with legs 3 and 4, clockwise: half of 3 × 4.
    /// let triangle = Polygon::new(vec![Point::new(0.0, 0.0), Point::new(0.0, 4.0), Point::new(3.0, 0.0)]);
    /// assert_eq!(triangle.area(), 6.0);
    /// ```
    pub fn area(&self) -> f64 {
        self.signed_area().abs()
    }
    /// The bounding box (a point at the origin for a polygon without vertices).
    pub fn aabb(&self) -> Aabb {
        Aabb::around(self.vertices.iter().copied()).unwrap_or(Aabb { min: Point::ORIGIN, max: Point::ORIGIN })
    }
    /// The area centroid (the vertex mean for a degenerate polygon).
    ///
    /// # Examples
    ///
    /// A triangle's centroid is the mean of its vertices; an L made of three unit squares has its
    /// centroid at the mean of the squares' centres.
    ///
    /// ```
    /// use linkwright_core::geom::{Point, Polygon};
    ///
    /// let triangle = Polygon::new(vec![Point::new(0.0, 0.0), Point::new(3.0, 0.0), Point::new(0.0, 3.0)]);
    /// assert!(triangle.centroid().distance(Point::new(1.0, 1.0)) < 1e-15);
    ///
    /// let l_shape = [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0), (1.0, 2.0), (0.0, 2.0)];
    /// let l_shape = Polygon::new(l_shape.iter().map(|&(x, y)| Point::new(x, y)).collect());
    /// // The squares' centres: (0.5, 0.5), (1.5, 0.5), (0.5, 1.5).
    /// assert!(l_shape.centroid().distance(Point::new(2.5 / 3.0, 2.5 / 3.0)) < 1e-15);
    /// ```
    pub fn centroid(&self) -> Point {
        let a = self.signed_area();
        let n = self.vertices.len();
        if a.abs() < 1e-300 || n == 0 {
            let s = self.vertices.iter().fold((0.0, 0.0), |s, p| (s.0 + p.x, s.1 + p.y));
            return Point::new(s.0 / n.max(1) as f64, s.1 / n.max(1) as f64);
        }
        let (mut cx, mut cy) = (0.0, 0.0);
        for (p, q) in self.edges() {
            let c = p.x * q.y - q.x * p.y;
            cx += (p.x + q.x) * c;
            cy += (p.y + q.y) * c;
        }
        Point::new(cx / (6.0 * a), cy / (6.0 * a))
    }
    /// The polygon with every vertex moved by `t`.
    pub fn transformed(&self, t: &Rigid) -> Polygon {
        Polygon::new(self.vertices.iter().map(|&p| t.apply(p)).collect())
    }

    /// Checks that this is a simple polygon with a positive area.
    ///
    /// # Examples
    ///
    /// ```
    /// use linkwright_core::geom::{Point, Polygon, PolygonError};
    ///
    /// let p = Point::new;
    /// let square = Polygon::new(vec![p(0.0, 0.0), p(2.0, 0.0), p(2.0, 2.0), p(0.0, 2.0)]);
    /// assert_eq!(square.validate(), Ok(()));
    /// // The same corners in another order: a bow-tie, whose first and third edges cross at (1, 1).
    /// let bow_tie = Polygon::new(vec![p(0.0, 0.0), p(2.0, 2.0), p(2.0, 0.0), p(0.0, 2.0)]);
    /// assert_eq!(bow_tie.validate(), Err(PolygonError::SelfIntersecting(0, 2)));
    /// ```
    pub fn validate(&self) -> Result<(), PolygonError> {
        let n = self.vertices.len();
        if n < 3 {
            return Err(PolygonError::TooFewVertices(n));
        }
        if let Some(i) = self.vertices.iter().position(|p| !p.is_finite()) {
            return Err(PolygonError::NonFinite(i));
        }
        let size = self.aabb().diagonal();
        let area = self.area();
        if area <= 1e-9 * size * size {
            // Too little area for its size: an outline whose crossing lobes cancel (a bow-tie), the
            // vertices of one line, or a sliver; each is told apart, so the message says what to fix.
            if let Some((i, j)) = self.proper_crossing() {
                return Err(PolygonError::SelfIntersecting(i, j));
            }
            if self.width_across() <= 1e-12 * size {
                return Err(PolygonError::ZeroArea);
            }
            return Err(PolygonError::TooThin { area, size });
        }
        let tol = 1e-9 * size;
        let edges: Vec<_> = self.edges().collect();
        for i in 0..n {
            for j in i + 1..n {
                let adjacent = j == i + 1 || (i == 0 && j == n - 1);
                let (a0, a1) = edges[i];
                let (b0, b1) = edges[j];
                if adjacent {
                    // Adjacent edges may only share their common vertex: folding back onto each other
                    // (a spike) is a self-intersection too.
                    let (shared, other_a, other_b) = if j == i + 1 { (a1, a0, b1) } else { (a0, a1, b0) };
                    let u = other_a - shared;
                    let v = other_b - shared;
                    let folded = u.cross(v).abs() <= 1e-12 * u.norm() * v.norm() && u.dot(v) > 0.0;
                    if folded {
                        return Err(PolygonError::SelfIntersecting(i, j));
                    }
                } else if segments_cross(a0, a1, b0, b1, tol)
                    || point_segment_distance(b0, a0, a1) <= tol
                    || point_segment_distance(a0, b0, b1) <= tol
                {
                    return Err(PolygonError::SelfIntersecting(i, j));
                }
            }
        }
        Ok(())
    }

    /// The first two edges that cross each other at a point inside both, if any.
    fn proper_crossing(&self) -> Option<(usize, usize)> {
        let edges: Vec<_> = self.edges().collect();
        let n = edges.len();
        (0..n).flat_map(|i| (i + 2..n).map(move |j| (i, j))).filter(|&(i, j)| !(i == 0 && j == n - 1)).find(
            |&(i, j)| {
                let ((a0, a1), (b0, b1)) = (edges[i], edges[j]);
                super::segments_cross(a0, a1, b0, b1, 0.0)
            },
        )
    }

    /// How far the vertices stray from the line through the first vertex and the one farthest from
    /// it (0 when they all lie on it).
    fn width_across(&self) -> f64 {
        let Some(&p0) = self.vertices.first() else { return 0.0 };
        let far = self.vertices.iter().copied().max_by(|a, b| p0.distance(*a).total_cmp(&p0.distance(*b)));
        let Some(far) = far.filter(|&f| f != p0) else { return 0.0 };
        let along = (far - p0).normalized();
        self.vertices.iter().map(|&v| (v - p0).cross(along).abs()).fold(0.0, f64::max)
    }

    /// Even-odd containment; points on the boundary may answer either way.
    ///
    /// # Examples
    ///
    /// ```
    /// use linkwright_core::geom::{Point, Polygon};
    ///
    /// let p = Point::new;
    /// let square = Polygon::new(vec![p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)]);
    /// assert!(square.contains(p(0.5, 0.5)));
    /// assert!(!square.contains(p(1.5, 0.5)));
    /// ```
    pub fn contains(&self, p: Point) -> bool {
        contains_raw(&self.vertices, p)
    }
    /// Distance from `p` to the boundary.
    pub fn boundary_distance(&self, p: Point) -> f64 {
        boundary_distance_raw(&self.vertices, p)
    }
    /// Distance from `p` to the polygon's area: 0 inside.
    ///
    /// # Examples
    ///
    /// ```
    /// use linkwright_core::geom::{Point, Polygon};
    ///
    /// let p = Point::new;
    /// let square = Polygon::new(vec![p(0.0, 0.0), p(2.0, 0.0), p(2.0, 2.0), p(0.0, 2.0)]);
    /// assert_eq!(square.distance(p(1.0, 1.0)), 0.0);
    /// // Nearest to the right edge, x = 2.
    /// assert_eq!(square.distance(p(3.0, 1.0)), 1.0);
    /// // Nearest to the corner (2, 2): the hypotenuse of a 3-4-5 triangle.
    /// assert_eq!(square.distance(p(5.0, 6.0)), 5.0);
    /// // The distance to the boundary is not 0 inside.
    /// assert_eq!(square.boundary_distance(p(1.0, 1.5)), 0.5);
    /// ```
    pub fn distance(&self, p: Point) -> f64 {
        if self.contains(p) {
            0.0
        } else {
            self.boundary_distance(p)
        }
    }

    /// True when the interiors of the two polygons overlap by more than `tol` (a length): an edge of one
    /// crosses an edge of the other away from their ends, or a vertex or edge midpoint of one lies
    /// deeper than `tol` inside the other. Polygons that only touch along edges or at vertices do not
    /// penetrate.
    pub fn penetrates(&self, other: &Polygon, tol: f64) -> bool {
        if !self.aabb().overlaps(&other.aabb(), tol) {
            return false;
        }
        penetrates_unchecked(&self.vertices, &other.vertices, tol)
    }
}

/// The body of [`Polygon::penetrates`] on raw vertex lists (a two-point list is a segment), for callers
/// that keep transformed vertices in reused buffers and have already compared bounding boxes.
pub(crate) fn penetrates_unchecked(a: &[Point], b: &[Point], tol: f64) -> bool {
    let (na, nb) = (a.len(), b.len());
    let (Some(box_a), Some(box_b)) = (Aabb::around(a.iter().copied()), Aabb::around(b.iter().copied())) else {
        return false;
    };
    // Two edges can cross only where both boxes are: edges outside the other outline's box, and pairs
    // whose own boxes are apart, skip the exact test (boxes grown by `tol`: a crossing at a shallow
    // angle has boxes that barely overlap).
    for i in 0..na {
        let (a0, a1) = (a[i], a[(i + 1) % na]);
        let edge_a = segment_box(a0, a1);
        if !edge_a.overlaps(&box_b, -tol) {
            continue;
        }
        for j in 0..nb {
            let (b0, b1) = (b[j], b[(j + 1) % nb]);
            if edge_a.overlaps(&segment_box(b0, b1), -tol) && segments_cross(a0, a1, b0, b1, tol) {
                return true;
            }
        }
    }
    // Only points inside the other polygon's box can lie in it: the box test spares most
    // point-in-polygon tests.
    let deep_in = |pts: &[Point], poly: &[Point], bb: &Aabb| {
        let n = pts.len();
        (0..n).any(|i| {
            let mid = pts[i].lerp(pts[(i + 1) % n], 0.5);
            (bb.contains(pts[i]) && contains_deeply_raw(poly, pts[i], tol))
                || (bb.contains(mid) && contains_deeply_raw(poly, mid, tol))
        })
    };
    deep_in(a, b, &box_b) || deep_in(b, a, &box_a)
}

/// The least distance between the boundaries of two outlines (a two-point outline is a segment): the
/// nearest pair of boundary points always includes a vertex of one of them, so it is the least
/// distance between a vertex of one outline and an edge of the other. Edges whose box is farther from
/// the other outline's box than the best distance so far are skipped.
pub fn outline_distance(a: &[Point], b: &[Point]) -> f64 {
    let mut best = f64::INFINITY;
    for (p, q) in [(a, b), (b, a)] {
        let Some(box_p) = Aabb::around(p.iter().copied()) else { continue };
        let n = q.len();
        let edges = if n == 2 { 1 } else { n };
        for i in 0..edges {
            let (q0, q1) = (q[i], q[(i + 1) % n]);
            let edge = segment_box(q0, q1);
            let gap = box_p.gap(&edge);
            if gap * gap >= best {
                continue;
            }
            for &v in p {
                closer(&mut best, v, (q0, q1), &edge);
            }
        }
    }
    best.sqrt()
}

/// Lowers `best` (squared) to the distance between `v` and the edge `e0`–`e1` whose box is `edge`,
/// unless the box is already as far. One expression for the brute force and the obstacle index, so
/// that their distances agree.
pub(super) fn closer(best: &mut f64, v: Point, (e0, e1): (Point, Point), edge: &Aabb) {
    let dx = (edge.min.x - v.x).max(v.x - edge.max.x).max(0.0);
    let dy = (edge.min.y - v.y).max(v.y - edge.max.y).max(0.0);
    if dx * dx + dy * dy < *best {
        *best = best.min(point_segment_distance_sq(v, e0, e1));
    }
}

/// The box of a segment.
pub(super) fn segment_box(p: Point, q: Point) -> Aabb {
    Aabb { min: Point::new(p.x.min(q.x), p.y.min(q.y)), max: Point::new(p.x.max(q.x), p.y.max(q.y)) }
}

pub(super) fn contains_deeply_raw(poly: &[Point], p: Point, tol: f64) -> bool {
    contains_raw(poly, p) && boundary_distance_raw(poly, p) > tol
}

/// Even-odd containment on a raw vertex list.
pub(crate) fn contains_raw(poly: &[Point], p: Point) -> bool {
    let n = poly.len();
    let mut inside = false;
    for i in 0..n {
        if crosses_ray(poly[i], poly[(i + 1) % n], p) {
            inside = !inside;
        }
    }
    inside
}

/// Whether the even-odd test counts edge `a`–`b` for `p`: the edge spans p's height (half-open, so a
/// vertex at that height counts once) and crosses it right of `p`. One expression for every caller,
/// so that their answers agree to the last bit.
pub(super) fn crosses_ray(a: Point, b: Point, p: Point) -> bool {
    (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x)
}

/// The distance from `p` to the boundary of `poly`.
pub(super) fn boundary_distance_raw(poly: &[Point], p: Point) -> f64 {
    let n = poly.len();
    (0..n).map(|i| point_segment_distance(p, poly[i], poly[(i + 1) % n])).fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::testing::assert_close;

    fn square(x: f64, y: f64, s: f64) -> Polygon {
        let p = Point::new;
        Polygon::new(vec![p(x, y), p(x + s, y), p(x + s, y + s), p(x, y + s)])
    }

    #[test]
    fn area_and_centroid_of_a_square() {
        let sq = square(1.0, 2.0, 2.0);
        assert_close(sq.signed_area(), 4.0, 1e-12);
        let c = sq.centroid();
        assert_close(c.x, 2.0, 1e-12);
        assert_close(c.y, 3.0, 1e-12);
    }

    #[test]
    fn validation_catches_bad_polygons() {
        let p = Point::new;
        assert_eq!(Polygon::new(vec![p(0., 0.), p(1., 0.)]).validate(), Err(PolygonError::TooFewVertices(2)));
        assert_eq!(Polygon::new(vec![p(0., 0.), p(1., 0.), p(2., 0.)]).validate(), Err(PolygonError::ZeroArea));
        let bowtie = Polygon::new(vec![p(0., 0.), p(2., 2.), p(2., 0.), p(0., 1.)]);
        assert!(matches!(bowtie.validate(), Err(PolygonError::SelfIntersecting(..))));
        let nan = Polygon::new(vec![p(0., 0.), p(f64::NAN, 1.), p(1., 0.)]);
        assert_eq!(nan.validate(), Err(PolygonError::NonFinite(1)));
        assert_eq!(square(0., 0., 1.).validate(), Ok(()));
    }

    #[test]
    fn a_symmetric_bow_tie_crosses_itself_and_a_sliver_is_too_thin() {
        let p = Point::new;
        // Its two lobes cancel, so its signed area is 0, but its vertices are not on one line.
        let bowtie = Polygon::new(vec![p(0., 0.), p(2., 2.), p(2., 0.), p(0., 2.)]);
        assert_eq!(bowtie.validate(), Err(PolygonError::SelfIntersecting(0, 2)));
        let sliver = Polygon::new(vec![p(0., 0.), p(1000., 0.), p(1000., 1e-6), p(0., 1e-6)]);
        let Err(PolygonError::TooThin { area, size }) = sliver.validate() else { panic!("{:?}", sliver.validate()) };
        assert_close(area, 1e-3, 1e-12);
        assert_close(size, 1000.0, 1e-9);
        let words = sliver.validate().unwrap_err().to_string();
        assert_eq!(words, "is too thin: about 1.0e-6 wide for 1.0e3 long (an area of 1.0e-3)");
        // A sliver a thousand times wider is a valid, if thin, outline.
        assert_eq!(Polygon::new(vec![p(0., 0.), p(1000., 0.), p(1000., 1e-3), p(0., 1e-3)]).validate(), Ok(()));
    }

    #[test]
    fn touching_squares_do_not_penetrate_but_overlapping_do() {
        let a = square(0.0, 0.0, 1.0);
        assert!(!a.penetrates(&square(1.0, 0.0, 1.0), 1e-9));
        assert!(!a.penetrates(&square(1.0, 1.0, 1.0), 1e-9));
        assert!(a.penetrates(&square(0.5, 0.5, 1.0), 1e-9));
        // One inside the other, no edges crossing.
        assert!(a.penetrates(&square(0.25, 0.25, 0.5), 1e-9));
        // A plus sign: edges cross, no vertex inside.
        let p = Point::new;
        let bar = Polygon::new(vec![p(-1., 0.4), p(2., 0.4), p(2., 0.6), p(-1., 0.6)]);
        assert!(a.penetrates(&bar, 1e-9));
    }

    #[test]
    fn distances() {
        let a = square(0.0, 0.0, 2.0);
        assert_close(a.distance(Point::new(1.0, 1.0)), 0.0, 0.0);
        assert_close(a.boundary_distance(Point::new(1.0, 1.5)), 0.5, 1e-12);
        assert_close(a.distance(Point::new(5.0, 6.0)), 5.0, 1e-12);
    }
}
