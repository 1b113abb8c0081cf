//! What the path search needs of a family of linkages: the tracer's place at a crank angle (in closed
//! form: the atlas traces thousands of curves), a random normalised member for the atlas, its
//! dimensions as a vector to refine, and the design it makes. One implementation per family.

use crate::geom::{Point, Vec2};
use crate::kinematics::Branch;
use crate::mechanism::Mechanism;
use crate::scene::MechanismType;
use rand::RngExt;
use rand_xoshiro::Xoshiro256PlusPlus;

/// The tracer at one crank angle, and how well the linkage transmits there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TracerAt {
    pub point: Point,
    /// The direction of the body's own x axis (not of unit length): how far the body has turned.
    pub heading: Vec2,
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

/// The point `(u, v)` of a body in the frame with its origin at joint `origin` and its x axis
/// towards joint `towards`, `length` away: where every family's tracer rides.
pub(crate) fn on_body(origin: Point, towards: Point, length: f64, u: f64, v: f64) -> Point {
    let x = (towards - origin) / length;
    origin + x * u + x.perp() * v
}

/// Either assembly of a dyad, at random.
pub(crate) fn random_branch(r: &mut Xoshiro256PlusPlus) -> Branch {
    if r.random::<bool>() {
        Branch::Positive
    } else {
        Branch::Negative
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Rigid;
    use crate::kinematics::{BodyFrames, Plan};
    use crate::synth::path::four_bar::FourBar;
    use crate::synth::path::six_bars::{StephensonThree, WattTwo};
    use crate::synth::path::slider_crank::SliderCrank;
    use rand::SeedableRng;

    /// The closed form of family `L` against the engine's general solver: members drawn for the
    /// atlas, mapped by a similarity, made into designs at one crank angle and simulated by
    /// [`Plan`] at others; the tracer (carried by the body's frame) and the transmission agree.
    fn agrees_with_the_general_solver<L: PathLinkage>() {
        let map = Similarity { from: Point::new(0.2, -0.1), to: Point::new(40.0, 25.0), scale: 30.0, turn: 2.0 };
        let mut checked = 0;
        for seed in 0..40 {
            let mut r = Xoshiro256PlusPlus::seed_from_u64(seed);
            let Some(m) = L::sample(&mut r) else { continue };
            let m = m.mapped(&map);
            let Some(mechanism) = m.mechanism(0.3) else { continue };
            assert_eq!(mechanism.topology.mechanism_type, L::FAMILY);
            let start = m.tracer_at(0.3).unwrap().point;
            let frames = BodyFrames::new(&mechanism, &[Rigid::new(0.0, start - Point::ORIGIN)]);
            let plan = Plan::compile(&mechanism).unwrap();
            let mut row = vec![Point::ORIGIN; plan.joint_count()];
            // Small steps from the start, so the general solver keeps every dyad's branch.
            let mut compared = 0;
            for k in 0..=60 {
                let theta = 0.3 + 0.02 * k as f64;
                let (Some(closed_form), Ok(())) = (m.tracer_at(theta), plan.solve(theta, &mut row)) else {
                    break;
                };
                let general = frames.pose(0, &row).apply(Point::ORIGIN);
                assert!(general.distance(closed_form.point) < 1e-9 * map.scale, "{m:?} at {theta}");
                let sine = plan.min_transmission_sine(&row);
                assert!((sine - closed_form.transmission_sine).abs() < 1e-9, "{m:?} at {theta}");
                compared += 1;
            }
            // Both assemble where the design was made, and a good way on.
            assert!(compared >= 10, "{m:?}: only {compared} angles compared");
            checked += 1;
        }
        assert!(checked >= 10, "only {checked} members drawn");
    }

    #[test]
    fn every_familys_closed_form_agrees_with_the_general_solver() {
        agrees_with_the_general_solver::<FourBar>();
        agrees_with_the_general_solver::<StephensonThree>();
        agrees_with_the_general_solver::<WattTwo>();
        agrees_with_the_general_solver::<SliderCrank>();
    }
}
