//! Points (positions) and vectors (displacements), kept apart by their operators.

use serde::{Deserialize, Serialize};
use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

/// A displacement in the plane.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Vec2 {
    /// Component along x.
    pub x: f64,
    /// Component along y (up).
    pub y: f64,
}

/// A position in the plane. Serialized as `[x, y]`, as the file formats write points.
///
/// # Examples
///
/// Two points differ by a [`Vec2`], and a point moved by a vector is a point; two points do not add.
///
/// ```
/// use linkwright_core::geom::{Point, Vec2};
///
/// let a = Point::new(1.0, 2.0);
/// let b = Point::new(4.0, 6.0);
/// assert_eq!(b - a, Vec2::new(3.0, 4.0));
/// assert_eq!(a + (b - a), b);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(from = "[f64; 2]", into = "[f64; 2]")]
pub struct Point {
    /// Coordinate along x.
    pub x: f64,
    /// Coordinate along y (up).
    pub y: f64,
}

impl Vec2 {
    /// The zero displacement.
    pub const ZERO: Vec2 = Vec2 { x: 0.0, y: 0.0 };

    /// The vector with these components.
    pub const fn new(x: f64, y: f64) -> Self {
        Vec2 { x, y }
    }
    /// The unit vector at `angle` radians from the x axis.
    ///
    /// # Examples
    ///
    /// ```
    /// use linkwright_core::geom::Vec2;
    /// use std::f64::consts::FRAC_PI_3;
    ///
    /// // 60° from the x axis: (cos 60°, sin 60°) = (1/2, √3/2).
    /// let v = Vec2::from_angle(FRAC_PI_3);
    /// assert!((v.x - 0.5).abs() < 1e-15);
    /// assert!((v.y - 3f64.sqrt() / 2.0).abs() < 1e-15);
    /// ```
    pub fn from_angle(angle: f64) -> Self {
        let (s, c) = angle.sin_cos();
        Vec2::new(c, s)
    }
    /// The dot product.
    ///
    /// # Examples
    ///
    /// ```
    /// use linkwright_core::geom::Vec2;
    ///
    /// assert_eq!(Vec2::new(3.0, 4.0).dot(Vec2::new(3.0, 4.0)), 25.0);
    /// // Perpendicular vectors.
    /// assert_eq!(Vec2::new(3.0, 4.0).dot(Vec2::new(-4.0, 3.0)), 0.0);
    /// ```
    pub fn dot(self, o: Vec2) -> f64 {
        self.x * o.x + self.y * o.y
    }
    /// The z component of the 3D cross product: positive when `o` is counter-clockwise of `self`.
    ///
    /// # Examples
    ///
    /// ```
    /// use linkwright_core::geom::Vec2;
    ///
    /// let (x, y) = (Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0));
    /// assert_eq!(x.cross(y), 1.0);
    /// assert_eq!(y.cross(x), -1.0);
    /// // Its magnitude is the area of the parallelogram the two vectors span: base 3, height 2.
    /// assert_eq!(Vec2::new(3.0, 0.0).cross(Vec2::new(5.0, 2.0)), 6.0);
    /// ```
    pub fn cross(self, o: Vec2) -> f64 {
        self.x * o.y - self.y * o.x
    }
    /// The squared length (no square root).
    pub fn norm_sq(self) -> f64 {
        self.dot(self)
    }
    /// Euclidean length. A plain square root, not `hypot`: it is several times faster, and coordinates
    /// of drawings (validated to at most 1e9) are far from overflowing when squared.
    pub fn norm(self) -> f64 {
        self.norm_sq().sqrt()
    }
    /// Rotated a quarter turn counter-clockwise.
    ///
    /// # Examples
    ///
    /// ```
    /// use linkwright_core::geom::Vec2;
    ///
    /// assert_eq!(Vec2::new(1.0, 0.0).perp(), Vec2::new(0.0, 1.0));
    /// assert_eq!(Vec2::new(3.0, 4.0).perp(), Vec2::new(-4.0, 3.0));
    /// ```
    pub fn perp(self) -> Vec2 {
        Vec2::new(-self.y, self.x)
    }
    /// Angle from the x axis, in (−π, π].
    ///
    /// # Examples
    ///
    /// ```
    /// use linkwright_core::geom::Vec2;
    /// use std::f64::consts::{FRAC_PI_4, PI};
    ///
    /// assert!((Vec2::new(1.0, 1.0).angle() - FRAC_PI_4).abs() < 1e-15);
    /// assert_eq!(Vec2::new(-1.0, 0.0).angle(), PI);
    /// assert!((Vec2::new(0.0, -2.0).angle() + PI / 2.0).abs() < 1e-15);
    /// ```
    pub fn angle(self) -> f64 {
        self.y.atan2(self.x)
    }
    /// The unit vector along `self` (NaN components for the zero vector).
    pub fn normalized(self) -> Vec2 {
        self / self.norm()
    }
    /// Whether both components are finite.
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite()
    }
}

impl Point {
    /// The origin of the world.
    pub const ORIGIN: Point = Point { x: 0.0, y: 0.0 };

    /// The point with these coordinates.
    pub const fn new(x: f64, y: f64) -> Self {
        Point { x, y }
    }
    /// The vector from the origin to this point.
    pub fn to_vec2(self) -> Vec2 {
        Vec2::new(self.x, self.y)
    }
    /// The Euclidean distance to `o`.
    ///
    /// # Examples
    ///
    /// ```
    /// use linkwright_core::geom::Point;
    ///
    /// // The hypotenuse of a 3-4-5 right triangle.
    /// assert_eq!(Point::new(1.0, 1.0).distance(Point::new(4.0, 5.0)), 5.0);
    /// ```
    pub fn distance(self, o: Point) -> f64 {
        (self - o).norm()
    }
    /// Whether both coordinates are finite.
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite()
    }
    /// The point a fraction `t` of the way from `self` to `o`.
    ///
    /// # Examples
    ///
    /// ```
    /// use linkwright_core::geom::Point;
    ///
    /// let (a, b) = (Point::new(0.0, 0.0), Point::new(4.0, 2.0));
    /// assert_eq!(a.lerp(b, 0.5), Point::new(2.0, 1.0));
    /// assert_eq!(a.lerp(b, 0.0), a);
    /// assert_eq!(a.lerp(b, 1.0), b);
    /// ```
    pub fn lerp(self, o: Point, t: f64) -> Point {
        self + (o - self) * t
    }
}

impl From<[f64; 2]> for Point {
    fn from(a: [f64; 2]) -> Self {
        Point::new(a[0], a[1])
    }
}
impl From<Point> for [f64; 2] {
    fn from(p: Point) -> Self {
        [p.x, p.y]
    }
}

impl Sub for Point {
    type Output = Vec2;
    fn sub(self, o: Point) -> Vec2 {
        Vec2::new(self.x - o.x, self.y - o.y)
    }
}
impl Add<Vec2> for Point {
    type Output = Point;
    fn add(self, v: Vec2) -> Point {
        Point::new(self.x + v.x, self.y + v.y)
    }
}
impl Sub<Vec2> for Point {
    type Output = Point;
    fn sub(self, v: Vec2) -> Point {
        Point::new(self.x - v.x, self.y - v.y)
    }
}
impl Add for Vec2 {
    type Output = Vec2;
    fn add(self, o: Vec2) -> Vec2 {
        Vec2::new(self.x + o.x, self.y + o.y)
    }
}
impl AddAssign for Vec2 {
    fn add_assign(&mut self, o: Vec2) {
        self.x += o.x;
        self.y += o.y;
    }
}
impl Sub for Vec2 {
    type Output = Vec2;
    fn sub(self, o: Vec2) -> Vec2 {
        Vec2::new(self.x - o.x, self.y - o.y)
    }
}
impl Neg for Vec2 {
    type Output = Vec2;
    fn neg(self) -> Vec2 {
        Vec2::new(-self.x, -self.y)
    }
}
impl Mul<f64> for Vec2 {
    type Output = Vec2;
    fn mul(self, s: f64) -> Vec2 {
        Vec2::new(self.x * s, self.y * s)
    }
}
impl Div<f64> for Vec2 {
    type Output = Vec2;
    fn div(self, s: f64) -> Vec2 {
        Vec2::new(self.x / s, self.y / s)
    }
}
