//! What the path search needs of a family of linkages: the tracer's place at a crank angle (in closed
//! form: the atlas traces thousands of curves), a random normalised member for the atlas, its
//! dimensions as a vector to refine, and the design it makes. One implementation per family.

use crate::geom::{Point, Vec2};
use crate::mechanism::Mechanism;
use crate::scene::MechanismType;
use rand_xoshiro::Xoshiro256PlusPlus;

/// The tracer at one crank angle, and how well the linkage transmits there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TracerAt {
    pub point: Point,
    /// The least sine of a transmission angle over the linkage's dyads, in [0, 1], measured as
    /// [`Plan::min_transmission_sine`](crate::kinematics::Plan::min_transmission_sine) does.
    pub transmission_sine: f64,
}

/// A similarity of the plane: `p ↦ to + scale·turn(p − from)`, which maps a normalised atlas member
/// onto the drawn curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Similarity {
    pub from: Point,
    pub to: Point,
    pub scale: f64,
    /// The turn, radians.
    pub turn: f64,
}

impl Similarity {
    /// The translation by `by`.
    pub(crate) fn shift(by: Vec2) -> Similarity {
        Similarity { from: Point::ORIGIN, to: Point::ORIGIN + by, scale: 1.0, turn: 0.0 }
    }
    pub(crate) fn point(&self, p: Point) -> Point {
        let v = p - self.from;
        let (s, c) = self.turn.sin_cos();
        self.to + Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y) * self.scale
    }
}

/// A family of linkages whose crank turns about a ground pivot and whose tracer rides on the moving
/// body.
pub(crate) trait PathLinkage: Copy + std::fmt::Debug + Send + Sync + Sized {
    /// The family a design of it belongs to.
    const FAMILY: MechanismType;
    /// The stream of the family's atlas samples, apart from every other's.
    const STREAM: u64;

    /// The tracer at crank angle `theta` (radians), or `None` where the linkage does not assemble.
    fn tracer_at(&self, theta: f64) -> Option<TracerAt>;

    /// A random member, normalised (its size and turn are the similarity's), whose crank turns
    /// fully; `None` when the draw does not give one.
    fn sample(rng: &mut Xoshiro256PlusPlus) -> Option<Self>;

    /// The member mapped by `map`: every point moved, every length scaled, every direction turned.
    fn mapped(&self, map: &Similarity) -> Self;

    /// The dimensions the refinement moves, and the member with other values of them.
    fn params(&self) -> Vec<f64>;
    fn with_params(&self, x: &[f64]) -> Self;
    /// Whether parameter `k` is an angle (radians) rather than a length or a coordinate.
    fn is_angle(_k: usize) -> bool {
        false
    }

    /// The design: every joint where it is at crank angle `theta`, in the family's topology.
    fn mechanism(&self, theta: f64) -> Option<Mechanism>;
}
