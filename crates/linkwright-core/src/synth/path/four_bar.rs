//! A four-bar's coupler curve in closed form: the path search traces thousands of them, each at a
//! hundred crank angles, so it solves the one loop directly rather than through the general dyad plan.

use super::linkage::{on_body, PathLinkage, Similarity, TracerAt};
use crate::geom::{Point, Vec2};
use crate::mechanism::{Mechanism, Topology};
use crate::scene::MechanismType;
use rand::RngExt;
use rand_xoshiro::Xoshiro256PlusPlus;
use std::sync::Arc;

/// A four-bar with a point on its coupler: ground pivots `crank_pivot` (the driver's) and
/// `rocker_pivot`, link lengths, and the coupler point `(u, v)` in the coupler's frame (origin at the
/// crank's tip, x towards the rocker's tip).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FourBar {
    pub crank_pivot: Point,
    pub rocker_pivot: Point,
    pub crank: f64,
    pub coupler: f64,
    pub rocker: f64,
    pub u: f64,
    pub v: f64,
    /// Which of the two assemblies: +1 or −1 (the rocker's tip to the left or right of the line from
    /// the crank's tip to the rocker pivot).
    pub branch: f64,
}

/// Where a four-bar's moving joints and coupler point are at one crank angle, and how well it
/// transmits there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Configuration {
    pub crank_tip: Point,
    pub rocker_tip: Point,
    pub tracer: Point,
    /// The sine of the transmission angle (between coupler and rocker), in [0, 1].
    pub transmission_sine: f64,
}

/// A random draw between `lo` and `hi` whose logarithm is uniform: lengths of every ratio alike.
pub(crate) fn log_uniform(r: &mut Xoshiro256PlusPlus, lo: f64, hi: f64) -> f64 {
    (lo.ln() + (hi.ln() - lo.ln()) * r.random::<f64>()).exp()
}

impl PathLinkage for FourBar {
    const FAMILY: MechanismType = MechanismType::Chain;
    const STREAM: u64 = 0x7061_7468;

    fn tracer_at(&self, theta: f64) -> Option<TracerAt> {
        self.at(theta).map(|c| TracerAt {
            point: c.tracer,
            heading: c.rocker_tip - c.crank_tip,
            transmission_sine: c.transmission_sine,
        })
    }

    /// Ground pivots (0, 0) and (1, 0), a crank shorter than every other link and a Grashof loop,
    /// the coupler point anywhere near the coupler.
    fn sample(r: &mut Xoshiro256PlusPlus) -> Option<FourBar> {
        let crank = r.random_range(0.05..0.7);
        let coupler = log_uniform(r, 0.3, 4.0);
        let rocker = log_uniform(r, 0.3, 4.0);
        let m = FourBar {
            crank_pivot: Point::new(0.0, 0.0),
            rocker_pivot: Point::new(1.0, 0.0),
            crank,
            coupler,
            rocker,
            u: coupler * r.random_range(-1.0..2.0),
            v: coupler * r.random_range(-1.5..1.5),
            branch: if r.random::<bool>() { 1.0 } else { -1.0 },
        };
        m.crank_turns_fully().then_some(m)
    }

    fn mapped(&self, map: &Similarity) -> FourBar {
        let s = map.scale;
        FourBar {
            crank_pivot: map.point(self.crank_pivot),
            rocker_pivot: map.point(self.rocker_pivot),
            crank: self.crank * s,
            coupler: self.coupler * s,
            rocker: self.rocker * s,
            u: self.u * s,
            v: self.v * s,
            branch: self.branch,
        }
    }

    fn params(&self) -> Vec<f64> {
        vec![
            self.crank_pivot.x,
            self.crank_pivot.y,
            self.rocker_pivot.x,
            self.rocker_pivot.y,
            self.crank,
            self.coupler,
            self.rocker,
            self.u,
            self.v,
        ]
    }

    fn with_params(&self, x: &[f64]) -> FourBar {
        FourBar {
            crank_pivot: Point::new(x[0], x[1]),
            rocker_pivot: Point::new(x[2], x[3]),
            crank: x[4],
            coupler: x[5],
            rocker: x[6],
            u: x[7],
            v: x[8],
            branch: self.branch,
        }
    }

    fn mechanism(&self, theta: f64) -> Option<Mechanism> {
        let c = self.at(theta)?;
        let topology = Arc::new(Topology::chain(1));
        let joints = topology
            .joint_names
            .iter()
            .map(|n| match n.as_str() {
                "q0" => self.crank_pivot,
                "r0" => self.rocker_pivot,
                "p1" => c.crank_tip,
                _ => c.rocker_tip,
            })
            .collect();
        Some(Mechanism { topology, joints, slider: None })
    }
}

impl FourBar {
    /// The configuration at crank angle `theta` (radians), or `None` where the loop does not close.
    pub(crate) fn at(&self, theta: f64) -> Option<Configuration> {
        let crank_tip = self.crank_pivot + Vec2::from_angle(theta) * self.crank;
        let to_pivot = self.rocker_pivot - crank_tip;
        let e = to_pivot.norm();
        if e.is_nan() || e <= 0.0 || self.coupler <= 0.0 || self.rocker <= 0.0 {
            return None;
        }
        let along = (self.coupler * self.coupler - self.rocker * self.rocker + e * e) / (2.0 * e);
        let h_sq = self.coupler * self.coupler - along * along;
        if h_sq.is_nan() || h_sq < 0.0 {
            return None;
        }
        let axis = to_pivot / e;
        let rocker_tip = crank_tip + axis * along + axis.perp() * (self.branch * h_sq.sqrt());
        let x = (rocker_tip - crank_tip) / self.coupler;
        let tracer = on_body(crank_tip, rocker_tip, self.coupler, self.u, self.v);
        // sin μ from the triangle crank tip, rocker tip, rocker pivot: twice its area over b·c.
        let transmission_sine =
            (x * self.coupler).cross(rocker_tip - self.rocker_pivot).abs() / (self.coupler * self.rocker);
        Some(Configuration { crank_tip, rocker_tip, tracer, transmission_sine: transmission_sine.min(1.0) })
    }

    /// Whether the crank turns fully (Grashof, the crank the shortest link, and the loop never
    /// folds flat: a crank-rocker or a drag link).
    pub(crate) fn crank_turns_fully(&self) -> bool {
        let ground = self.crank_pivot.distance(self.rocker_pivot);
        let mut links = [ground, self.crank, self.coupler, self.rocker];
        links.sort_by(f64::total_cmp);
        let grashof = links[0] + links[3] < links[1] + links[2];
        grashof && self.crank <= links[0]
    }
}

#[cfg(test)]
impl FourBar {
    /// A known crank-rocker for tests, off the atlas's normal form: pivots (2, 1) and (5, 2), links
    /// 1, 3.5, 2.8, its tracer at (1.2, 1.5) in the coupler's frame.
    pub(crate) fn known() -> FourBar {
        FourBar {
            crank_pivot: Point::new(2.0, 1.0),
            rocker_pivot: Point::new(5.0, 2.0),
            crank: 1.0,
            coupler: 3.5,
            rocker: 2.8,
            u: 1.2,
            v: 1.5,
            branch: 1.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A crank-rocker with ground 1, crank 0.3, coupler 1, rocker 0.8: at θ = 0 the crank's tip is at
    /// (0.3, 0), 0.7 from the rocker pivot (1, 0); the rocker's tip solves |C − B| = 1, |C − D| = 0.8.
    #[test]
    fn the_loop_closes_where_the_circles_meet() {
        let m = FourBar {
            crank_pivot: Point::new(0.0, 0.0),
            rocker_pivot: Point::new(1.0, 0.0),
            crank: 0.3,
            coupler: 1.0,
            rocker: 0.8,
            u: 0.5,
            v: 0.2,
            branch: 1.0,
        };
        assert!(m.crank_turns_fully());
        for k in 0..36 {
            let c = m.at(k as f64 * 10f64.to_radians()).expect("a crank-rocker assembles everywhere");
            assert!((c.crank_tip.distance(c.rocker_tip) - 1.0).abs() < 1e-12);
            assert!((c.rocker_tip.distance(m.rocker_pivot) - 0.8).abs() < 1e-12);
            assert!((c.tracer.distance(c.crank_tip) - (0.5f64.powi(2) + 0.2f64.powi(2)).sqrt()).abs() < 1e-12);
        }
        // At θ = 0: along = (1 − 0.64 + 0.49) / 1.4, the rocker's tip above the ground line; the
        // transmission angle's cosine is (b² + c² − e²) / 2bc (law of cosines).
        let c = m.at(0.0).unwrap();
        let along = (1.0 - 0.64 + 0.49) / 1.4;
        assert!(c.rocker_tip.distance(Point::new(0.3 + along, (1.0 - along * along).sqrt())) < 1e-12);
        let cos_mu: f64 = (1.0 + 0.64 - 0.49) / 1.6;
        assert!((c.transmission_sine - (1.0 - cos_mu * cos_mu).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn a_crank_longer_than_the_ground_does_not_turn_fully() {
        let m = FourBar {
            crank_pivot: Point::new(0.0, 0.0),
            rocker_pivot: Point::new(1.0, 0.0),
            crank: 1.2,
            coupler: 0.5,
            rocker: 0.6,
            u: 0.0,
            v: 0.0,
            branch: 1.0,
        };
        assert!(!m.crank_turns_fully());
        // Crank pointing away from the rocker pivot: its tip is 2.2 from it, past coupler + rocker.
        assert!(m.at(std::f64::consts::PI).is_none());
        assert!(m.at(0.0).is_some(), "towards it, 0.2 away: the circles of 0.5 and 0.6 meet");
    }
}
