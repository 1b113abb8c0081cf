//! Counterbalance springs: one or two springs chosen so that the driver's torque against gravity
//! ([`crate::statics`]) has the smallest peak over the travel.
//!
//! A spring adds its potential energy to the parts' weight: an extension spring between a ground
//! point and a point on a moving part stores `½ k (L − L₀)²`, a torsion spring at a ground pivot
//! `½ κ (φ − φ₀)²`. By virtual work the driver then supplies `τ + k (L − L₀) dL/dθ` (or
//! `τ + κ (φ − φ₀) dφ/dθ`), the derivatives from the joints' exact velocities. For fixed anchors
//! and a fixed free length the torque is linear in the stiffness, so the peak is a convex function
//! of it: each pair of anchors and free length gets its best stiffness by a bracketing search (every
//! pair screened on a quarter of the rows, the best again on all). The best pairs whose spring stays
//! out of the avoid regions along the motion (it hangs in a layer of its own beside the links) have
//! their anchors moved to a local optimum, and the lowest peak wins. The best single springs of the
//! moving parts each start a pair: a second spring added on what the first leaves, then the two
//! chosen again against each other; the best pair is kept when it lowers the peak enough further.
//!
//! The springs are ones a person can buy: every free length and rate tried is a member of a stock
//! series ([`FREE_LENGTHS`], [`EXTENSION_RATES`], [`TORSION_RATES`]) at the size of the thing built
//! (the model's millimetres for a printed model), so the torque reported with them is the torque
//! those very springs leave. A load whose peak is below [`NO_SPRING_NEEDED_NM`] gets no spring.

use crate::geom::{segments_cross, Point, Polygon, Rigid, Vec2};
use crate::kinematics::{BodyFrames, Plan, Trace};
use crate::mechanism::{Mechanism, PartKind};
use crate::scene::Problem;
use crate::statics::{peak, Masses, Torque};
use crate::{Cancelled, Observer};
use rayon::prelude::*;
use serde::Serialize;

/// An extension spring is at most this many times its free length (and never shorter than it: it
/// only pulls), a common limit for wire extension springs.
pub const STRETCH_RATIO: f64 = 2.5;
/// A torsion spring is wound one way only, by at most this many degrees.
pub const MAX_TWIST_DEG: f64 = 360.0;

/// The peak torque without springs, N·m, below which no spring is needed: 1 N·mm, the order of
/// what the friction of a printed model's pin joints holds by itself (an estimate, not a
/// measurement: μ ≈ 0.3 between PLA faces, pressed together by a snap cap with about a newton, on
/// faces about 3.5 mm from the axis of the default 2 mm pin: 0.3 × 1 N × 3.5 mm ≈ 1 N·mm). A
/// full-size load is far above it (a 1 kg part 1 cm from its pivot asks 98 N·mm), and so are the
/// bundled garbage truck's printed parts (about 5 N·mm).
pub const NO_SPRING_NEEDED_NM: f64 = 1e-3;

/// A series of preferred numbers (ISO 3, the Renard series): the same steps in every decade, each
/// about the same ratio above the last, so rounding to the series errs by at most half a step in
/// proportion whatever the size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Series {
    /// Its name in ISO 3 (`R10`).
    pub name: &'static str,
    /// The steps of the decade from 1 to 10, in hundredths (`125` for 1.25).
    pub hundredths: &'static [u32],
}

/// Powers of ten that are exact (10²² is the largest a double holds exactly): a member of a series
/// is then the double nearest its decimal, 3.15 mm as 3.15, not 3.1500000000000004.
const EXACT_POWERS_OF_TEN: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20,
    1e21, 1e22,
];

impl Series {
    /// R10: ten steps a decade, each about 1.26 times the last (1, 1.25, 1.6, 2, 2.5, 3.15, 4, 5,
    /// 6.3, 8).
    pub const R10: Series = Series { name: "R10", hundredths: &[100, 125, 160, 200, 250, 315, 400, 500, 630, 800] };
    /// R20: twenty steps a decade, each about 1.12 times the last (R10 and the numbers between).
    pub const R20: Series = Series {
        name: "R20",
        hundredths: &[
            100, 112, 125, 140, 160, 180, 200, 224, 250, 280, 315, 355, 400, 450, 500, 560, 630, 710, 800, 900,
        ],
    };

    /// Step `i` of the decade starting at 10^`decade`.
    fn member(&self, decade: i32, i: usize) -> f64 {
        let n = f64::from(self.hundredths[i]);
        let power = |e: i32| EXACT_POWERS_OF_TEN.get(e.unsigned_abs() as usize).copied().unwrap_or(10f64.powi(e.abs()));
        let e = decade - 2;
        if e >= 0 {
            n * power(e)
        } else {
            n / power(e)
        }
    }

    /// The members from `lo` to `hi` (both included), ascending; none unless 0 < lo ≤ hi, finite.
    pub fn within(&self, lo: f64, hi: f64) -> Vec<f64> {
        if !(lo > 0.0 && hi >= lo && hi.is_finite()) {
            return Vec::new();
        }
        // A decade either side, so the logarithms' rounding cannot lose an end.
        let (first, last) = (lo.log10().floor() as i32 - 1, hi.log10().floor() as i32 + 1);
        (first..=last)
            .flat_map(|d| (0..self.hundredths.len()).map(move |i| self.member(d, i)))
            .filter(|&v| lo <= v && v <= hi)
            .collect()
    }

    /// The largest member not above `x` and the smallest not below it (the same twice when `x` is a
    /// member); `None` unless `x` is positive and finite.
    pub fn around(&self, x: f64) -> Option<[f64; 2]> {
        // No step of a series is a factor of 2: both neighbours lie within it.
        let near = self.within(x / 2.0, x * 2.0);
        let below = near.iter().copied().rfind(|&v| v <= x)?;
        let above = near.iter().copied().find(|&v| v >= x)?;
        Some([below, above])
    }

    /// The member nearest `x` in proportion; `None` unless `x` is positive and finite.
    pub fn nearest(&self, x: f64) -> Option<f64> {
        let [below, above] = self.around(x)?;
        Some(if x / below <= above / x { below } else { above })
    }

    /// Whether `x` is a member, to a part in 10¹².
    pub fn contains(&self, x: f64) -> bool {
        self.nearest(x).is_some_and(|v| (v - x).abs() <= 1e-12 * v)
    }
}

/// The free lengths of the extension springs suggested, mm (hook to hook, at the size of the thing
/// built): the R20 series. Catalogue extension springs are listed in steps of free length of about
/// a tenth (suppliers quote the free length, the longest extended length and the rate in N/mm for each
/// spring), and R20's steps of 12% always leave a member in a range of allowed free lengths wider than
/// that; R10's 26% steps would leave none for a spring whose length changes by more than twice along
/// the travel, whose free length must lie between its longest length ÷ [`STRETCH_RATIO`] and its
/// shortest.
pub const FREE_LENGTHS: Series = Series::R20;
/// The rates of the extension springs suggested, N/mm: the R10 series, the catalogue's coarser steps
/// for the spring's stiffness, which the peak depends on less than on the free length (a rate 12% off
/// at worst, and the better of the two neighbouring rates is taken).
pub const EXTENSION_RATES: Series = Series::R10;
/// The rates of the torsion springs suggested, N·mm per degree, as catalogues give them: the R10
/// series. A torsion spring's free angle is no catalogue size (where its ground leg rests is set by
/// the stop it bears on), so it is not rounded.
pub const TORSION_RATES: Series = Series::R10;

/// Free angles of a torsion spring tried per pair of anchors.
const FREE_STEPS: usize = 16;
/// Golden-section steps narrowing the stiffness bracket (the peak is convex in the stiffness) to
/// 0.618³⁶ ≈ 3·10⁻⁸ of its width.
const STIFFNESS_STEPS: usize = 36;
/// Points of the linkage region tried as ground anchors, per side of its bounding box.
const REGION_GRID: usize = 7;
/// Points of a body's face tried as anchors, per side of its bounding box.
const FACE_GRID: usize = 4;
/// The best extension springs whose anchors are then moved to a local optimum.
const POLISHED: usize = 6;
/// Halvings of the anchors' step while polishing, from a twentieth of the scene's size.
const POLISH_LEVELS: usize = 7;
/// A second spring is kept when it lowers the peak by at least this fraction of what one leaves.
const SECOND_SPRING_GAIN: f64 = 0.1;
/// Rounds of choosing each of two springs again against the other.
const PAIR_ROUNDS: usize = 3;
/// Moving parts whose best single spring starts a search for a pair: the parts' best single springs
/// can lower the peak alike while only some leave room for a second, so the pair search starts from
/// more than the best one.
const PAIR_SEEDS: usize = 2;
/// Extension springs checked for clearance, cheapest first, before giving up on that kind.
const CLEARANCE_TRIES: usize = 400;
/// Every pair of anchors is screened at every this-many-th row of the travel (and the last) before
/// the best [`CLEARANCE_TRIES`] are fitted at every row.
const SCREEN_STRIDE: usize = 4;

pub use crate::fab::Anchor;

/// What the spring search may choose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpringSearch {
    /// Whether torsion springs may be chosen (fabrication hooks extension springs only).
    pub torsion: bool,
    /// The most springs (1 or 2).
    pub most: usize,
    /// Anchors on a link stay at least this far from its joints (scene units) unless on one: room
    /// for a printed hook beside the joint's pin.
    pub clear_of_joints: f64,
}

impl SpringSearch {
    /// What `analyze` reports: one or two springs of either kind, anywhere.
    pub const ANALYSIS: SpringSearch = SpringSearch { torsion: true, most: 2, clear_of_joints: 0.0 };

    /// Up to `most` extension springs that fabrication with `dims` can hook.
    pub fn hooked(dims: &crate::fab::Dims, most: usize) -> SpringSearch {
        SpringSearch { torsion: false, most, clear_of_joints: dims.hook_clear_of_joints() }
    }
}

/// A counterbalance spring and what it does along the travel.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Spring {
    /// A wire extension spring between a ground point and a point on a moving part.
    Extension {
        /// The ground end first, then the moving end.
        anchors: [Anchor; 2],
        /// Stiffness, N/m.
        stiffness_n_per_m: f64,
        /// Unstretched length between the hooks, scene units.
        free_length: f64,
        /// Shortest and longest length along the travel, scene units.
        length_range: [f64; 2],
        /// The free length to buy, mm at the size of the thing built (a model's millimetres for a
        /// printed model): a member of [`FREE_LENGTHS`].
        free_length_mm: f64,
        /// Shortest and longest length along the travel, mm at the size of the thing built: the
        /// longest is at most [`STRETCH_RATIO`] times the free length.
        length_range_mm: [f64; 2],
        /// The rate to buy, N/mm: a member of [`EXTENSION_RATES`] (`stiffness_n_per_m` ÷ 1000).
        rate_n_per_mm: f64,
        /// Smallest and largest pull along the travel, N.
        force_range_n: [f64; 2],
        /// Both ends at every row of the travel, scene units.
        ends: Vec<[Point; 2]>,
    },
    /// A torsion spring at a ground pivot, wound by the part turning about it.
    Torsion {
        /// The part that turns about the pivot (its rotation winds the spring).
        part: String,
        /// The ground pivot, scene units.
        pivot: Point,
        /// Stiffness, N·m per radian.
        stiffness_nm_per_rad: f64,
        /// The rate to buy, N·mm per degree: a member of [`TORSION_RATES`].
        rate_n_mm_per_deg: f64,
        /// The part's rotation from the first pose at which the spring is unwound, degrees.
        free_angle_deg: f64,
        /// Least and most wind along the travel, degrees.
        twist_range_deg: [f64; 2],
        /// Least and most torque of the spring along the travel, N·m.
        torque_range_nm: [f64; 2],
        /// The pivot and the part's other joint at every row of the travel, scene units.
        ends: Vec<[Point; 2]>,
    },
}

/// Whether a load gets springs, as data for the front ends to word.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SpringNeed {
    /// The peak without springs is below [`NO_SPRING_NEEDED_NM`]: the linkage needs none.
    NotNeeded,
    /// Springs lower the peak: [`Balance::springs`] holds them.
    Springs,
    /// The load needs springs, but no stock spring hooked where the search may hook one lowers the
    /// peak (or the travel passes a dead point, where no torque holds the linkage).
    NoneHelps,
}

/// The springs chosen and the driver's torque with them.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Balance {
    /// Whether springs are needed and found.
    pub need: SpringNeed,
    /// The peak without springs below which no spring is needed, N·m ([`NO_SPRING_NEEDED_NM`]).
    pub no_spring_below_nm: f64,
    /// One or two springs; none when none is needed or none lowers the peak.
    pub springs: Vec<Spring>,
    /// The torque the driver supplies at each row with the springs, N·m (signs as without).
    pub torque_with_springs_nm: Vec<f64>,
    /// The largest |torque| with the springs, N·m.
    pub peak_with_springs_nm: f64,
    /// Where it occurs, degrees of crank.
    pub peak_with_springs_crank_deg: f64,
}

/// The torque along a travel and the springs that balance it, side by side: the document
/// `linkwright analyze --json` prints and `POST /api/balance` answers.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Balanced<'a> {
    /// The torque without springs.
    #[serde(flatten)]
    pub torque: &'a Torque,
    /// The springs and the torque with them.
    #[serde(flatten)]
    pub balance: &'a Balance,
}

/// A point carried by a part: fixed on the ground, or rigid with two joints of a moving part (given
/// in the frame those joints span).
#[derive(Clone, Copy, Debug)]
struct Place {
    part: usize,
    joints: Option<(usize, usize)>,
    local: Point,
}

impl Place {
    fn at(&self, row: &[Point]) -> Point {
        match self.joints {
            None => self.local,
            Some((a, c)) => Rigid::from_frame(row[a], row[c] - row[a]).apply(self.local),
        }
    }

    /// Its velocity per radian of crank, given the joints' velocities.
    fn velocity(&self, row: &[Point], velocity: &[Vec2]) -> Vec2 {
        match self.joints {
            None => Vec2::ZERO,
            Some((a, c)) => {
                crate::kinematics::carried_velocity([row[a], row[c]], [velocity[a], velocity[c]], self.at(row))
            }
        }
    }
}

/// A spring's share of the torque per unit stiffness at each row, given its free length (or angle):
/// `share(free)[r] = along · (x_r − free) · x'_r · unit`, x the length (m) or the angle (rad).
#[derive(Clone)]
struct Stretch {
    /// The length or angle at each row (scene units or radians).
    x: Vec<f64>,
    /// Its derivative along the crank, per radian.
    dx: Vec<f64>,
    /// Metres per scene unit for lengths, 1 for angles.
    unit: f64,
}

impl Stretch {
    fn range(&self) -> (f64, f64) {
        self.x.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| (lo.min(x), hi.max(x)))
    }

    /// The torque per unit stiffness at each row with free length `free`.
    fn share(&self, free: f64, along: f64) -> Vec<f64> {
        self.x.iter().zip(&self.dx).map(|(x, dx)| along * (x - free) * dx * self.unit * self.unit).collect()
    }

    /// [`Stretch::share`] at the given rows only.
    fn share_at(&self, free: f64, along: f64, rows: &[usize]) -> Vec<f64> {
        rows.iter().map(|&r| along * (self.x[r] - free) * self.dx[r] * self.unit * self.unit).collect()
    }

    /// The free lengths (or angles) the spring may have: an extension spring's are the members of
    /// [`FREE_LENGTHS`] (in mm of the thing built, `unit` metres a scene unit) that keep it between
    /// its free length and [`STRETCH_RATIO`] times it; a torsion spring stays wound one way, by at
    /// most [`MAX_TWIST_DEG`].
    fn free_choices(&self, torsion: bool) -> Vec<f64> {
        let (lo, hi) = self.range();
        let steps = |a: f64, b: f64| -> Vec<f64> {
            (0..FREE_STEPS).map(|i| a + (b - a) * i as f64 / (FREE_STEPS - 1) as f64).collect()
        };
        if torsion {
            let twist = MAX_TWIST_DEG.to_radians();
            if hi - lo >= twist {
                return Vec::new();
            }
            // Unwound before the travel's least angle or after its largest.
            let mut out = steps(hi - twist, lo);
            out.extend(steps(hi, lo + twist));
            out
        } else if hi / STRETCH_RATIO <= lo && lo > 0.0 {
            let mm = self.unit * 1000.0;
            // Kept only when the length in scene units, as reported, keeps the limits too.
            FREE_LENGTHS
                .within(hi / STRETCH_RATIO * mm, lo * mm)
                .into_iter()
                .map(|free_mm| free_mm / mm)
                .filter(|&free| free <= lo && hi <= STRETCH_RATIO * free)
                .collect()
        } else {
            Vec::new()
        }
    }
}

/// The best stiffness (≥ 0) for `share` added to `torque`, and the peak it leaves: the peak
/// `max |τ + k·share|` is convex in k, so its minimum is bracketed and narrowed.
fn best_stiffness(torque: &[f64], share: &[f64]) -> (f64, f64) {
    let peak = |k: f64| peak_with(torque, share, k);
    let t_max = torque.iter().fold(0.0f64, |m, t| m.max(t.abs()));
    let s_max = share.iter().fold(0.0f64, |m, s| m.max(s.abs()));
    if s_max == 0.0 || t_max == 0.0 {
        return (0.0, peak(0.0));
    }
    // Beyond 2·max|τ|/max|share| the spring alone exceeds the unbalanced peak.
    let golden = 0.5 * (5f64.sqrt() - 1.0);
    let (mut lo, mut hi) = (0.0, 2.0 * t_max / s_max);
    let (mut a, mut b) = (hi - golden * (hi - lo), lo + golden * (hi - lo));
    let (mut fa, mut fb) = (peak(a), peak(b));
    for _ in 0..STIFFNESS_STEPS {
        if fa <= fb {
            (hi, b, fb) = (b, a, fa);
            a = hi - golden * (hi - lo);
            fa = peak(a);
        } else {
            (lo, a, fa) = (a, b, fb);
            b = lo + golden * (hi - lo);
            fb = peak(b);
        }
    }
    let k = 0.5 * (lo + hi);
    (k, peak(k))
}

/// The peak of `torque` with a spring of stiffness `k` whose share per unit stiffness is `share`.
fn peak_with(torque: &[f64], share: &[f64], k: f64) -> f64 {
    torque.iter().zip(share).map(|(t, s)| (t + k * s).abs()).fold(0.0, f64::max)
}

/// One spring's fit: where it is, its stretch along the travel, stiffness and free length, and the
/// peak it leaves.
#[derive(Clone)]
struct Fit {
    kind: Kind,
    stretch: Stretch,
    stiffness: f64,
    free: f64,
    peak: f64,
}

#[derive(Clone, Copy)]
enum Kind {
    Extension { ground: Place, moving: Place },
    Torsion { part: usize, pivot: usize, tip: usize },
}

impl Kind {
    /// The series its rate is bought in, and the stiffness (N/m, or N·m per radian) of a unit of
    /// that rate (N/mm, or N·mm per degree).
    fn rates(&self) -> (Series, f64) {
        match self {
            Kind::Extension { .. } => (EXTENSION_RATES, 1000.0),
            Kind::Torsion { .. } => (TORSION_RATES, 180.0 / std::f64::consts::PI / 1000.0),
        }
    }
}

/// What the search needs of the linkage along its travel.
struct Motion<'a> {
    problem: &'a Problem,
    mechanism: &'a Mechanism,
    trace: &'a Trace,
    frames: BodyFrames,
    /// The joints' velocities at every row.
    velocities: Vec<Vec<Vec2>>,
    along: f64,
    metres: f64,
    /// Asked between pieces of the search whether to stop.
    observer: &'a dyn Observer,
    /// What may be chosen.
    search: SpringSearch,
}

impl<'a> Motion<'a> {
    /// The travel's joint velocities; `None` when it passes a dead point.
    fn new(
        problem: &'a Problem,
        mechanism: &'a Mechanism,
        plan: &Plan,
        trace: &'a Trace,
        masses: &Masses,
        observer: &'a dyn Observer,
    ) -> Option<Self> {
        let first_poses: Vec<_> = problem.bodies.iter().map(|b| b.poses[0]).collect();
        let velocities = (0..trace.len())
            .map(|r| {
                let mut v = vec![Vec2::ZERO; plan.joint_count()];
                plan.velocities(trace.thetas[r], trace.row(r), &mut v).map(|()| v)
            })
            .collect::<Option<Vec<_>>>()?;
        let along = if trace.len() > 1 && trace.thetas[trace.len() - 1] < trace.thetas[0] { -1.0 } else { 1.0 };
        Some(Motion {
            problem,
            mechanism,
            trace,
            frames: BodyFrames::new(mechanism, &first_poses),
            velocities,
            along,
            metres: masses.millimetres_per_unit / 1000.0,
            observer,
            search: SpringSearch::ANALYSIS,
        })
    }

    fn extension(&self, ground: &Place, moving: &Place) -> Stretch {
        let (mut x, mut dx) = (Vec::with_capacity(self.trace.len()), Vec::with_capacity(self.trace.len()));
        for (r, velocity) in self.velocities.iter().enumerate() {
            let row = self.trace.row(r);
            let (a, b) = (ground.at(row), moving.at(row));
            let length = a.distance(b);
            x.push(length);
            let rel = moving.velocity(row, velocity) - ground.velocity(row, velocity);
            dx.push(if length > 0.0 { (b - a).dot(rel) / length } else { 0.0 });
        }
        Stretch { x, dx, unit: self.metres }
    }

    fn torsion(&self, pivot: usize, tip: usize) -> Stretch {
        let first = self.trace.row(0)[tip] - self.trace.row(0)[pivot];
        let (mut x, mut dx) = (Vec::with_capacity(self.trace.len()), Vec::with_capacity(self.trace.len()));
        let mut last = 0.0;
        for (r, velocity) in self.velocities.iter().enumerate() {
            let row = self.trace.row(r);
            let arm = row[tip] - row[pivot];
            // Unwrapped rotation from the first row.
            let mut angle = first.cross(arm).atan2(first.dot(arm));
            angle += std::f64::consts::TAU * ((last - angle) / std::f64::consts::TAU).round();
            last = angle;
            x.push(angle);
            dx.push(arm.cross(velocity[tip]) / arm.norm_sq());
        }
        Stretch { x, dx, unit: 1.0 }
    }

    /// The best free length and stiffness for a spring of this stretch against `torque`.
    fn fit(&self, kind: Kind, stretch: Stretch, torque: &[f64]) -> Option<Fit> {
        self.fit_at(kind, stretch, torque, None)
    }

    /// [`Motion::fit`] judged at `rows` only (every row when `None`), `torque` given at those rows.
    fn fit_at(&self, kind: Kind, stretch: Stretch, torque: &[f64], rows: Option<&[usize]>) -> Option<Fit> {
        let torsion = matches!(kind, Kind::Torsion { .. });
        let (series, per_rate) = kind.rates();
        let (stiffness, free, peak) = stretch
            .free_choices(torsion)
            .into_iter()
            .filter_map(|free| {
                let share = match rows {
                    None => stretch.share(free, self.along),
                    Some(rows) => stretch.share_at(free, self.along, rows),
                };
                let (best, _) = best_stiffness(torque, &share);
                // The peak is convex in the stiffness: the better stock rate is one of the two
                // beside the best.
                series
                    .around(best / per_rate)?
                    .into_iter()
                    .map(|rate| {
                        let stiffness = rate * per_rate;
                        (stiffness, free, peak_with(torque, &share, stiffness))
                    })
                    .min_by(|a, b| a.2.total_cmp(&b.2))
            })
            .min_by(|a, b| a.2.total_cmp(&b.2))?;
        Some(Fit { kind, stretch, stiffness, free, peak })
    }

    /// Whether an extension spring between these places stays out of the avoid regions along the
    /// travel: it hangs in a layer of its own beside the links, which the bodies pass as they pass
    /// the links (the synthesis checks links against avoid regions only, paper §5.5).
    fn clear(&self, ground: &Place, moving: &Place) -> bool {
        (0..self.trace.len()).all(|r| {
            let row = self.trace.row(r);
            let (a, b) = (ground.at(row), moving.at(row));
            let blocked = |polygon: &Polygon| {
                polygon.contains(a)
                    || polygon.contains(b)
                    || polygon.edges().any(|(p, q)| segments_cross(a, b, p, q, 0.0))
            };
            a != b && !self.problem.avoid.iter().any(blocked)
        })
    }

    fn spring(&self, fit: &Fit) -> Spring {
        let parts = &self.mechanism.topology.parts;
        let (lo, hi) = fit.stretch.range();
        match fit.kind {
            Kind::Extension { ground, moving } => {
                let row = self.trace.row(0);
                let force = |x: f64| fit.stiffness * (x - fit.free) * self.metres;
                let mm = self.metres * 1000.0;
                // The stock values themselves, without the round trip through scene units.
                let stock = |series: Series, x: f64| series.nearest(x).unwrap_or(x);
                Spring::Extension {
                    anchors: [
                        Anchor { part: parts[ground.part].name.clone(), point: ground.at(row) },
                        Anchor { part: parts[moving.part].name.clone(), point: moving.at(row) },
                    ],
                    stiffness_n_per_m: fit.stiffness,
                    free_length: fit.free,
                    length_range: [lo, hi],
                    free_length_mm: stock(FREE_LENGTHS, fit.free * mm),
                    length_range_mm: [lo * mm, hi * mm],
                    rate_n_per_mm: stock(EXTENSION_RATES, fit.stiffness / 1000.0),
                    force_range_n: [force(lo), force(hi)],
                    ends: (0..self.trace.len())
                        .map(|r| [ground.at(self.trace.row(r)), moving.at(self.trace.row(r))])
                        .collect(),
                }
            }
            Kind::Torsion { part, pivot, tip } => {
                let twist = |x: f64| (x - fit.free).abs();
                let (t0, t1) = (twist(lo), twist(hi));
                let (least, most) = (t0.min(t1), t0.max(t1));
                Spring::Torsion {
                    part: parts[part].name.clone(),
                    pivot: self.trace.row(0)[pivot],
                    stiffness_nm_per_rad: fit.stiffness,
                    rate_n_mm_per_deg: {
                        let per_rate = Kind::Torsion { part, pivot, tip }.rates().1;
                        TORSION_RATES.nearest(fit.stiffness / per_rate).unwrap_or(fit.stiffness / per_rate)
                    },
                    free_angle_deg: fit.free.to_degrees(),
                    twist_range_deg: [least.to_degrees(), most.to_degrees()],
                    torque_range_nm: [fit.stiffness * least, fit.stiffness * most],
                    ends: (0..self.trace.len()).map(|r| [self.trace.row(r)[pivot], self.trace.row(r)[tip]]).collect(),
                }
            }
        }
    }

    /// The ground anchors tried: the fixed bodies' corners, edge middles and points on their faces,
    /// the ground pivots, and points of the linkage region.
    fn ground_places(&self) -> Vec<Place> {
        let ground = self.mechanism.topology.parts.iter().position(|p| p.kind == PartKind::Fixed).unwrap_or(0);
        let fixed = |local: Point| Place { part: ground, joints: None, local };
        let mut out: Vec<Place> = self
            .problem
            .fixed
            .iter()
            .flat_map(|p| p.edges())
            .flat_map(|(v, w)| [v, v + (w - v) * 0.5])
            .map(fixed)
            .collect();
        out.extend(self.mechanism.topology.fixed_joints().iter().map(|&j| fixed(self.mechanism.joints[j])));
        out.extend(inside(&self.problem.region, REGION_GRID).into_iter().map(fixed));
        for polygon in &self.problem.fixed {
            out.extend(inside(polygon, FACE_GRID).into_iter().map(fixed));
        }
        out
    }

    /// The moving anchors tried: each moving body's corners, edge middles and points on its face (the
    /// spring hangs beside it, hooked on a post), and points along each link.
    fn moving_places(&self) -> Vec<Place> {
        let row = self.trace.row(0);
        let carried = |part: usize, (a, c): (usize, usize), world: Point| Place {
            part,
            joints: Some((a, c)),
            local: Rigid::from_frame(row[a], row[c] - row[a]).inverse().apply(world),
        };
        let mut out = Vec::new();
        for (i, part) in self.mechanism.topology.parts.iter().enumerate() {
            match part.kind {
                PartKind::Fixed => {}
                PartKind::Body(b) => {
                    let (a, c, _) = self.frames.frame(b);
                    let pose = self.frames.pose(b, row);
                    let outline = &self.problem.bodies[b].outline;
                    for (v, w) in outline.edges() {
                        out.push(carried(i, (a, c), pose.apply(v)));
                        out.push(carried(i, (a, c), pose.apply(v + (w - v) * 0.5)));
                    }
                    for p in inside(outline, FACE_GRID) {
                        out.push(carried(i, (a, c), pose.apply(p)));
                    }
                }
                PartKind::Link => {
                    let joints = &part.joints;
                    for (k, &a) in joints.iter().enumerate() {
                        let c = joints[(k + 1) % joints.len()];
                        if a == c || (joints.len() == 2 && k == 1) {
                            continue;
                        }
                        for t in [0.25, 0.5, 0.75] {
                            let at = row[a] + (row[c] - row[a]) * t;
                            if joints.iter().all(|&j| row[j].distance(at) >= self.search.clear_of_joints) {
                                out.push(carried(i, (a, c), at));
                            }
                        }
                    }
                    for &j in joints {
                        let other = joints.iter().copied().find(|&o| o != j).unwrap_or(j);
                        if other != j && !self.mechanism.topology.fixed_joints().contains(&j) {
                            out.push(carried(i, (j, other), row[j]));
                        }
                    }
                }
            }
        }
        out
    }

    /// The best spring of any kind against `torque` (hooked on moving part `on` only, when given): the
    /// extension spring with the lowest peak that stays clear of the bodies, or a torsion spring when
    /// that does better.
    fn best_spring(&self, torque: &[f64], on: Option<usize>) -> Option<Fit> {
        if self.observer.cancelled() {
            return None;
        }
        let grounds = self.ground_places();
        let mut movings = self.moving_places();
        movings.retain(|m| on.is_none_or(|part| m.part == part));
        // Every pair is first judged at every SCREEN_STRIDE-th row (and the last), the best of them
        // again at every row. Independent pairs, in a fixed order whatever the thread count.
        let mut rows: Vec<usize> = (0..torque.len()).step_by(SCREEN_STRIDE).collect();
        if rows.last().is_some_and(|&r| r + 1 < torque.len()) {
            rows.push(torque.len() - 1);
        }
        let screened: Vec<f64> = rows.iter().map(|&r| torque[r]).collect();
        let (rows, screened) = (&rows, &screened);
        let mut extensions: Vec<Fit> = movings
            .into_par_iter()
            .flat_map_iter(|moving| {
                // Once cancelled, the rest is skipped (the caller answers `Cancelled`).
                let go_on = !self.observer.cancelled();
                grounds.iter().take_while(move |_| go_on).filter_map(move |ground| {
                    let kind = Kind::Extension { ground: *ground, moving };
                    self.fit_at(kind, self.extension(ground, &moving), screened, Some(rows))
                })
            })
            .collect();
        extensions.sort_by(|a, b| a.peak.total_cmp(&b.peak));
        extensions.truncate(CLEARANCE_TRIES);
        let mut extensions: Vec<Fit> =
            extensions.into_par_iter().filter_map(|f| self.fit(f.kind, f.stretch, torque)).collect();
        extensions.sort_by(|a, b| a.peak.total_cmp(&b.peak));
        let clear: Vec<Fit> = extensions
            .into_iter()
            .filter(|f| match f.kind {
                Kind::Extension { ground, moving } => self.clear(&ground, &moving),
                Kind::Torsion { .. } => true,
            })
            .take(POLISHED)
            .collect();
        let extension = clear
            .into_par_iter()
            .map(|f| self.polish(f, torque))
            .collect::<Vec<_>>()
            .into_iter()
            .min_by(|a, b| a.peak.total_cmp(&b.peak));
        let fixed = self.mechanism.topology.fixed_joints();
        let torsion = self
            .mechanism
            .topology
            .parts
            .iter()
            .enumerate()
            .filter(|&(i, p)| self.search.torsion && p.kind == PartKind::Link && on.is_none_or(|part| part == i))
            .filter_map(|(i, p)| {
                let pivot = *p.joints.iter().find(|j| fixed.contains(j))?;
                let tip = *p.joints.iter().find(|j| !fixed.contains(j))?;
                let kind = Kind::Torsion { part: i, pivot, tip };
                self.fit(kind, self.torsion(pivot, tip), torque)
            })
            .min_by(|a, b| a.peak.total_cmp(&b.peak));
        [extension, torsion].into_iter().flatten().min_by(|a, b| a.peak.total_cmp(&b.peak))
    }

    /// Moves an extension spring's anchors to a local optimum of the peak (a pattern search, the
    /// step halved when no move helps), each anchor staying on its part: the ground one inside the
    /// linkage region or on a fixed body, one on a moving body on that body's face; one on a link
    /// stays where it is.
    fn polish(&self, fit: Fit, torque: &[f64]) -> Fit {
        let Kind::Extension { moving, .. } = fit.kind else { return fit };
        let row = self.trace.row(0);
        let on_ground = |p: Point| self.problem.region.contains(p) || self.problem.fixed.iter().any(|f| f.contains(p));
        let body = match self.mechanism.topology.parts[moving.part].kind {
            PartKind::Body(b) => Some(b),
            _ => None,
        };
        let on_body = |place: &Place| {
            body.is_some_and(|b| {
                let local = self.frames.pose(b, row).inverse().apply(place.at(row));
                self.problem.bodies[b].outline.contains(local)
            })
        };
        let mut best = fit;
        let mut step = 0.05 * self.problem.scale;
        for _ in 0..POLISH_LEVELS {
            if self.observer.cancelled() {
                break;
            }
            let mut moved = true;
            while moved {
                moved = false;
                let Kind::Extension { ground, moving } = best.kind else { break };
                let shifts = [Vec2::new(step, 0.0), Vec2::new(-step, 0.0), Vec2::new(0.0, step), Vec2::new(0.0, -step)];
                let mut tries: Vec<(Place, Place)> = Vec::new();
                for d in shifts {
                    let g = Place { local: ground.local + d, ..ground };
                    if on_ground(g.local) {
                        tries.push((g, moving));
                    }
                    if body.is_some() {
                        // A shift of the hook in the world at the first pose, carried into its frame.
                        let (a, c) = moving.joints.expect("a moving anchor is carried by joints");
                        let frame = Rigid::from_frame(row[a], row[c] - row[a]);
                        let m = Place { local: frame.inverse().apply(moving.at(row) + d), ..moving };
                        if on_body(&m) {
                            tries.push((ground, m));
                        }
                    }
                }
                for (g, m) in tries {
                    let kind = Kind::Extension { ground: g, moving: m };
                    if let Some(f) = self.fit(kind, self.extension(&g, &m), torque) {
                        if f.peak < best.peak && self.clear(&g, &m) {
                            best = f;
                            moved = true;
                            break;
                        }
                    }
                }
            }
            step *= 0.5;
        }
        best
    }

    /// The best second spring beside `first` against `unbalanced`, then each of the two chosen again
    /// against the other while that lowers the peak (the first was chosen before the second was
    /// there); the two and the peak they leave.
    fn pair_from(&self, unbalanced: &[f64], first: Fit) -> Option<(Fit, Fit, f64)> {
        let mut second = self.best_spring(&self.with(unbalanced, &first), None)?;
        let mut first = first;
        for _ in 0..PAIR_ROUNDS {
            let Some(better) =
                self.best_spring(&self.with(unbalanced, &second), None).filter(|f| f.peak < second.peak * 0.999)
            else {
                break;
            };
            first = better;
            match self.best_spring(&self.with(unbalanced, &first), None) {
                Some(next) if next.peak < first.peak => second = next,
                _ => break,
            }
        }
        let (_, both) = peak(&self.with(&self.with(unbalanced, &first), &second));
        Some((first, second, both))
    }

    fn with(&self, torque: &[f64], fit: &Fit) -> Vec<f64> {
        let share = fit.stretch.share(fit.free, self.along);
        torque.iter().zip(share).map(|(t, s)| t + fit.stiffness * s).collect()
    }
}

/// The points of an n × n grid over `polygon`'s bounding box that lie inside it.
fn inside(polygon: &Polygon, n: usize) -> Vec<Point> {
    let b = polygon.aabb();
    let t = |k: usize| (k as f64 + 0.5) / n as f64;
    (0..n)
        .flat_map(|i| {
            (0..n).map(move |j| Point::new(b.min.x + (b.max.x - b.min.x) * t(i), b.min.y + (b.max.y - b.min.y) * t(j)))
        })
        .filter(|&p| polygon.contains(p))
        .collect()
}

impl Balance {
    /// No spring: the driver's torque as it is, [`SpringNeed::NotNeeded`] when its peak is below
    /// [`NO_SPRING_NEEDED_NM`] and [`SpringNeed::NoneHelps`] otherwise.
    pub fn none(torque: &Torque) -> Balance {
        total(torque, torque.torque_nm.clone(), Vec::new())
    }

    /// How much lower the springs make the peak than `torque`'s (the torque without them), percent.
    pub fn peak_lowered_percent(&self, torque: &Torque) -> f64 {
        100.0 * (1.0 - self.peak_with_springs_nm / torque.peak_nm)
    }
}

/// The torque with the given springs' shares added (the same travel `torque` was computed on).
fn total(torque: &Torque, balance_torque: Vec<f64>, springs: Vec<Spring>) -> Balance {
    let (at, peak) = peak(&balance_torque);
    let need = if !springs.is_empty() {
        SpringNeed::Springs
    } else if !needs_springs(torque) {
        SpringNeed::NotNeeded
    } else {
        SpringNeed::NoneHelps
    };
    Balance {
        need,
        no_spring_below_nm: NO_SPRING_NEEDED_NM,
        springs,
        peak_with_springs_crank_deg: torque.crank_deg.get(at).copied().unwrap_or(0.0),
        peak_with_springs_nm: peak,
        torque_with_springs_nm: balance_torque,
    }
}

/// Whether the torque's peak is enough to need a spring.
fn needs_springs(torque: &Torque) -> bool {
    torque.peak_nm >= NO_SPRING_NEEDED_NM
}

/// What a spring search balances: `mechanism` (compiled as `plan`) moving along `trace` in the scene
/// of `problem`, its parts weighing `masses`, and the driver's `torque` along it as
/// [`crate::statics::driving_torque`] gives it.
#[derive(Clone, Copy)]
pub struct Balancing<'a> {
    /// The scene.
    pub problem: &'a Problem,
    /// The linkage.
    pub mechanism: &'a Mechanism,
    /// The linkage compiled.
    pub plan: &'a Plan,
    /// Its travel.
    pub trace: &'a Trace,
    /// Its parts' masses.
    pub masses: &'a Masses,
    /// The driver's torque along `trace`, without springs.
    pub torque: &'a Torque,
}

impl Balancing<'_> {
    /// One or two stock springs that lower the peak of the torque, and the torque with them, as
    /// `search` allows ([`Balance::none`] when none is needed or none does). The search takes seconds
    /// on multi-body linkages: it stops soon after `observer` says it is cancelled, and then returns
    /// [`Cancelled`].
    pub fn best(&self, search: SpringSearch, observer: &dyn Observer) -> Result<Balance, Cancelled> {
        let choices = self.choices(search, observer)?;
        Ok(choices.into_iter().next().unwrap_or_else(|| Balance::none(self.torque)))
    }

    /// What [`Balancing::best`] chooses, then the next best choices: the other pairs worth a second
    /// spring, then the best single spring of each moving part, best first (where the first's springs
    /// cannot be printed, another's may). Empty when no spring is needed (the peak is below
    /// [`NO_SPRING_NEEDED_NM`]), when no spring lowers the peak, or when the travel passes a dead
    /// point.
    pub fn choices(&self, search: SpringSearch, observer: &dyn Observer) -> Result<Vec<Balance>, Cancelled> {
        let Balancing { problem, mechanism, plan, trace, masses, torque } = *self;
        if !needs_springs(torque) {
            return Ok(Vec::new());
        }
        let Some(mut motion) = Motion::new(problem, mechanism, plan, trace, masses, observer) else {
            // A dead point: the statics has no torque there to balance.
            return Ok(Vec::new());
        };
        motion.search = search;
        let go_on = || if observer.cancelled() { Err(Cancelled) } else { Ok(()) };
        let unbalanced = torque.torque_nm.clone();
        // The best single spring on each moving part, best first (on a tie, the part listed first).
        let mut singles: Vec<Fit> = (0..mechanism.topology.parts.len())
            .filter(|&p| mechanism.topology.parts[p].kind != PartKind::Fixed)
            .filter_map(|p| motion.best_spring(&unbalanced, Some(p)))
            .filter(|fit| fit.peak < torque.peak_nm)
            .collect();
        go_on()?;
        singles.sort_by(|a, b| a.peak.total_cmp(&b.peak));
        let Some(single) = singles.first() else {
            return Ok(Vec::new());
        };
        let one = motion.with(&unbalanced, single);
        // A second spring is kept when a pair lowers the peak by enough more than one spring.
        let mut pairs: Vec<(Fit, Fit, f64)> = singles
            .iter()
            .take(if search.most >= 2 { PAIR_SEEDS } else { 0 })
            .filter_map(|first| motion.pair_from(&unbalanced, first.clone()))
            .filter(|pair| pair.2 < (1.0 - SECOND_SPRING_GAIN) * peak(&one).1)
            .collect();
        pairs.sort_by(|a, b| a.2.total_cmp(&b.2));
        go_on()?;
        let mut choices = Vec::new();
        for (first, second, _) in pairs {
            let balanced = motion.with(&motion.with(&unbalanced, &first), &second);
            choices.push(total(torque, balanced, [first, second].iter().map(|f| motion.spring(f)).collect()));
        }
        for fit in &singles {
            choices.push(total(torque, motion.with(&unbalanced, fit), vec![motion.spring(fit)]));
        }
        Ok(choices)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::statics::tests::{assert_energy_derivative, parallelogram, weight_energy, MASSES, PARALLELOGRAM_R};
    use crate::statics::{driving_torque, GRAVITY};
    use crate::testbed::{known_scene, Known};

    /// A spring's stored energy, J, from a row of joints.
    type Energy = Box<dyn Fn(&[Point]) -> f64>;

    /// A zero-free-length spring from a point h above the crank's pivot to a point s along the crank
    /// stores ½k(h² + s² − 2hs sin θ): with k h s equal to the parts' m g r, their potential energy
    /// m g r sin θ is cancelled for every θ, and the driver needs no torque at all.
    #[test]
    fn a_zero_free_length_spring_balances_a_parallelogram_exactly() {
        let (problem, mechanism, plan, trace) = parallelogram();
        let torque = driving_torque(&problem, &mechanism, &plan, &trace, &MASSES).unwrap();
        let r = PARALLELOGRAM_R;
        let metres = 1e-3;
        let weight: f64 =
            torque.parts.iter().map(|p| p.mass_kg * GRAVITY * if p.name == "body1" { r } else { r / 2.0 }).sum::<f64>()
                * metres;
        let (h, s) = (40.0, r / 2.0);
        let stiffness = weight / (h * s * metres * metres);
        let motion = Motion::new(&problem, &mechanism, &plan, &trace, &MASSES, &crate::Silent).unwrap();
        let topology = &mechanism.topology;
        let crank = topology.parts.iter().position(|p| p.name == "crank").unwrap();
        let (q0, p1) = (topology.joint("q0").unwrap(), topology.joint("p1").unwrap());
        let row = trace.row(0);
        let world = row[q0] + (row[p1] - row[q0]) * 0.5;
        let moving = Place {
            part: crank,
            joints: Some((q0, p1)),
            local: Rigid::from_frame(row[q0], row[p1] - row[q0]).inverse().apply(world),
        };
        let ground = Place { part: 0, joints: None, local: Point::new(0.0, h) };
        let fit = Fit {
            kind: Kind::Extension { ground, moving },
            stretch: motion.extension(&ground, &moving),
            stiffness,
            free: 0.0,
            peak: 0.0,
        };
        let balanced = motion.with(&torque.torque_nm, &fit);
        assert!(torque.peak_nm > 1e-3, "{}", torque.peak_nm);
        for (k, tau) in balanced.iter().enumerate() {
            assert!(tau.abs() <= 1e-12, "row {k}: {tau} N·m left of {}", torque.torque_nm[k]);
        }
    }

    /// The suggested springs: in tension within the stretch ratio, and the torque reported with them
    /// is the derivative of the whole potential energy (weights and springs) along the crank, on
    /// known linkages of every family.
    #[test]
    fn the_torque_with_springs_is_the_derivative_of_the_whole_potential_energy() {
        let families = [
            Known::chain(1),
            Known::chain(2),
            Known::one(crate::MechanismType::SliderCrank),
            Known::one(crate::MechanismType::WattTwo),
        ];
        for (seed, family) in families.into_iter().enumerate() {
            let known = known_scene(family, 3, seed as u64, 100.0).unwrap();
            let problem = Problem::new(&known.scene).unwrap();
            let design = known.design();
            let replay = crate::analysis::Replay::new(&problem, &design, crate::analysis::Which::Best, 90).unwrap();
            let (mechanism, plan, trace) = (&replay.mechanism, &replay.plan, &replay.trace);
            let torque = driving_torque(&problem, mechanism, plan, trace, &MASSES).unwrap();
            let balancing = Balancing { problem: &problem, mechanism, plan, trace, masses: &MASSES, torque: &torque };
            let balance = balancing.best(SpringSearch::ANALYSIS, &crate::Silent).unwrap();
            assert!(!balance.springs.is_empty(), "{family:?}: no spring");
            assert!(balance.peak_with_springs_nm < torque.peak_nm, "{family:?}");
            let motion = Motion::new(&problem, mechanism, plan, trace, &MASSES, &crate::Silent).unwrap();
            let parts = &mechanism.topology.parts;
            let metres = MASSES.millimetres_per_unit / 1000.0;
            // Each spring's energy at any crank angle, from its reported anchors and free length.
            let energies: Vec<Energy> = balance
                .springs
                .iter()
                .map(|spring| -> Energy {
                    match spring {
                        Spring::Extension { anchors, stiffness_n_per_m, free_length, length_range, .. } => {
                            assert!(length_range[0] >= free_length - 1e-9, "{family:?}: pushes");
                            assert!(length_range[1] <= STRETCH_RATIO * free_length + 1e-9, "{family:?}: overstretched");
                            let place = |anchor: &Anchor| {
                                let part = parts.iter().position(|p| p.name == anchor.part).unwrap();
                                let joints = match parts[part].kind {
                                    PartKind::Fixed => None,
                                    PartKind::Body(b) => Some((motion.frames.frame(b).0, motion.frames.frame(b).1)),
                                    PartKind::Link => Some((parts[part].joints[0], parts[part].joints[1])),
                                };
                                let row = trace.row(0);
                                let local = match joints {
                                    None => anchor.point,
                                    Some((a, c)) => {
                                        Rigid::from_frame(row[a], row[c] - row[a]).inverse().apply(anchor.point)
                                    }
                                };
                                Place { part, joints, local }
                            };
                            let (a, b) = (place(&anchors[0]), place(&anchors[1]));
                            let (k, free) = (*stiffness_n_per_m, *free_length);
                            Box::new(move |row: &[Point]| {
                                let stretch = (a.at(row).distance(b.at(row)) - free) * metres;
                                0.5 * k * stretch * stretch
                            })
                        }
                        Spring::Torsion { part, stiffness_nm_per_rad, free_angle_deg, .. } => {
                            let p = parts.iter().find(|p| &p.name == part).unwrap();
                            let fixed = mechanism.topology.fixed_joints();
                            let pivot = *p.joints.iter().find(|j| fixed.contains(j)).unwrap();
                            let tip = *p.joints.iter().find(|j| !fixed.contains(j)).unwrap();
                            let first = trace.row(0)[tip] - trace.row(0)[pivot];
                            let (k, free) = (*stiffness_nm_per_rad, free_angle_deg.to_radians());
                            // Small steps: the angle from the first row needs no unwrapping here
                            // unless the part turns past a half turn, which these travels do not.
                            Box::new(move |row: &[Point]| {
                                let arm = row[tip] - row[pivot];
                                let twist = first.cross(arm).atan2(first.dot(arm)) - free;
                                0.5 * k * twist * twist
                            })
                        }
                    }
                })
                .collect();
            let bound = 1e-4 * torque.peak_nm;
            assert_energy_derivative(
                &format!("{family:?}"),
                plan,
                trace,
                &balance.torque_with_springs_nm,
                bound,
                |row| {
                    weight_energy(&problem, mechanism, &motion.frames, &MASSES, row)
                        + energies.iter().map(|e| e(row)).sum::<f64>()
                },
            );
        }
    }

    /// A search its observer cancels stops and says so, instead of answering with fewer springs.
    #[test]
    fn a_cancelled_search_stops_and_says_so() {
        struct Cancelling;
        impl Observer for Cancelling {
            fn cancelled(&self) -> bool {
                true
            }
        }
        let (problem, mechanism, plan, trace) = parallelogram();
        // Ten times as dense as MASSES, so the load (11 N·mm) is clearly one that needs a spring.
        let masses = Masses { kg_per_mm3: 1e-5, ..MASSES };
        let torque = driving_torque(&problem, &mechanism, &plan, &trace, &masses).unwrap();
        assert!(torque.peak_nm > 10.0 * NO_SPRING_NEEDED_NM, "{}", torque.peak_nm);
        let balancing = Balancing {
            problem: &problem,
            mechanism: &mechanism,
            plan: &plan,
            trace: &trace,
            masses: &masses,
            torque: &torque,
        };
        assert_eq!(balancing.best(SpringSearch::ANALYSIS, &Cancelling), Err(Cancelled));
        let balance = balancing.best(SpringSearch::ANALYSIS, &crate::Silent).unwrap();
        assert!(!balance.springs.is_empty());
        assert_eq!(balance.need, SpringNeed::Springs);
    }

    /// The series are ISO 3's R10 and R20, in every decade, each member the decimal it is written as.
    #[test]
    fn stock_series_are_the_renard_numbers_in_every_decade() {
        assert_eq!(Series::R10.within(1.0, 10.0), [1.0, 1.25, 1.6, 2.0, 2.5, 3.15, 4.0, 5.0, 6.3, 8.0, 10.0]);
        assert_eq!(Series::R20.within(0.0031, 0.0046), [0.00315, 0.00355, 0.004, 0.0045]);
        assert_eq!(Series::R20.within(2000.0, 2500.0), [2000.0, 2240.0, 2500.0]);
        // R10's members are R20's every other one.
        let r20 = Series::R20.within(0.01, 100.0);
        assert_eq!(Series::R10.within(0.01, 100.0), r20.iter().copied().step_by(2).collect::<Vec<_>>());
        assert_eq!(Series::R10.around(0.0029), Some([0.0025, 0.00315]));
        assert_eq!(Series::R10.around(400.0), Some([400.0, 400.0]));
        assert_eq!(Series::R10.nearest(2.7), Some(2.5));
        assert_eq!(Series::R10.nearest(2.9), Some(3.15));
        assert!(Series::R20.contains(710.0) && !Series::R20.contains(700.0) && !Series::R10.contains(0.0));
        assert_eq!(Series::R10.around(-1.0), None);
        assert!(Series::R10.within(f64::NAN, 1.0).is_empty());
    }
}
