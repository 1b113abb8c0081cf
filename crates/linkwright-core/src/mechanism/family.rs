//! Linkage families: what the engine needs to know of each to build, search, analyse and name its
//! linkages, and to draw random ones. A new family is one more implementation of [`Family`] in this
//! module, returned by [`MechanismType::family`] for its word in files.

use super::dimensioned::{Mechanism, SliderLine};
use super::topology::Topology;
use crate::geom::{Point, Vec2};
use crate::scene::MechanismType;
use rand::{Rng, RngExt};
use std::f64::consts::PI;
use std::sync::Arc;

/// A family of linkages.
pub trait Family: Sync {
    /// The family's word in files.
    fn mechanism_type(&self) -> MechanismType;
    /// What a person calls the family.
    fn label(&self) -> &'static str;
    /// The family in a few words, for a menu.
    fn description(&self) -> &'static str;
    /// What a person calls this family's linkage for `bodies` moving bodies.
    fn linkage_label(&self, bodies: usize) -> String;
    /// The family's linkage for `bodies` moving bodies (at least one, and at most
    /// [`MechanismType::max_bodies`]).
    fn topology(&self, bodies: usize) -> Topology;
    /// The most poses through which the linkage for `bodies` bodies generally has exact solutions;
    /// with more, a linkage can only approximate the motion.
    fn max_exact_poses(&self, bodies: usize) -> usize;
    /// The loops of `topology` whose types (Grashof's, for a four-bar) describe how it moves.
    fn loops(&self, topology: &Topology) -> Vec<Loop>;
    /// The factor on the scene's pose noise for this family's linkage of `bodies` bodies through
    /// `poses` poses: how far the sampler perturbs the intermediate poses it fits a sample through,
    /// relative to the scene's `pose_tolerance` and `angle_tolerance_deg`.
    fn pose_noise(&self, _bodies: usize, _poses: usize) -> f64 {
        1.0
    }
    /// The family's own stream of random numbers, so adding a family changes no other's samples.
    fn stream(&self) -> u64;
    /// A random linkage of the family for `bodies` moving bodies, drawn from `rng` in a unit frame:
    /// body centres 1.2 apart, each joint within 0.35 of its body's centre, the ground pivots near
    /// the origin. Nothing more is asked of it: it may not assemble, or not move far (the testbed
    /// keeps the ones that do, as known mechanisms to measure designs against).
    fn random_linkage(&self, bodies: usize, rng: &mut dyn Rng) -> Mechanism;
}

/// In a random linkage ([`Family::random_linkage`]), the distance between consecutive body centres.
pub(crate) const CENTRE_SPACING: f64 = 1.2;
/// In a random linkage, how far a joint may lie from its body's centre.
const JOINT_SPREAD: f64 = 0.35;

/// A point uniformly in the disc of radius [`JOINT_SPREAD`] about `centre`.
fn near(centre: Point, rng: &mut dyn Rng) -> Point {
    let r = JOINT_SPREAD * rng.random::<f64>().sqrt();
    centre + Vec2::from_angle(rng.random_range(-PI..PI)) * r
}

/// `joints` (sized for `topology`) with each named one placed; names the topology lacks are skipped.
fn place(topology: &Topology, joints: &mut [Point], placed: impl IntoIterator<Item = (&'static str, Point)>) {
    for (name, p) in placed {
        if let Some(j) = topology.joint(name) {
            joints[j] = p;
        }
    }
}

/// A loop of a linkage, by joint indices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Loop {
    /// A four-bar, each link by its two joints.
    FourBar {
        /// The link the loop stands on (the ground, or the body the loop hangs from), `[a, b]`.
        frame: [usize; 2],
        /// The link that drives the loop, `[a, c]`.
        input: [usize; 2],
        /// The floating link, `[c, d]`.
        coupler: [usize; 2],
        /// The link driven, `[b, d]`.
        output: [usize; 2],
    },
    /// A slider-crank.
    SliderCrank {
        /// The ground joint the crank turns about.
        pivot: usize,
        /// The crank's moving end, which drives the rod.
        tip: usize,
        /// The joint that runs on the slider's line.
        slider: usize,
    },
}

impl MechanismType {
    /// The family this word names.
    pub fn family(self) -> &'static dyn Family {
        match self {
            MechanismType::Chain => &Chain,
            MechanismType::SliderCrank => &SliderCrank,
            MechanismType::WattTwo => &WattTwo,
            MechanismType::StephensonThree => &StephensonThree,
        }
    }
    /// What a person calls the family ([`Family::label`]).
    pub fn label(self) -> &'static str {
        self.family().label()
    }
    /// The family in a few words, for a menu ([`Family::description`]).
    pub fn description(self) -> &'static str {
        self.family().description()
    }
    /// What a person calls this family's linkage for `bodies` moving bodies ([`Family::linkage_label`]).
    pub fn linkage_label(self, bodies: usize) -> String {
        self.family().linkage_label(bodies)
    }
}

/// The multi-bar chain of paper §4.2 (see [`Topology::chain`]).
struct Chain;

/// Chains of this many bodies or more are long, and take [`LONG_CHAIN_NOISE`].
const LONG_CHAIN: usize = 4;
/// The pose noise of long chains ([`Family::pose_noise`]). Every body's intermediate pose is
/// perturbed on its own, and each ternary link must be rigid through the relative motion of two
/// perturbed bodies, so the more bodies, the farther the fits land from any linkage through the drawn
/// poses: their loops lock up between the poses. Chains of four to six bodies through three poses
/// (`linkwright bench --known`, the K = 4–6, N = 3 rows) find a design on 8 of 9 scenes with this
/// factor, worst pose error 0.08·d; at the paper's 0.5·d the worst is 0.24·d (those scenes from
/// `--save DIR` with `settings.pose_tolerance` and `angle_tolerance_deg` ten times as large,
/// `linkwright design SCENE --no-print-check`). Shorter chains gain nothing from it (K = 2 and 3
/// through three poses: costs higher on three of six scenes at a factor of 0.44).
const LONG_CHAIN_NOISE: f64 = 0.1;
/// The pose noise of the one-body six-bars through as many poses as the body's four-bar meets
/// exactly or more ([`Family::pose_noise`]). A six-bar has three links to fit where a four-bar has
/// two, and there the body's ground link is down to a few Burmester points, which move far with
/// each perturbed pose: fits to poses perturbed as far as the scene allows keep few linkages, and
/// those far from the drawn poses. On the known Watt-II (one way and out and back) and
/// Stephenson-III scenes through 5–8 poses, scene seeds 0–2 (`linkwright bench --known --save DIR`,
/// then `linkwright design` on each with `pose_tolerance` and `angle_tolerance_deg` scaled), 24 of
/// 36 come within 0.05·d of every pose at the full noise, 33 at 0.4 of it and 35 at 0.2, where the
/// median worst miss falls from 0.019 to 0.008·d and the runs take a quarter less time. Through
/// fewer poses the full noise stays: at 0.2, as many of the one-body reference scenes through three
/// poses get a costlier design as a cheaper one (`k1_peg` seed 0: cost 3.2 to 13).
const SIX_BAR_NOISE: f64 = 0.2;

/// [`SIX_BAR_NOISE`] through `poses` poses, for a six-bar whose body's four-bar meets `exact`.
fn six_bar_noise(exact: usize, poses: usize) -> f64 {
    if poses >= exact {
        SIX_BAR_NOISE
    } else {
        1.0
    }
}

impl Family for Chain {
    fn mechanism_type(&self) -> MechanismType {
        MechanismType::Chain
    }
    fn label(&self) -> &'static str {
        "bar chain"
    }
    fn description(&self) -> &'static str {
        "Bar chain (four-bar, six-bar, …)"
    }
    fn linkage_label(&self, bodies: usize) -> String {
        match bodies {
            1 => "four-bar linkage".to_string(),
            2 => "Watt-I six-bar linkage".to_string(),
            k => format!("{}-bar chain", 2 * k + 2),
        }
    }
    fn topology(&self, bodies: usize) -> Topology {
        Topology::chain(bodies)
    }
    /// A four-bar's dyads up to five poses (Burmester), a longer chain's ternary links up to three.
    fn max_exact_poses(&self, bodies: usize) -> usize {
        if bodies == 1 {
            5
        } else {
            3
        }
    }
    /// Loop k is the four-bar `q(k−1) r(k−1) q(k) p(k)`, k = 1..K.
    fn loops(&self, topology: &Topology) -> Vec<Loop> {
        let joint = |name: String| topology.joint(&name);
        (1..=topology.body_count)
            .filter_map(|k| {
                let (a, b) = (joint(format!("q{}", k - 1))?, joint(format!("r{}", k - 1))?);
                let (c, d) = (joint(format!("p{k}"))?, joint(format!("q{k}"))?);
                Some(Loop::FourBar { frame: [a, b], input: [a, c], coupler: [c, d], output: [b, d] })
            })
            .collect()
    }
    fn pose_noise(&self, bodies: usize, _poses: usize) -> f64 {
        if bodies >= LONG_CHAIN {
            LONG_CHAIN_NOISE
        } else {
            1.0
        }
    }
    fn stream(&self) -> u64 {
        0
    }
    /// Body centres one step apart along a wandering heading, each joint near its body's centre, the
    /// ground pivots near the origin.
    fn random_linkage(&self, bodies: usize, rng: &mut dyn Rng) -> Mechanism {
        let topology = Arc::new(self.topology(bodies));
        let mut joints = vec![Point::ORIGIN; topology.joint_count()];
        let mut set = |name: String, p: Point| {
            if let Some(j) = topology.joint(&name) {
                joints[j] = p;
            }
        };
        let mut centre = Point::ORIGIN;
        let mut heading = rng.random_range(-PI..PI);
        set("q0".into(), near(centre, rng));
        set("r0".into(), near(centre, rng));
        for b in 1..=bodies {
            heading += rng.random_range(-1.2..1.2);
            centre = centre + Vec2::from_angle(heading) * CENTRE_SPACING;
            set(format!("p{b}"), near(centre, rng));
            set(format!("q{b}"), near(centre, rng));
            if b < bodies {
                set(format!("r{b}"), near(centre, rng));
            }
        }
        Mechanism { topology, joints, slider: None }
    }
}

/// The RRRP slider-crank of paper §4.3 (see [`Topology::slider_crank`]).
struct SliderCrank;

impl Family for SliderCrank {
    fn mechanism_type(&self) -> MechanismType {
        MechanismType::SliderCrank
    }
    fn label(&self) -> &'static str {
        "slider-crank"
    }
    fn description(&self) -> &'static str {
        "Slider-crank (one moving body)"
    }
    fn linkage_label(&self, _bodies: usize) -> String {
        "slider-crank".to_string()
    }
    fn topology(&self, _bodies: usize) -> Topology {
        Topology::slider_crank()
    }
    /// The slider joint up to four poses: a body point on a line in four positions (Ball's point).
    fn max_exact_poses(&self, _bodies: usize) -> usize {
        4
    }
    fn loops(&self, topology: &Topology) -> Vec<Loop> {
        let Some(slider) = topology.slider_joint else { return Vec::new() };
        vec![Loop::SliderCrank { pivot: topology.driver_pivot, tip: topology.driver_tip, slider }]
    }
    fn stream(&self) -> u64 {
        1
    }
    /// A crank about the origin, a rod to the slider joint, and a guide through the slider joint in
    /// any direction.
    fn random_linkage(&self, bodies: usize, rng: &mut dyn Rng) -> Mechanism {
        let topology = Arc::new(self.topology(bodies));
        let q0 = Point::ORIGIN;
        let p1 = q0 + Vec2::from_angle(rng.random_range(-PI..PI)) * rng.random_range(0.3..0.8);
        let q1 = p1 + Vec2::from_angle(rng.random_range(-PI..PI)) * rng.random_range(0.9..1.8);
        let direction = Vec2::from_angle(rng.random_range(-PI..PI));
        let mut joints = vec![Point::ORIGIN; topology.joint_count()];
        place(&topology, &mut joints, [("q0", q0), ("p1", p1), ("q1", q1)]);
        Mechanism { topology, joints, slider: Some(SliderLine { point: q1, direction }) }
    }
}

/// The Watt-II six-bar (see [`Topology::watt_two`]).
struct WattTwo;

impl Family for WattTwo {
    fn mechanism_type(&self) -> MechanismType {
        MechanismType::WattTwo
    }
    fn label(&self) -> &'static str {
        "Watt-II six-bar"
    }
    fn description(&self) -> &'static str {
        "Watt-II six-bar (one moving body)"
    }
    fn linkage_label(&self, _bodies: usize) -> String {
        "Watt-II six-bar linkage".to_string()
    }
    fn topology(&self, _bodies: usize) -> Topology {
        Topology::watt_two()
    }
    /// The body's four-bar: its dyads up to five poses (Burmester). The driving four-bar only has
    /// to move the body's input link in order, which any crank near it does.
    fn max_exact_poses(&self, _bodies: usize) -> usize {
        5
    }
    fn pose_noise(&self, bodies: usize, poses: usize) -> f64 {
        six_bar_noise(self.max_exact_poses(bodies), poses)
    }
    /// The driving four-bar `u0 q0 t1 u1`, then the body's `q0 r0 q1 p1`.
    fn loops(&self, topology: &Topology) -> Vec<Loop> {
        let joint = |name: &str| topology.joint(name);
        let (Some(q0), Some(r0), Some(u0), Some(u1), Some(t1), Some(p1), Some(q1)) =
            (joint("q0"), joint("r0"), joint("u0"), joint("u1"), joint("t1"), joint("p1"), joint("q1"))
        else {
            return Vec::new();
        };
        vec![
            Loop::FourBar { frame: [u0, q0], input: [u0, u1], coupler: [u1, t1], output: [q0, t1] },
            Loop::FourBar { frame: [q0, r0], input: [q0, p1], coupler: [p1, q1], output: [r0, q1] },
        ]
    }
    fn stream(&self) -> u64 {
        2
    }
    /// The random four-bar of [`Chain`], its input link extended to `t1` near the ground pivot `q0`,
    /// driven by a crank about `u0` (beside the ground pivots) whose tip `u1` lies between the two.
    fn random_linkage(&self, bodies: usize, rng: &mut dyn Rng) -> Mechanism {
        let four_bar = Chain.random_linkage(1, rng);
        let topology = Arc::new(self.topology(bodies));
        let mut joints = vec![Point::ORIGIN; topology.joint_count()];
        for (j, name) in four_bar.topology.joint_names.iter().enumerate() {
            if let Some(k) = topology.joint(name) {
                joints[k] = four_bar.joints[j];
            }
        }
        let q0 = four_bar.joint("q0").unwrap_or(Point::ORIGIN);
        let u0 = q0 + Vec2::from_angle(rng.random_range(-PI..PI)) * CENTRE_SPACING;
        let t1 = near(q0, rng);
        let u1 = near(Point::new(0.5 * (u0.x + t1.x), 0.5 * (u0.y + t1.y)), rng);
        place(&topology, &mut joints, [("u0", u0), ("t1", t1), ("u1", u1)]);
        Mechanism { topology, joints, slider: None }
    }
}

/// The Stephenson-III six-bar (see [`Topology::stephenson_three`]).
struct StephensonThree;

impl Family for StephensonThree {
    fn mechanism_type(&self) -> MechanismType {
        MechanismType::StephensonThree
    }
    fn label(&self) -> &'static str {
        "Stephenson-III six-bar"
    }
    fn description(&self) -> &'static str {
        "Stephenson-III six-bar (one body)"
    }
    fn linkage_label(&self, _bodies: usize) -> String {
        "Stephenson-III six-bar linkage".to_string()
    }
    fn topology(&self, _bodies: usize) -> Topology {
        Topology::stephenson_three()
    }
    /// The body's ground link up to five poses (Burmester); its joint on the coupler follows a
    /// four-bar's coupler curve, which passes more points than that.
    fn max_exact_poses(&self, _bodies: usize) -> usize {
        5
    }
    fn pose_noise(&self, bodies: usize, poses: usize) -> f64 {
        six_bar_noise(self.max_exact_poses(bodies), poses)
    }
    /// The four-bar `q0 u0 b1 a1` the body hangs from (the body's own loop is a five-bar).
    fn loops(&self, topology: &Topology) -> Vec<Loop> {
        let joint = |name: &str| topology.joint(name);
        let (Some(q0), Some(u0), Some(a1), Some(b1)) = (joint("q0"), joint("u0"), joint("a1"), joint("b1")) else {
            return Vec::new();
        };
        vec![Loop::FourBar { frame: [q0, u0], input: [q0, a1], coupler: [a1, b1], output: [u0, b1] }]
    }
    fn stream(&self) -> u64 {
        3
    }
    /// The body's joints near its centre one step from the origin, its ground link's pivot `r0` near
    /// the origin, and a small four-bar `q0 a1 b1 u0` between the two whose coupler holds the body's
    /// `p1`.
    fn random_linkage(&self, bodies: usize, rng: &mut dyn Rng) -> Mechanism {
        let topology = Arc::new(self.topology(bodies));
        let centre = Point::ORIGIN + Vec2::from_angle(rng.random_range(-PI..PI)) * CENTRE_SPACING;
        let between = Point::new(0.5 * centre.x, 0.5 * centre.y);
        let mut joints = vec![Point::ORIGIN; topology.joint_count()];
        place(
            &topology,
            &mut joints,
            [
                ("r0", near(Point::ORIGIN, rng)),
                ("q0", near(Point::ORIGIN, rng)),
                ("u0", near(Point::ORIGIN, rng)),
                ("a1", near(between, rng)),
                ("b1", near(between, rng)),
                ("p1", near(centre, rng)),
                ("q1", near(centre, rng)),
            ],
        );
        Mechanism { topology, joints, slider: None }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mechanism::PartKind;

    #[test]
    fn every_family_names_itself_and_builds_its_linkage() {
        for t in MechanismType::ALL {
            let family = t.family();
            assert_eq!(family.mechanism_type(), t);
            for bodies in 1..=t.max_bodies().unwrap_or(4) {
                let topology = family.topology(bodies);
                assert_eq!(topology.mechanism_type, t);
                assert_eq!(topology.body_count, bodies);
                let bodies_carried = topology.parts.iter().filter(|p| matches!(p.kind, PartKind::Body(_))).count();
                assert_eq!(bodies_carried, bodies);
                assert!(!family.loops(&topology).is_empty());
            }
        }
        let streams: std::collections::HashSet<u64> = MechanismType::ALL.iter().map(|t| t.family().stream()).collect();
        assert_eq!(streams.len(), MechanismType::ALL.len(), "each family draws its own numbers");
    }
}
