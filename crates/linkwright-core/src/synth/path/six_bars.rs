//! The six-bars as path generators, in closed form.
//!
//! - The Stephenson-III: a crank-rocker whose coupler carries the body's first joint `p1` along its
//!   coupler curve, while the body's other joint `q1` swings on a ground link. The tracer rides on
//!   the body, so its curve is the coupler curve bent by the body's own turning: loops, cusps and
//!   figure-eights a four-bar's coupler curve cannot make.
//! - The Watt-II: a crank-rocker rocks the input link of the body's four-bar, so once per turn of
//!   the crank the tracer runs out along an arc of that four-bar's coupler curve and back (a wiper's
//!   stroke), which no crank of a four-bar can do.

use super::four_bar::{log_uniform, FourBar};
use super::linkage::{on_body, random_branch, PathLinkage, Similarity, TracerAt};
use crate::geom::{Point, Vec2};
use crate::kinematics::{circle_circle, transmission_sine, Branch};
use crate::mechanism::{Mechanism, Topology};
use crate::scene::MechanismType;
use rand::RngExt;
use rand_xoshiro::Xoshiro256PlusPlus;
use std::f64::consts::TAU;
use std::sync::Arc;

/// A Stephenson-III six-bar: `driver` is the crank-rocker `q0 a1 b1 u0` with the body's joint `p1`
/// as its coupler point; the body `p1 q1` carries the tracer at `(u, v)` in its frame (origin `p1`,
/// x towards `q1`); `q1` turns on the ground link `link_pivot`–`q1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct StephensonThree {
    pub driver: FourBar,
    pub link_pivot: Point,
    /// |p1 q1|.
    pub body: f64,
    /// |r0 q1|.
    pub link: f64,
    pub u: f64,
    pub v: f64,
    /// Which side of the line from `p1` to `link_pivot` the joint `q1` is on.
    pub branch: Branch,
}

/// Where the body's joints are at one crank angle.
struct Joints {
    crank_tip: Point,
    rocker_tip: Point,
    p1: Point,
    q1: Point,
    transmission_sine: f64,
}

impl StephensonThree {
    fn joints_at(&self, theta: f64) -> Option<Joints> {
        let c = self.driver.at(theta)?;
        let q1 = circle_circle(c.tracer, self.body, self.link_pivot, self.link, self.branch).ok()?;
        let sine = transmission_sine(c.tracer - q1, self.link_pivot - q1);
        Some(Joints {
            crank_tip: c.crank_tip,
            rocker_tip: c.rocker_tip,
            p1: c.tracer,
            q1,
            transmission_sine: c.transmission_sine.min(sine),
        })
    }
}

/// Crank angles at which a drawn second loop is checked to assemble all the way round.
const SAMPLE_STEPS: usize = 36;

/// The crank angles of [`SAMPLE_STEPS`], over a whole turn.
fn around() -> impl Iterator<Item = f64> {
    (0..SAMPLE_STEPS).map(|k| TAU * k as f64 / SAMPLE_STEPS as f64)
}

/// The lengths `(a, b)` of a dyad from a ground pivot whose far joint must reach a point at each of
/// `distances` from it (`None`: the loop before it came apart): |a − b| below the least distance and
/// a + b above the greatest, with room to spare (`a` 0.55 to 2 times the spread, or `floor`).
fn reaching(
    distances: impl Iterator<Item = Option<f64>>,
    floor: f64,
    r: &mut Xoshiro256PlusPlus,
) -> Option<(f64, f64)> {
    let (mut near, mut far) = (f64::INFINITY, 0.0f64);
    for d in distances {
        let d = d?;
        (near, far) = (near.min(d), far.max(d));
    }
    let a = 0.5 * (far - near).max(floor) * log_uniform(r, 1.1, 4.0);
    let (lo, hi) = ((far - a).max(a - near), a + near);
    if hi <= lo {
        return None;
    }
    Some((a, lo + (hi - lo) * r.random_range(0.1..0.9)))
}

impl PathLinkage for StephensonThree {
    const FAMILY: MechanismType = MechanismType::StephensonThree;
    const STREAM: u64 = 0x7061_7468_0003;

    fn tracer_at(&self, theta: f64) -> Option<TracerAt> {
        let j = self.joints_at(theta)?;
        Some(TracerAt {
            point: on_body(j.p1, j.q1, self.body, self.u, self.v),
            heading: j.q1 - j.p1,
            transmission_sine: j.transmission_sine,
        })
    }

    /// The atlas's four-bar, then a ground pivot near it and a body and link whose lengths reach
    /// from it to every point of the coupler curve (drawn between the least and the greatest
    /// distance, so they assemble all the way round).
    fn sample(r: &mut Xoshiro256PlusPlus) -> Option<StephensonThree> {
        let driver = FourBar::sample(r)?;
        let link_pivot = Point::new(r.random_range(-1.0..2.0), r.random_range(-1.5..1.5));
        let distances = around().map(|theta| Some(driver.at(theta)?.tracer.distance(link_pivot)));
        let (body, link) = reaching(distances, 0.05, r)?;
        Some(StephensonThree {
            driver,
            link_pivot,
            body,
            link,
            u: body * r.random_range(-1.0..2.0),
            v: body * r.random_range(-1.5..1.5),
            branch: random_branch(r),
        })
    }

    fn mapped(&self, map: &Similarity) -> StephensonThree {
        let s = map.scale;
        StephensonThree {
            driver: self.driver.mapped(map),
            link_pivot: map.point(self.link_pivot),
            body: self.body * s,
            link: self.link * s,
            u: self.u * s,
            v: self.v * s,
            branch: self.branch,
        }
    }

    fn params(&self) -> Vec<f64> {
        let mut x = self.driver.params();
        x.extend([self.link_pivot.x, self.link_pivot.y, self.body, self.link, self.u, self.v]);
        x
    }

    fn with_params(&self, x: &[f64]) -> StephensonThree {
        let n = x.len() - 6;
        StephensonThree {
            driver: self.driver.with_params(&x[..n]),
            link_pivot: Point::new(x[n], x[n + 1]),
            body: x[n + 2],
            link: x[n + 3],
            u: x[n + 4],
            v: x[n + 5],
            branch: self.branch,
        }
    }

    fn mechanism(&self, theta: f64) -> Option<Mechanism> {
        let j = self.joints_at(theta)?;
        let topology = Arc::new(Topology::stephenson_three());
        let joints = topology
            .joint_names
            .iter()
            .map(|n| match n.as_str() {
                "q0" => self.driver.crank_pivot,
                "u0" => self.driver.rocker_pivot,
                "r0" => self.link_pivot,
                "a1" => j.crank_tip,
                "b1" => j.rocker_tip,
                "p1" => j.p1,
                _ => j.q1,
            })
            .collect();
        Some(Mechanism { topology, joints, slider: None })
    }
}

/// A Watt-II six-bar: `driver` is the crank-rocker `u0 u1 t1 q0` (crank `u0 u1`, its rocker the
/// ternary link `q0 t1 p1` about `q0`); the ternary link carries `p1` at `input` from `q0`, turned
/// `turn` from `t1`; the body `p1 q1` is the coupler of the four-bar `q0 p1 q1 r0`, its rocker
/// `r0 q1`, and carries the tracer at `(u, v)` in its frame (origin `p1`, x towards `q1`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct WattTwo {
    /// The driving crank-rocker; its coupler point is not used.
    pub driver: FourBar,
    /// |q0 p1|, and the angle at `q0` from `t1` to `p1` (radians).
    pub input: f64,
    pub turn: f64,
    pub rocker_pivot: Point,
    /// |p1 q1| and |r0 q1|.
    pub coupler: f64,
    pub rocker: f64,
    pub u: f64,
    pub v: f64,
    /// Which side of the line from `p1` to `rocker_pivot` the joint `q1` is on.
    pub branch: Branch,
}

/// Where a Watt-II's joints are at one crank angle.
struct WattJoints {
    u1: Point,
    t1: Point,
    p1: Point,
    q1: Point,
    transmission_sine: f64,
}

impl WattTwo {
    fn joints_at(&self, theta: f64) -> Option<WattJoints> {
        let c = self.driver.at(theta)?;
        let q0 = self.driver.rocker_pivot;
        let p1 = q0 + Vec2::from_angle((c.rocker_tip - q0).angle() + self.turn) * self.input;
        let q1 = circle_circle(p1, self.coupler, self.rocker_pivot, self.rocker, self.branch).ok()?;
        let sine = transmission_sine(p1 - q1, self.rocker_pivot - q1);
        Some(WattJoints { u1: c.crank_tip, t1: c.rocker_tip, p1, q1, transmission_sine: c.transmission_sine.min(sine) })
    }
}

impl PathLinkage for WattTwo {
    const FAMILY: MechanismType = MechanismType::WattTwo;
    const STREAM: u64 = 0x7061_7468_0002;

    fn tracer_at(&self, theta: f64) -> Option<TracerAt> {
        let j = self.joints_at(theta)?;
        Some(TracerAt {
            point: on_body(j.p1, j.q1, self.coupler, self.u, self.v),
            heading: j.q1 - j.p1,
            transmission_sine: j.transmission_sine,
        })
    }

    /// The atlas's crank-rocker drives the ternary link; the body's four-bar gets a rocker pivot near
    /// it and a coupler and rocker whose lengths reach from it to every place of `p1`.
    fn sample(r: &mut Xoshiro256PlusPlus) -> Option<WattTwo> {
        let driver = FourBar { u: 0.0, v: 0.0, ..FourBar::sample(r)? };
        let q0 = driver.rocker_pivot;
        let input = log_uniform(r, 0.3, 3.0);
        let turn = r.random_range(0.0..TAU);
        let rocker_pivot = q0 + Vec2::new(r.random_range(-2.0..2.0), r.random_range(-2.0..2.0)) * input;
        let distances = around().map(|theta| {
            let t1 = driver.at(theta)?.rocker_tip;
            Some((q0 + Vec2::from_angle((t1 - q0).angle() + turn) * input).distance(rocker_pivot))
        });
        let (coupler, rocker) = reaching(distances, 0.05 * input, r)?;
        Some(WattTwo {
            driver,
            input,
            turn,
            rocker_pivot,
            coupler,
            rocker,
            u: coupler * r.random_range(-1.0..2.0),
            v: coupler * r.random_range(-1.5..1.5),
            branch: random_branch(r),
        })
    }

    fn mapped(&self, map: &Similarity) -> WattTwo {
        let s = map.scale;
        WattTwo {
            driver: self.driver.mapped(map),
            input: self.input * s,
            turn: self.turn,
            rocker_pivot: map.point(self.rocker_pivot),
            coupler: self.coupler * s,
            rocker: self.rocker * s,
            u: self.u * s,
            v: self.v * s,
            branch: self.branch,
        }
    }

    /// The driver's pivots and links (not its unused coupler point), then the body's four-bar.
    fn params(&self) -> Vec<f64> {
        let mut x = self.driver.params();
        x.truncate(DRIVER_PARAMETERS);
        x.extend([
            self.input,
            self.turn,
            self.rocker_pivot.x,
            self.rocker_pivot.y,
            self.coupler,
            self.rocker,
            self.u,
            self.v,
        ]);
        x
    }

    fn with_params(&self, x: &[f64]) -> WattTwo {
        let n = DRIVER_PARAMETERS;
        let mut driver = x[..n].to_vec();
        driver.extend([0.0, 0.0]);
        WattTwo {
            driver: self.driver.with_params(&driver),
            input: x[n],
            turn: x[n + 1],
            rocker_pivot: Point::new(x[n + 2], x[n + 3]),
            coupler: x[n + 4],
            rocker: x[n + 5],
            u: x[n + 6],
            v: x[n + 7],
            branch: self.branch,
        }
    }

    fn is_angle(k: usize) -> bool {
        k == DRIVER_PARAMETERS + 1
    }

    fn mechanism(&self, theta: f64) -> Option<Mechanism> {
        let j = self.joints_at(theta)?;
        let topology = Arc::new(Topology::watt_two());
        let joints = topology
            .joint_names
            .iter()
            .map(|n| match n.as_str() {
                "u0" => self.driver.crank_pivot,
                "q0" => self.driver.rocker_pivot,
                "r0" => self.rocker_pivot,
                "u1" => j.u1,
                "t1" => j.t1,
                "p1" => j.p1,
                _ => j.q1,
            })
            .collect();
        Some(Mechanism { topology, joints, slider: None })
    }
}

/// The driving four-bar's parameters a Watt-II refines: pivots and link lengths.
const DRIVER_PARAMETERS: usize = 7;
