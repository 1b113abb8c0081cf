//! The two dyads every step of a plan reduces to, as small pure functions with typed answers.

use crate::geom::{Point, Vec2};

/// Which of the two assemblies a dyad takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Branch {
    /// Circle-circle: the joint is left of the line from the first centre to the second.
    /// Circle-line: the joint is ahead of the foot of the perpendicular, along the line's direction.
    Positive,
    /// The other assembly.
    Negative,
}

impl Branch {
    /// The other assembly.
    pub fn other(self) -> Branch {
        match self {
            Branch::Positive => Branch::Negative,
            Branch::Negative => Branch::Positive,
        }
    }
    fn sign(self) -> f64 {
        match self {
            Branch::Positive => 1.0,
            Branch::Negative => -1.0,
        }
    }
}

/// Why a dyad has no solution.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum DyadError {
    /// Circle-circle: the two circles do not meet (the links are too short, or too long, to close the
    /// loop).
    #[error("the two circles do not meet")]
    CirclesApart,
    /// Circle-line: the circle does not reach the slider's line.
    #[error("the circle does not reach the line")]
    LineOutOfReach,
    /// Circle-circle: the two centres coincide, so the dyad's direction is undefined.
    #[error("the two centres coincide")]
    CoincidentCentres,
}

/// The point at distance `ra` from `a` and `rb` from `b` on the given branch.
///
/// In units of `b − a`: the foot of the joint on the centres' line is `t·(b − a)` from `a`, and its
/// offset across `k·(b − a)`, so one division and one square root give the point. This is the
/// simulation's innermost step; computed with the distance `|b − a|` itself, it would take three
/// divisions and two square roots.
///
/// # Examples
///
/// Centres 5 apart and radii 3 and 4: the joint closes a 3-4-5 right triangle, at (1.8, ±2.4).
///
/// ```
/// use linkwright_core::geom::Point;
/// use linkwright_core::kinematics::{circle_circle, Branch, DyadError};
///
/// let (a, b) = (Point::new(0.0, 0.0), Point::new(5.0, 0.0));
/// // Left of the line from `a` to `b`, then right of it.
/// let left = circle_circle(a, 3.0, b, 4.0, Branch::Positive)?;
/// assert!(left.distance(Point::new(1.8, 2.4)) < 1e-12);
/// let right = circle_circle(a, 3.0, b, 4.0, Branch::Negative)?;
/// assert!(right.distance(Point::new(1.8, -2.4)) < 1e-12);
/// // Links of 2 and 2 cannot span the 5 between the centres.
/// assert_eq!(circle_circle(a, 2.0, b, 2.0, Branch::Positive), Err(DyadError::CirclesApart));
/// # Ok::<(), DyadError>(())
/// ```
pub fn circle_circle(a: Point, ra: f64, b: Point, rb: f64, branch: Branch) -> Result<Point, DyadError> {
    let ab = b - a;
    let d_sq = ab.norm_sq();
    if d_sq <= 1e-300 {
        return Err(DyadError::CoincidentCentres);
    }
    let inverse = 1.0 / d_sq;
    let t = 0.5 * (d_sq + ra * ra - rb * rb) * inverse;
    let k_sq = ra * ra * inverse - t * t;
    if k_sq < 0.0 || !k_sq.is_finite() {
        return Err(DyadError::CirclesApart);
    }
    Ok(a + ab * t + ab.perp() * (branch.sign() * k_sq.sqrt()))
}

/// Which branch `p` is on, relative to the centres `a`, `b` of a circle-circle dyad.
///
/// # Examples
///
/// ```
/// use linkwright_core::geom::Point;
/// use linkwright_core::kinematics::{circle_circle_branch, Branch};
///
/// let (a, b) = (Point::new(0.0, 0.0), Point::new(5.0, 0.0));
/// assert_eq!(circle_circle_branch(a, b, Point::new(1.8, 2.4)), Branch::Positive);
/// assert_eq!(circle_circle_branch(a, b, Point::new(1.8, -2.4)), Branch::Negative);
/// // Seen from `b` towards `a`, left and right swap.
/// assert_eq!(circle_circle_branch(b, a, Point::new(1.8, 2.4)), Branch::Negative);
/// ```
pub fn circle_circle_branch(a: Point, b: Point, p: Point) -> Branch {
    if (b - a).cross(p - a) >= 0.0 {
        Branch::Positive
    } else {
        Branch::Negative
    }
}

/// The point at distance `r` from `c` on the line through `origin` with unit `direction`.
pub(crate) fn circle_line(
    c: Point,
    r: f64,
    origin: Point,
    direction: Vec2,
    branch: Branch,
) -> Result<Point, DyadError> {
    let w = c - origin;
    let foot = w.dot(direction);
    let off_sq = w.norm_sq() - foot * foot;
    let h_sq = r * r - off_sq;
    if h_sq < 0.0 || !h_sq.is_finite() {
        return Err(DyadError::LineOutOfReach);
    }
    Ok(origin + direction * (foot + branch.sign() * h_sq.sqrt()))
}

/// Which branch `p` (on the line) is on, relative to the circle centre `c`.
pub(crate) fn circle_line_branch(c: Point, origin: Point, direction: Vec2, p: Point) -> Branch {
    if (p - origin).dot(direction) >= (c - origin).dot(direction) {
        Branch::Positive
    } else {
        Branch::Negative
    }
}

/// The sine of the angle between `u` and `v`, which is the sine of its transmission margin: it orders
/// margins as they do (the margin lies in [0, π/2]) without an inverse trigonometric function per step.
pub(crate) fn transmission_sine(u: Vec2, v: Vec2) -> f64 {
    let norms = (u.norm_sq() * v.norm_sq()).sqrt();
    if norms > 0.0 {
        (u.cross(v).abs() / norms).min(1.0)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::testing::assert_close;
    use proptest::prelude::*;

    proptest! {
        /// A joint placed by the dyad is at the requested distances and on the requested branch.
        #[test]
        fn circle_circle_keeps_distances(ax in -10.0..10.0f64, ay in -10.0..10.0f64,
                                         bx in -10.0..10.0f64, by in -10.0..10.0f64,
                                         px in -10.0..10.0f64, py in -10.0..10.0f64) {
            let (a, b, p) = (Point::new(ax, ay), Point::new(bx, by), Point::new(px, py));
            prop_assume!(a.distance(b) > 1e-3);
            let branch = circle_circle_branch(a, b, p);
            let q = circle_circle(a, a.distance(p), b, b.distance(p), branch).unwrap();
            assert_close(q.x, p.x, 1e-6 * (1.0 + p.x.abs()));
            assert_close(q.y, p.y, 1e-6 * (1.0 + p.y.abs()));
        }

        #[test]
        fn circle_line_keeps_distance(cx in -10.0..10.0f64, cy in -10.0..10.0f64, s in -10.0..10.0f64,
                                      angle in -3.2..3.2f64) {
            let c = Point::new(cx, cy);
            let dir = Vec2::from_angle(angle);
            let origin = Point::new(1.0, -2.0);
            let p = origin + dir * s;
            let branch = circle_line_branch(c, origin, dir, p);
            let q = circle_line(c, c.distance(p), origin, dir, branch).unwrap();
            prop_assert!(q.distance(p) < 1e-6 * (1.0 + s.abs()));
        }

        #[test]
        fn circles_too_far_apart_are_an_error(d in 2.1..100.0f64) {
            let r = circle_circle(Point::ORIGIN, 1.0, Point::new(d, 0.0), 1.0, Branch::Positive);
            prop_assert_eq!(r, Err(DyadError::CirclesApart));
        }
    }

    #[test]
    fn transmission_margin_of_right_and_flat_angles() {
        assert_close(
            transmission_sine(Vec2::new(1.0, 0.0), Vec2::new(0.0, 2.0)).asin(),
            std::f64::consts::FRAC_PI_2,
            1e-15,
        );
        assert_close(transmission_sine(Vec2::new(1.0, 0.0), Vec2::new(-3.0, 0.0)).asin(), 0.0, 1e-15);
        assert_close(
            transmission_sine(Vec2::new(1.0, 0.0), Vec2::new(1.0, 1.0)).asin(),
            std::f64::consts::FRAC_PI_4,
            1e-15,
        );
    }
}
