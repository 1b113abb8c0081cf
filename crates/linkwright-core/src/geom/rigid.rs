//! Rigid transforms of the plane (rotation then translation).

use super::vector::{Point, Vec2};

/// A proper rigid motion `p ↦ R(angle)·p + translation`.
///
/// Named by frames: `body_to_world` maps body-frame points into the world. Composition reads left to
/// right with [`Rigid::then`]: `a.then(b)` applies `a` first.
///
/// # Examples
///
/// A quarter turn counter-clockwise about the origin takes the x axis to the y axis.
///
/// ```
/// use linkwright_core::geom::{Point, Rigid, Vec2};
/// use std::f64::consts::FRAC_PI_2;
///
/// let quarter_turn = Rigid::new(FRAC_PI_2, Vec2::ZERO);
/// let p = quarter_turn.apply(Point::new(1.0, 0.0));
/// assert!(p.distance(Point::new(0.0, 1.0)) < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rigid {
    /// Unwrapped: composing adds angles.
    angle: f64,
    isometry: Isometry,
}

/// A [`Rigid`] motion without its angle: the rotation's cosine and sine, and the translation. The
/// collision sweep places outlines by it from two joints, where recovering the angle (an `atan2`)
/// would be wasted. The same arithmetic as [`Rigid`]'s, so the same points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Isometry {
    cos: f64,
    sin: f64,
    translation: Vec2,
}

impl Rigid {
    /// The motion that moves nothing.
    pub const IDENTITY: Rigid =
        Rigid { angle: 0.0, isometry: Isometry { cos: 1.0, sin: 0.0, translation: Vec2::ZERO } };

    /// Rotation by `angle` radians about the origin, then translation.
    pub fn new(angle: f64, translation: Vec2) -> Self {
        let (sin, cos) = angle.sin_cos();
        Rigid { angle, isometry: Isometry { cos, sin, translation } }
    }
    /// A pose as the scene writes it: `[x, y, angle_deg]`.
    ///
    /// # Examples
    ///
    /// ```
    /// use linkwright_core::geom::{Rigid, Vec2};
    ///
    /// let body_to_world = Rigid::from_pose([10.0, 5.0, 90.0]);
    /// assert_eq!(body_to_world.translation(), Vec2::new(10.0, 5.0));
    /// assert!((body_to_world.angle() - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    /// ```
    pub fn from_pose(pose: [f64; 3]) -> Self {
        Rigid::new(pose[2].to_radians(), Vec2::new(pose[0], pose[1]))
    }
    /// The frame whose origin is `origin` and whose x axis points along `x_axis` (need not be unit).
    pub fn from_frame(origin: Point, x_axis: Vec2) -> Self {
        Rigid { angle: x_axis.angle(), isometry: Isometry::from_frame(origin, x_axis) }
    }
    /// Back to `[x, y, angle_deg]`.
    pub fn to_pose(&self) -> [f64; 3] {
        let t = self.isometry.translation;
        [t.x, t.y, self.angle.to_degrees()]
    }
    /// The rotation angle, radians, unwrapped (composing adds angles).
    pub fn angle(&self) -> f64 {
        self.angle
    }
    /// Where the motion takes the origin, as a vector.
    pub fn translation(&self) -> Vec2 {
        self.isometry.translation
    }
    /// The motion without its angle.
    pub fn isometry(&self) -> Isometry {
        self.isometry
    }
    /// `v` rotated by the motion's angle (a vector is not translated).
    pub fn rotate(&self, v: Vec2) -> Vec2 {
        self.isometry.rotate(v)
    }
    /// Rotation by the inverse angle.
    pub fn unrotate(&self, v: Vec2) -> Vec2 {
        self.isometry.unrotate(v)
    }
    /// Where the motion takes `p`.
    ///
    /// # Examples
    ///
    /// A body posed at `(10, 5)` and turned 90°: the point one unit along its x axis is one unit above
    /// its origin in the world.
    ///
    /// ```
    /// use linkwright_core::geom::{Point, Rigid};
    ///
    /// let body_to_world = Rigid::from_pose([10.0, 5.0, 90.0]);
    /// let p_world = body_to_world.apply(Point::new(1.0, 0.0));
    /// assert!(p_world.distance(Point::new(10.0, 6.0)) < 1e-12);
    /// ```
    pub fn apply(&self, p: Point) -> Point {
        self.isometry.apply(p)
    }
    /// The motion that undoes this one.
    ///
    /// # Examples
    ///
    /// ```
    /// use linkwright_core::geom::{Point, Rigid};
    ///
    /// let body_to_world = Rigid::from_pose([10.0, 5.0, 90.0]);
    /// let world_to_body = body_to_world.inverse();
    /// // The body's origin, and the world point one unit above it, seen from the body.
    /// assert!(world_to_body.apply(Point::new(10.0, 5.0)).distance(Point::ORIGIN) < 1e-12);
    /// assert!(world_to_body.apply(Point::new(10.0, 6.0)).distance(Point::new(1.0, 0.0)) < 1e-12);
    /// ```
    pub fn inverse(&self) -> Rigid {
        Rigid { angle: -self.angle, isometry: self.isometry.inverse() }
    }
    /// `self` followed by `next`.
    ///
    /// # Examples
    ///
    /// Order matters: a quarter turn then a shift along x is not the shift then the turn.
    ///
    /// ```
    /// use linkwright_core::geom::{Point, Rigid, Vec2};
    /// use std::f64::consts::FRAC_PI_2;
    ///
    /// let turn = Rigid::new(FRAC_PI_2, Vec2::ZERO);
    /// let shift = Rigid::new(0.0, Vec2::new(2.0, 0.0));
    /// let p = Point::new(1.0, 0.0);
    /// // Turned to (0, 1), then shifted to (2, 1).
    /// assert!(turn.then(&shift).apply(p).distance(Point::new(2.0, 1.0)) < 1e-15);
    /// // Shifted to (3, 0), then turned to (0, 3).
    /// assert!(shift.then(&turn).apply(p).distance(Point::new(0.0, 3.0)) < 1e-15);
    /// // Angles add.
    /// assert_eq!(turn.then(&turn).angle(), std::f64::consts::PI);
    /// ```
    pub fn then(&self, next: &Rigid) -> Rigid {
        Rigid { angle: self.angle + next.angle, isometry: self.isometry.then(&next.isometry) }
    }
    /// The transform that takes `self`'s output frame to `other`'s: `self.inverse().then(other)`.
    /// With poses of one body, `pose_1.to(&pose_i)` moves world points carried by the body from pose 1
    /// to pose i.
    pub fn to(&self, other: &Rigid) -> Rigid {
        self.inverse().then(other)
    }
}

impl Isometry {
    /// [`Rigid::from_frame`] without the angle.
    pub fn from_frame(origin: Point, x_axis: Vec2) -> Self {
        let length = x_axis.norm();
        if !(length > 0.0 && length.is_finite()) {
            return Rigid::new(x_axis.angle(), origin.to_vec2()).isometry;
        }
        Isometry { cos: x_axis.x / length, sin: x_axis.y / length, translation: origin.to_vec2() }
    }
    /// `v` rotated by the motion's rotation (a vector is not translated).
    pub fn rotate(&self, v: Vec2) -> Vec2 {
        Vec2::new(self.cos * v.x - self.sin * v.y, self.sin * v.x + self.cos * v.y)
    }
    /// Rotation by the inverse angle.
    pub fn unrotate(&self, v: Vec2) -> Vec2 {
        Vec2::new(self.cos * v.x + self.sin * v.y, -self.sin * v.x + self.cos * v.y)
    }
    /// Where the motion takes `p`.
    pub fn apply(&self, p: Point) -> Point {
        Point::ORIGIN + self.rotate(p.to_vec2()) + self.translation
    }
    /// The motion that undoes this one.
    pub fn inverse(&self) -> Isometry {
        Isometry { cos: self.cos, sin: -self.sin, translation: -self.unrotate(self.translation) }
    }
    /// `self` followed by `next`. The rotations compose as products of their cosines and sines (no
    /// trigonometric call: composing is the kinematic sweep's most frequent operation).
    pub fn then(&self, next: &Isometry) -> Isometry {
        Isometry {
            cos: self.cos * next.cos - self.sin * next.sin,
            sin: self.sin * next.cos + self.cos * next.sin,
            translation: next.rotate(self.translation) + next.translation,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::testing::assert_close;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn inverse_undoes(a in -7.0..7.0f64, tx in -1e3..1e3f64, ty in -1e3..1e3f64,
                          px in -1e3..1e3f64, py in -1e3..1e3f64) {
            let t = Rigid::new(a, Vec2::new(tx, ty));
            let p = Point::new(px, py);
            let back = t.inverse().apply(t.apply(p));
            assert_close(back.x, p.x, 1e-9);
            assert_close(back.y, p.y, 1e-9);
        }

        #[test]
        fn then_composes_left_to_right(a in -7.0..7.0f64, b in -7.0..7.0f64, px in -50.0..50.0f64) {
            let t1 = Rigid::new(a, Vec2::new(1.0, -2.0));
            let t2 = Rigid::new(b, Vec2::new(-3.0, 0.5));
            let p = Point::new(px, 2.0);
            let composed = t1.then(&t2).apply(p);
            let stepwise = t2.apply(t1.apply(p));
            assert_close(composed.x, stepwise.x, 1e-9);
            assert_close(composed.y, stepwise.y, 1e-9);
        }
    }

    #[test]
    fn pose_moves_body_points() {
        let pose = Rigid::from_pose([10.0, 5.0, 90.0]);
        let p = pose.apply(Point::new(1.0, 0.0));
        assert_close(p.x, 10.0, 1e-12);
        assert_close(p.y, 6.0, 1e-12);
    }
}
