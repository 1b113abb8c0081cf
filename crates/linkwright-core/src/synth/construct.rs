//! Rigid linkages through given poses without the general fit (paper §4.2–4.3), wherever the rigidity
//! equations allow it: the sampler draws joints in the linkage region and moves them onto an exact
//! solution directly, and only the links without one go on to the Levenberg–Marquardt fit of
//! [`super::rigidity`], started from the constructed joints.
//!
//! A link between `m` on body A and `n` on body B (or the ground) keeps its length from the first
//! pose to pose i when `|Gᵢ m − n|² = |m − n|²`, where `Gᵢ = M_B,i⁻¹ M_A,i` is A's motion seen from B.
//! For `m` fixed this is linear in `n`: `n` lies on the perpendicular bisector of `m` and `Gᵢ m`
//! ([`Line`]), and the residual of eq. 4 is `−2 dᵢ · (n − midpointᵢ)` with `dᵢ = Gᵢ m − m`. The same
//! holds for `n` fixed with `Gᵢ⁻¹`. Per block of [`super::rigidity`], for N poses:
//! - **links with fewer equations than unknowns** (a binary link for N ≤ 3, a ternary link for
//!   N = 2): the exact solutions form a manifold, and the fit from uniform draws ends near the draws'
//!   nearest point on it. Minimum-norm Gauss–Newton steps from the draws ([`project`]) reach about the
//!   same point in a few cheap iterations. Solving one end in closed form from the other's draw (the
//!   circumcentre for a ground pivot and N = 3, the point of the bisector nearest a second draw for
//!   N = 2) is cheaper still, but it moves one joint all the way: on the bundled scenes it gives more
//!   kinematically valid samples yet fewer collision-free ones and costlier designs, so it only seeds
//!   the fit below.
//! - **links with as many equations as unknowns or more** (a binary link for N ≥ 4, a ternary link
//!   for N ≥ 3): one end drawn, the next on its bisectors, the third by least squares: a start that
//!   the fit polishes.
//! - **the slider joint** `q` and direction φ: for N = 2 any point works (the line through its two
//!   positions); for N = 3 the positions are collinear exactly on a circle, because
//!   `(q¹ − q⁰) × (q² − q⁰)` is `α|q|² + β·q + γ` (the quadratic part of `((R₁ − I)q) × ((R₂ − I)q)` is
//!   a multiple of `|q|²`), so `q` is that circle's point nearest the draw; for N ≥ 4 the same start
//!   on the first three poses, then polished.
//!
//! Blocks are built and polished one after the other, in chain order, each checked as soon as its
//! joints are placed: the loop it closes keeps its branch at every pose, its ternary link is not
//! turned over, its joints are apart from their parts' others ([`Constructor::construct`]). A block
//! whose solved joint lands far outside the region's box, or a ternary link that fails a check, is
//! drawn again a few times (the sample's own random stream, so results stay reproducible): such a
//! joint would only be penalised by `E_loc` later.

use super::rigidity::turns_over;
use crate::geom::{Aabb, Point, Rigid, Vec2};
use crate::kinematics::{circle_circle, complete, completion_order, Branch, Completion, Plan};
use crate::mechanism::{PartKind, Topology};
use rand::RngExt;
use rand_xoshiro::Xoshiro256PlusPlus;
use std::f64::consts::PI;

/// How often a block is drawn when a solved joint lands far outside the region's box, or a ternary
/// link leaves a defect ([`Constructor::construct`]).
const TRIES: usize = 4;
/// The same for a ternary link through three poses. Such a link has finitely many exact solutions
/// (six equations in six unknowns), which Newton's method from random starts finds one at a time
/// ([`ternary_through_three`]), and most of them are turned over or change a loop's branch; with
/// three or more such links in a row, four tries each leave too few whole samples: chains of five
/// and six bodies through three poses find a design on 5 of the 6 `linkwright bench --known` scenes
/// (its K = 5–6, N = 3 rows) with 16 tries, on 4 with 4. Newton's method makes a try cheap enough for
/// two- and three-body chains to take as many, and their designs then come closer to the poses than
/// with the general fit and four tries, in less time.
const THREE_POSE_TERNARY_TRIES: usize = 16;
/// How far outside the region's box a solved joint may land, in box diagonals, before the block is
/// drawn again.
const BOX_MARGIN: f64 = 0.5;
/// Below this `|det|` relative to the squared trace, a least-squares point of lines is taken as
/// undetermined (the lines are parallel).
const SINGULAR: f64 = 1e-14;
/// Points along the rocking link's travel at which a turning tip's distances are measured
/// ([`Constructor::turning`]).
const TURN_SAMPLES: usize = 32;
/// The most a turning tip's crank and link may differ, relative to their sum, when they stretch out
/// at the turn: a crank much shorter than its link barely moves the rocking link.
const TURN_SPREAD: f64 = 0.8;
/// Gauss–Newton steps of [`Constructor::round_places`], the finite-difference step of its Jacobian
/// (relative to the link's length) and its damping (relative to the normal matrix's mean diagonal).
const ROUNDING_ITERATIONS: usize = 10;
/// The fewest poses through which [`Constructor::round_places`] moves the free joints. Through four,
/// the least-squares centre leaves the rocker stretching little, and the joints' moves cost more
/// than they buy: `k1_garbage_truck2` (four poses, a Stephenson-III) costs 2.38 unrounded and 2.82
/// rounded (`linkwright design` with `mechanism: stephenson_iii`).
const ROUNDED_POSES: usize = 5;
const ROUNDING_STEP: f64 = 1e-7;
const ROUNDING_DAMPING: f64 = 1e-9;

/// One independent block of the rigidity energy, as a construction.
#[derive(Clone, Copy, Debug)]
enum Piece {
    /// A link holding two joints.
    Binary([usize; 2]),
    /// A link holding three joints.
    Ternary([usize; 3]),
    /// The slider joint; the slider angle is the last unknown.
    Slider(usize),
    /// A joint no rigidity equation holds (carried by links only, or a ground pivot whose links
    /// carry no other joint the ground or a body carries): drawn where the region says.
    Free(usize),
    /// `[pivot, joint]`: a ground pivot whose link's other joint is carried by links only and placed
    /// without that link ([`Constructor::new`]): the pivot goes to the centre of that joint's places
    /// through the poses, so the link keeps its length (exactly through three poses).
    Centre([usize; 2]),
    /// The crank's tip, where the crank meets a link to a joint that turns about a ground pivot
    /// ([`TurningTip`]): placed so that the joint turns back where the poses do.
    Turning(TurningTip),
}

/// A crank's tip placed where the crank (about the ground joint `pivot`) meets a link to
/// `follower`, a joint carried by links only on a link that turns about the ground joint `hub` and
/// holds `arm`, a joint a body carries: a Watt-II six-bar's drive, whose body's four-bar has
/// `hub`–`arm` as its input.
///
/// Such a link rocks back exactly where the crank and the link to it line up, at the distance
/// between `pivot` and `follower` equal to the sum (or the difference) of the two links' lengths.
/// When the poses take the rocking link out and back, a tip drawn at random rarely puts that
/// turn between the right poses (`linkwright bench --known` scenes of out-and-back Watt-II
/// motions through five or more poses: no design in 200,000 samples on two scenes of three). So
/// the links' lengths are chosen to put the turn just beyond the pose where the link is farthest
/// out, and the tip is placed with them.
#[derive(Clone, Copy, Debug)]
struct TurningTip {
    tip: usize,
    pivot: usize,
    follower: usize,
    hub: usize,
    arm: usize,
}

impl Piece {
    /// The joints the piece places, in its order.
    fn joints(&self) -> &[usize] {
        match self {
            Piece::Binary(j) => j,
            Piece::Ternary(j) => j,
            Piece::Slider(q) | Piece::Free(q) => std::slice::from_ref(q),
            Piece::Centre(pivot_and_joint) => &pivot_and_joint[..1],
            Piece::Turning(turning) => std::slice::from_ref(&turning.tip),
        }
    }
}

/// The closed-form constructions of one topology, built once.
#[derive(Clone, Debug)]
pub(crate) struct Constructor {
    pieces: Vec<Piece>,
    /// The moving body carrying each joint, `None` for the ground.
    carriers: Vec<Option<usize>>,
    tolerances: Tolerances,
    /// The dyads of the solving order, `[a, b, joint]` ([`Plan::dyad_triangles`]): each loop's
    /// branch, which a block must keep through the poses once all three joints are placed.
    dyads: Vec<[usize; 3]>,
    /// Every pair of joints on one part.
    part_pairs: Vec<(usize, usize)>,
    /// Whether each joint is carried by links only ([`Topology::link_only_joints`]).
    link_only: Vec<bool>,
    /// Where each pinned joint must be ([`Constructor::with_pins`]).
    pins: Vec<Option<Point>>,
    /// How the joints carried by links only are placed at a pose ([`completion_order`]).
    completion: Vec<Completion>,
    /// The joints of [`Piece::Free`] pieces not pinned: no rigidity equation holds them, so
    /// [`Constructor::round_places`] may move them.
    movable: Vec<usize>,
}

/// What a constructed block must meet.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Tolerances {
    /// How far a projected link's length may stray from pose to pose (a length).
    pub projection: f64,
    /// The largest relative deviation a polished block may keep (see
    /// [`super::rigidity::Fit::max_relative_deviation`]).
    pub deviation: f64,
    /// Twice the height below which a ternary link counts as straight, so turning it over is not a
    /// defect (a length; see [`super::rigidity::RigidityModel::mirrored`]).
    pub flip: f64,
    /// How close two joints of one part may be (a length).
    pub spacing: f64,
    /// Whether a ternary link turned over at an intermediate pose is a defect: where the linkage
    /// type can pass every pose exactly (else only the last pose is checked).
    pub intermediate_turnover: bool,
}

/// Fits the block holding a joint (the second argument) in `x` and returns its relative deviation;
/// a quick fit (the third argument) gives up sooner, where another draw is cheaper than a slow fit.
pub(crate) type Polish<'a> = dyn FnMut(&mut [f64], usize, bool) -> f64 + 'a;

/// Reusable buffers of [`Constructor::construct`].
#[derive(Clone, Debug, Default)]
pub(crate) struct ConstructScratch {
    lines: Vec<Line>,
    /// The slider's direction, when the topology has one.
    slider_direction: Option<Vec2>,
    /// Which joints the blocks built so far have placed.
    placed: Vec<bool>,
}

impl ConstructScratch {
    /// The unit direction of the last construction's slider (`None` without a slider): its angle
    /// is left out of the parameter vector, since only a fit reads it there.
    pub(crate) fn slider_direction(&self) -> Option<Vec2> {
        self.slider_direction
    }
}

/// The points `y` with `normal · (y − point) = 0` (a line when `normal` is not zero).
#[derive(Clone, Copy, Debug)]
struct Line {
    normal: Vec2,
    point: Point,
}

/// Where to draw joints and which solved joints to keep.
pub(crate) struct Region<'a> {
    /// Draws a point of the linkage region.
    pub draw: &'a mut dyn FnMut(&mut Xoshiro256PlusPlus) -> Point,
    /// The region's bounding box.
    pub bounds: Aabb,
}

impl Region<'_> {
    /// Whether a solved joint lands near enough to the region to be worth keeping.
    fn keeps(&self, p: Point) -> bool {
        let b = &self.bounds;
        let margin = BOX_MARGIN * b.diagonal();
        p.is_finite()
            && p.x >= b.min.x - margin
            && p.x <= b.max.x + margin
            && p.y >= b.min.y - margin
            && p.y <= b.max.y + margin
    }
}

impl Constructor {
    /// The constructions for `topology`: one per link, and one for the slider.
    pub(crate) fn new(topology: &Topology, tolerances: Tolerances) -> Self {
        let mut carriers = vec![None; topology.joint_count()];
        for part in &topology.parts {
            if let PartKind::Body(b) = part.kind {
                for &j in &part.joints {
                    carriers[j] = Some(b);
                }
            }
        }
        let mut link_only = vec![false; topology.joint_count()];
        for j in topology.link_only_joints() {
            link_only[j] = true;
        }
        // Each link's rigidity equations hold between the joints the ground or a body carries.
        let mut pieces: Vec<Piece> = topology
            .parts
            .iter()
            .filter(|p| p.kind == PartKind::Link)
            .filter_map(|p| {
                let carried: Vec<usize> = p.joints.iter().copied().filter(|&j| !link_only[j]).collect();
                match carried[..] {
                    [a, b] => Some(Piece::Binary([a, b])),
                    [a, b, c] => Some(Piece::Ternary([a, b, c])),
                    _ => None,
                }
            })
            .collect();
        pieces.extend(topology.slider_joint.map(Piece::Slider));
        // A ground pivot linked to a joint the completion places some other way (not from this
        // link): nothing else keeps that link's length, so the pivot is solved for, last.
        let completion = completion_order(topology);
        let fixed = topology.fixed_joints();
        let placed_from = |joint: usize, pivot: usize| {
            completion.iter().any(
                |step| matches!(*step, Completion::Dyad { joint: j, a, b } if j == joint && (a == pivot || b == pivot)),
            )
        };
        let centres: Vec<Piece> = topology
            .parts
            .iter()
            .filter(|p| p.kind == PartKind::Link)
            .filter_map(|p| match p.joints[..] {
                [g, j] | [j, g] if fixed.contains(&g) && link_only[j] && !placed_from(j, g) => {
                    Some(Piece::Centre([g, j]))
                }
                _ => None,
            })
            .collect();
        let free: Vec<Piece> = (0..topology.joint_count())
            .filter(|j| !pieces.iter().chain(&centres).any(|piece| piece.joints().contains(j)))
            .map(Piece::Free)
            .collect();
        pieces.extend(free);
        // A crank tip that can turn a rocking link back is drawn as a free joint (so one-way motions
        // are drawn as before), then moved where the poses take that link out and back, once the
        // joints it is placed from are placed.
        pieces.extend(turning_tip(topology, &completion, &link_only).map(Piece::Turning));
        pieces.extend(centres);
        let movable = pieces
            .iter()
            .filter_map(|piece| match *piece {
                Piece::Free(j) => Some(j),
                _ => None,
            })
            .collect();
        Constructor {
            pieces,
            carriers,
            tolerances,
            dyads: Plan::dyad_triangles(topology),
            part_pairs: topology.part_pairs(),
            link_only,
            pins: vec![None; topology.joint_count()],
            completion,
            movable,
        }
    }

    /// The same constructions with the joints `pins` (index, place) put at their places: a block
    /// holding one is built as usual, then those joints are moved to their pins and the fit
    /// ([`Polish`], which must hold them there) finds the others.
    pub(crate) fn with_pins(mut self, pins: &[(usize, Point)]) -> Self {
        for &(j, p) in pins {
            self.pins[j] = Some(p);
        }
        self.movable.retain(|&j| self.pins[j].is_none());
        self
    }

    /// Fills `x`'s joints with a linkage through `motions` (`motions[b][i]` carries body b from the
    /// first pose to pose i), drawing joints with `region`, and puts the slider's direction in
    /// `scratch` ([`ConstructScratch::slider_direction`]; `x`'s slider angle is left unset). A block
    /// with no closed form for this many poses, or whose construction degenerated, holds a start
    /// that `polish` fits (it returns the block's relative deviation).
    /// Returns the largest deviation of the blocks polished (0 when none was), infinite when some
    /// block could not be built without a defect.
    ///
    /// Blocks are built in chain order, so each loop is closed by the block built last in it. A
    /// ternary link that leaves a loop on another branch at some pose, turns over, puts two joints
    /// of a part too close or cannot be fitted is drawn again right away: drawing the whole linkage
    /// again instead would make defect-free chains of five or six bodies as rare as the product of
    /// each loop's chance (none in 10⁶ samples of a five-body chain through two poses: `linkwright
    /// design SCENE --samples 1000000` on the K = 5, N = 2 scenes of `linkwright bench --known --save
    /// DIR`). Any other block with a defect ends the sample.
    pub(crate) fn construct(
        &self,
        x: &mut [f64],
        motions: &[Vec<Rigid>],
        rng: &mut Xoshiro256PlusPlus,
        region: &mut Region,
        polish: &mut Polish,
        scratch: &mut ConstructScratch,
    ) -> f64 {
        let poses = motions.first().map_or(1, Vec::len);
        let angle = 2 * self.carriers.len();
        scratch.slider_direction = None;
        scratch.placed.clear();
        scratch.placed.resize(self.carriers.len(), false);
        let set = |x: &mut [f64], j: usize, p: Point| {
            x[2 * j] = p.x;
            x[2 * j + 1] = p.y;
        };
        let mut worst = 0.0f64;
        for piece in &self.pieces {
            let joints = piece.joints();
            // The first sound try that lands near the region, else the first sound one.
            let mut best: Option<Built> = None;
            let (tries, quick) = match piece {
                Piece::Ternary(_) if poses == 3 => (THREE_POSE_TERNARY_TRIES, true),
                _ => (TRIES, false),
            };
            for _ in 0..tries {
                let mut built = match *piece {
                    Piece::Binary(joints) => self.binary(joints, motions, poses, rng, region, scratch),
                    Piece::Ternary(joints) => self.ternary(joints, motions, poses, rng, region, scratch),
                    Piece::Slider(q) => slider(self.carriers[q], motions, poses, rng, region),
                    Piece::Free(_) => Built::joints(&[(region.draw)(rng)], false),
                    Piece::Turning(turning) => {
                        let drawn = Point::new(x[2 * turning.tip], x[2 * turning.tip + 1]);
                        let tip = self.turning(turning, x, motions, poses, rng).unwrap_or(drawn);
                        Built::joints(&[tip], false)
                    }
                    Piece::Centre([_, joint]) => match self.centre_of(joint, x, motions, poses) {
                        Some(centre) if poses >= ROUNDED_POSES => {
                            Built::joints(&[self.round_places(joint, centre, x, motions)], false)
                        }
                        Some(centre) => Built::joints(&[centre], false),
                        None => return f64::INFINITY,
                    },
                };
                for (k, &j) in joints.iter().enumerate() {
                    if let Some(pin) = self.pins[j] {
                        built.points[k] = pin;
                        // Only a link's or the slider's block has a fit to find the others.
                        built.polish |= matches!(piece, Piece::Binary(_) | Piece::Ternary(_) | Piece::Slider(_));
                    }
                }
                if built.polish {
                    for (&j, &p) in joints.iter().zip(&built.points) {
                        set(x, j, p);
                    }
                    if let Some(direction) = built.direction {
                        x[angle] = direction.angle();
                    }
                    built.deviation = polish(x, joints[0], quick);
                    for (k, &j) in joints.iter().enumerate() {
                        built.points[k] = Point::new(x[2 * j], x[2 * j + 1]);
                    }
                    if built.direction.is_some() {
                        built.direction = Some(Vec2::from_angle(x[angle]));
                    }
                }
                let sound = built.deviation <= self.tolerances.deviation
                    && self.free_of_defects(piece, &built, x, motions, &scratch.placed);
                match (sound, piece) {
                    (true, _) => {}
                    (false, Piece::Ternary(_) | Piece::Free(_) | Piece::Turning(_)) => continue,
                    (false, Piece::Centre(_)) => return f64::INFINITY,
                    // A binary link's defect is as likely with any draw: the sample ends here,
                    // before the work of the blocks after it and of its checks.
                    (false, _) => return f64::INFINITY,
                }
                let kept = built.points[..built.len].iter().all(|&p| region.keeps(p));
                if best.is_none() || kept {
                    best = Some(built);
                }
                if kept {
                    break;
                }
            }
            let Some(built) = best else { return f64::INFINITY };
            for (&j, &p) in joints.iter().zip(&built.points) {
                set(x, j, p);
                scratch.placed[j] = true;
            }
            if let Some(direction) = built.direction {
                scratch.slider_direction = Some(direction);
            }
            worst = worst.max(built.deviation);
        }
        worst
    }

    /// Whether `built`, the joints of `piece`, keeps every loop it closes on one branch through the
    /// poses, its ternary link the right way round, and its joints apart from the others of their
    /// parts (the joints of earlier blocks are in `x`, flagged in `placed`).
    fn free_of_defects(
        &self,
        piece: &Piece,
        built: &Built,
        x: &[f64],
        motions: &[Vec<Rigid>],
        placed: &[bool],
    ) -> bool {
        if let Piece::Slider(_) = piece {
            return true;
        }
        let joints = piece.joints();
        let at = |j: usize| match joints.iter().position(|&k| k == j) {
            Some(k) => Some(built.points[k]),
            None => placed[j].then(|| Point::new(x[2 * j], x[2 * j + 1])),
        };
        let poses = motions.first().map_or(1, Vec::len);
        // `(b − a) × (c − a)` at pose i, for a triangle of joints at `first` in the first pose.
        let orientation = |triangle: [usize; 3], first: [Point; 3], i: usize| {
            let [a, b, c] = [0, 1, 2].map(|k| carried(motions, self.carriers[triangle[k]], i, first[k]));
            (b - a).cross(c - a)
        };
        let keeps = |triangle: [usize; 3], first: [Point; 3]| {
            let sign = orientation(triangle, first, 0);
            (1..poses).all(|i| orientation(triangle, first, i) * sign > 0.0)
        };
        let apart = self.part_pairs.iter().filter(|(a, b)| joints.contains(a) || joints.contains(b)).all(|&(a, b)| {
            match (at(a), at(b)) {
                (Some(p), Some(q)) => p.distance(q) >= self.tolerances.spacing,
                _ => true,
            }
        });
        // A dyad through a joint carried by links only is checked once the whole linkage is built
        // (the screening places such joints at every pose).
        let checkable = |t: &&[usize; 3]| t.iter().any(|j| joints.contains(j)) && t.iter().all(|&j| !self.link_only[j]);
        let closed = self.dyads.iter().filter(checkable).all(|&t| match (at(t[0]), at(t[1]), at(t[2])) {
            (Some(a), Some(b), Some(c)) => keeps(t, [a, b, c]),
            _ => true,
        });
        let turned_over = match *piece {
            Piece::Ternary(t) => {
                let first = [built.points[0], built.points[1], built.points[2]];
                // A fit through more poses than it can pass keeps a residual at the intermediate
                // ones; like the rest of the sampler, it answers for the end poses only.
                let checked = if self.tolerances.intermediate_turnover { 1..poses } else { poses - 1..poses };
                let at = |i: usize| [0, 1, 2].map(|k| carried(motions, self.carriers[t[k]], i, first[k]));
                turns_over(first, checked.map(at), self.tolerances.flip)
            }
            _ => false,
        };
        apart && closed && !turned_over
    }

    /// Where `turning.tip` goes so that its rocking link turns back between the right poses
    /// ([`TurningTip`]), the joints it is placed from already in `x`; `None` when the poses take
    /// that link one way (or back and forth more than once), or no lengths put the turn there.
    fn turning(
        &self,
        turning: TurningTip,
        x: &[f64],
        motions: &[Vec<Rigid>],
        poses: usize,
        rng: &mut Xoshiro256PlusPlus,
    ) -> Option<Point> {
        if poses < 3 {
            return None;
        }
        let at = |j: usize| Point::new(x[2 * j], x[2 * j + 1]);
        let (pivot, follower, hub, arm) = (at(turning.pivot), at(turning.follower), at(turning.hub), at(turning.arm));
        // The rocking link's angle at each pose from the first, unwrapped.
        let start = arm - hub;
        let mut angles = Vec::with_capacity(poses);
        let mut previous = 0.0;
        for i in 0..poses {
            let now = carried(motions, self.carriers[turning.arm], i, arm) - hub;
            let mut angle = start.cross(now).atan2(start.dot(now));
            angle += (previous - angle + PI).div_euclid(2.0 * PI) * 2.0 * PI;
            angles.push(angle);
            previous = angle;
        }
        // Out to pose `k`, then back: one reversal.
        let out = (angles[1] - angles[0]).signum();
        let k = (1..poses - 1).find(|&i| (angles[i + 1] - angles[i]) * out < 0.0)?;
        if (k..poses - 1).any(|i| (angles[i + 1] - angles[i]) * out > 0.0) {
            return None;
        }
        let step = (angles[k] - angles[k - 1]).abs().max((angles[k] - angles[k + 1]).abs());
        let turn = angles[k] + out * step * rng.random::<f64>();
        let reach = |angle: f64| pivot.distance(hub + Rigid::new(angle, Vec2::ZERO).rotate(follower - hub));
        // The distances the rocking link passes through on its way out, against the one at its turn.
        let nearest = angles.iter().map(|a| a * out).fold(f64::INFINITY, f64::min) * out;
        let at_turn = reach(turn);
        let (mut least, mut most) = (f64::INFINITY, 0.0f64);
        for s in 0..TURN_SAMPLES {
            let d = reach(nearest + (turn - nearest) * s as f64 / TURN_SAMPLES as f64);
            (least, most) = (least.min(d), most.max(d));
        }
        let (crank, link) = if most < at_turn {
            // The turn where the two links stretch out: their lengths add up to the distance there,
            // and differ by less than the nearest the rocking link comes.
            let spread = (least / at_turn).min(TURN_SPREAD);
            let share = 0.5 + spread * (rng.random::<f64>() - 0.5);
            (share * at_turn, (1.0 - share) * at_turn)
        } else if least > at_turn {
            // The turn where they fold: their lengths differ by the distance there, and add up to
            // more than the farthest the rocking link goes.
            let sum = most * (1.0 + rng.random::<f64>());
            let (long, short) = (0.5 * (sum + at_turn), 0.5 * (sum - at_turn));
            if rng.random::<bool>() {
                (long, short)
            } else {
                (short, long)
            }
        } else {
            return None;
        };
        let branch = if rng.random::<bool>() { Branch::Positive } else { Branch::Negative };
        circle_circle(pivot, crank, follower, link, branch).ok()
    }

    /// The places `joint` (carried by links only) takes at each pose, into `places`, from `first`,
    /// every joint at the first pose (`row` a buffer). False when the linkage does not assemble at
    /// some pose.
    fn places_of(
        &self,
        joint: usize,
        first: &[Point],
        motions: &[Vec<Rigid>],
        row: &mut Vec<Point>,
        places: &mut Vec<Point>,
    ) -> bool {
        row.clear();
        row.extend_from_slice(first);
        places.clear();
        for i in 0..motions.first().map_or(1, Vec::len) {
            for k in (0..first.len()).filter(|&k| !self.link_only[k]) {
                row[k] = carried(motions, self.carriers[k], i, first[k]);
            }
            if complete(&self.completion, first, row).is_err() {
                return false;
            }
            places.push(row[joint]);
        }
        true
    }

    /// The centre of the places `joint` (carried by links only) takes through the poses, the other
    /// joints placed in `x`: the circumcentre through three poses, the least-squares centre through
    /// more (the algebraic fit: linear in the centre and in r² − |c|²), the midpoint of the two
    /// places through two. `None` when the linkage does not assemble at a pose or the places are
    /// collinear.
    fn centre_of(&self, joint: usize, x: &[f64], motions: &[Vec<Rigid>], poses: usize) -> Option<Point> {
        let first: Vec<Point> = (0..self.carriers.len()).map(|k| Point::new(x[2 * k], x[2 * k + 1])).collect();
        let (mut row, mut places) = (Vec::new(), Vec::with_capacity(poses));
        if !self.places_of(joint, &first, motions, &mut row, &mut places) {
            return None;
        }
        match places[..] {
            [] | [_] => None,
            [p, q] => Some(Point::new(0.5 * (p.x + q.x), 0.5 * (p.y + q.y))),
            _ => {
                // Normal equations of 2 pᵢ·c + k = |pᵢ|², about the places' mean for conditioning.
                let m = places.iter().fold(Vec2::ZERO, |s, p| s + (*p - Point::ORIGIN)) * (1.0 / places.len() as f64);
                let (mut a, mut r) = ([[0.0f64; 3]; 3], [0.0f64; 3]);
                for p in &places {
                    let v = *p - Point::ORIGIN - m;
                    let row = [2.0 * v.x, 2.0 * v.y, 1.0];
                    for (i, ri) in row.iter().enumerate() {
                        for (j, rj) in row.iter().enumerate() {
                            a[i][j] += ri * rj;
                        }
                        r[i] += ri * v.norm_sq();
                    }
                }
                let c = solve3(a, r)?;
                Some(Point::ORIGIN + m + Vec2::new(c[0], c[1]))
            }
        }
    }

    /// The centre `joint`'s places turn about once the joints of [`Piece::Free`] pieces are moved
    /// (in `x`) so that those places lie on a circle, from `centre`, their least-squares centre:
    /// through more than three poses the places of joints drawn at random lie on no circle, so the link
    /// from the centre would stretch between poses (a Stephenson-III's rocker, whose coupler carries
    /// the body). The free joints have no rigidity equation of their own, so moving them breaks no
    /// other block. Damped Gauss–Newton steps on `|placeᵢ − centre| − radius`, with the centre and
    /// radius free too, from the draws: the least change that rounds the places, which is exact
    /// through as many poses as there are free coordinates and the best fit through more. When the
    /// steps do not bring the places nearer a circle, `x` and `centre` are kept.
    fn round_places(&self, joint: usize, centre: Point, x: &mut [f64], motions: &[Vec<Rigid>]) -> Point {
        use nalgebra::{DMatrix, DVector};
        let poses = motions.first().map_or(1, Vec::len);
        let movable = &self.movable;
        let dim = 2 * movable.len() + 3;
        // The unknowns: the movable joints' coordinates, then the centre and the radius.
        let mut first: Vec<Point> = (0..self.carriers.len()).map(|k| Point::new(x[2 * k], x[2 * k + 1])).collect();
        let (mut row, mut places) = (Vec::new(), Vec::with_capacity(poses));
        let mut residuals = |v: &DVector<f64>, out: &mut DVector<f64>| -> bool {
            for (m, &j) in movable.iter().enumerate() {
                first[j] = Point::new(v[2 * m], v[2 * m + 1]);
            }
            let c = Point::new(v[dim - 3], v[dim - 2]);
            if !self.places_of(joint, &first, motions, &mut row, &mut places) {
                return false;
            }
            for (i, p) in places.iter().enumerate() {
                out[i] = p.distance(c) - v[dim - 1];
            }
            true
        };
        let mut v = DVector::zeros(dim);
        for (m, &j) in movable.iter().enumerate() {
            (v[2 * m], v[2 * m + 1]) = (x[2 * j], x[2 * j + 1]);
        }
        (v[dim - 3], v[dim - 2]) = (centre.x, centre.y);
        let mut r = DVector::zeros(poses);
        // The radius that fits the places best from this centre: their mean distance.
        v[dim - 1] = 0.0;
        if !residuals(&v, &mut r) {
            return centre;
        }
        v[dim - 1] = r.mean();
        residuals(&v, &mut r);
        let start = r.amax();
        // Forward differences (the places come out of the completion's dyads), a step relative to the
        // link's length.
        let h = ROUNDING_STEP * centre.distance(Point::new(x[2 * joint], x[2 * joint + 1])).max(f64::MIN_POSITIVE);
        let (mut jacobian, mut trial) = (DMatrix::zeros(poses, dim), DVector::zeros(poses));
        // False for NaN.
        let nearer = |now: f64, before: f64| now < before;
        for _ in 0..ROUNDING_ITERATIONS {
            if r.amax() <= self.tolerances.projection {
                break;
            }
            for c in 0..dim {
                let mut moved = v.clone();
                moved[c] += h;
                if !residuals(&moved, &mut trial) {
                    return centre;
                }
                jacobian.set_column(c, &((&trial - &r) / h));
            }
            let jt = jacobian.transpose();
            let mut normal = &jt * &jacobian;
            let damping = ROUNDING_DAMPING * normal.trace() / dim as f64;
            for d in 0..dim {
                normal[(d, d)] += damping;
            }
            let Some(step) = normal.cholesky().map(|c| c.solve(&(-(&jt * &r)))) else { break };
            let next = &v + step;
            if !residuals(&next, &mut trial) || !nearer(trial.amax(), r.amax()) {
                break;
            }
            v = next;
            std::mem::swap(&mut r, &mut trial);
        }
        if !nearer(r.amax(), start) {
            return centre;
        }
        for (m, &j) in movable.iter().enumerate() {
            (x[2 * j], x[2 * j + 1]) = (v[2 * m], v[2 * m + 1]);
        }
        Point::new(v[dim - 3], v[dim - 2])
    }

    /// A binary link `[a, b]`: projected from two draws for N ≤ 3, else the better of the two
    /// least-squares ends as the fit's start.
    fn binary(
        &self,
        [a, b]: [usize; 2],
        motions: &[Vec<Rigid>],
        poses: usize,
        rng: &mut Xoshiro256PlusPlus,
        region: &mut Region,
        scratch: &mut ConstructScratch,
    ) -> Built {
        let (ca, cb) = (self.carriers[a], self.carriers[b]);
        let (da, db) = ((region.draw)(rng), (region.draw)(rng));
        if poses <= 3 {
            let mut points = [da, db];
            // One equation per pose after the first: at most two.
            if project_link(&mut points, [ca, cb], motions, poses, self.tolerances.projection) {
                return Built::joints(&points, false);
            }
            return Built::joints(&[da, db], true);
        }
        let lines = &mut scratch.lines;
        bisectors(motions, poses, da, ca, cb, lines);
        let b_from_a = nearest_on(lines, db);
        bisectors(motions, poses, db, cb, ca, lines);
        let a_from_b = nearest_on(lines, da);
        let chosen = match (b_from_a, a_from_b) {
            (Some(pb), Some(pa)) if pb.distance(db) <= pa.distance(da) => Some([da, pb]),
            (_, Some(pa)) => Some([pa, db]),
            (Some(pb), None) => Some([da, pb]),
            (None, None) => None,
        };
        Built::joints(&chosen.unwrap_or([da, db]), true)
    }

    /// A ternary link: projected from three draws for two poses, else a start for the fit.
    fn ternary(
        &self,
        joints: [usize; 3],
        motions: &[Vec<Rigid>],
        poses: usize,
        rng: &mut Xoshiro256PlusPlus,
        region: &mut Region,
        scratch: &mut ConstructScratch,
    ) -> Built {
        let draws = [(region.draw)(rng), (region.draw)(rng), (region.draw)(rng)];
        let c = joints.map(|j| self.carriers[j]);
        if poses == 2 {
            let mut points = draws;
            // Three pairs through two poses: three equations.
            if project::<3, 3, 4>(
                &mut points,
                &c,
                &[(0, 1), (0, 2), (1, 2)],
                motions,
                poses,
                self.tolerances.projection,
            ) {
                return Built::joints(&points, false);
            }
            return Built::joints(&draws, true);
        }
        // Keep the first draw, put the second on its bisectors, the third by least squares on both.
        let lines = &mut scratch.lines;
        bisectors(motions, poses, draws[0], c[0], c[1], lines);
        let Some(second) = nearest_on(lines, draws[1]) else { return Built::joints(&draws, true) };
        bisectors(motions, poses, draws[0], c[0], c[2], lines);
        bisectors_onto(motions, poses, second, c[1], c[2], lines);
        let third = nearest_on(lines, draws[2]).unwrap_or(draws[2]);
        if poses == 3 {
            return match ternary_through_three(motions, c, [draws[0], second, third], region.bounds.diagonal()) {
                Some(points) => Built::joints(&points, false),
                None => Built { deviation: f64::INFINITY, ..Built::joints(&draws, false) },
            };
        }
        Built::joints(&[draws[0], second, third], true)
    }
}

/// Newton iterations of [`ternary_through_three`].
const TERNARY_NEWTON_ITERATIONS: usize = 15;
/// [`ternary_through_three`] stops once each residual, a difference of squared lengths, is under this
/// share of the squared scale: exact to rounding.
const TERNARY_RESIDUAL: f64 = 1e-13;

/// A ternary link through three poses whose joints ride on `carriers`, solved exactly from `start`;
/// `None` when Newton's method does not converge from there.
///
/// Each pair of its joints keeps its distance at poses 2 and 3: six equations, each quadratic in the
/// six coordinates, with a Jacobian in closed form. Newton's method on them (each step halved while
/// it does not lower the largest residual) does what the general fit does from the same start, for
/// a fraction of its work: in its place, the general fit takes 90% of the sampling time of chains of
/// five and six bodies through three poses (`perf record -e cpu-clock linkwright design SCENE` on the
/// K = 5–6, N = 3 scenes of `linkwright bench --known --save DIR`).
fn ternary_through_three(
    motions: &[Vec<Rigid>],
    carriers: [Option<usize>; 3],
    start: [Point; 3],
    scale: f64,
) -> Option<[Point; 3]> {
    use nalgebra::{SMatrix, SVector};
    const PAIRS: [(usize, usize); 3] = [(0, 1), (0, 2), (1, 2)];
    let residuals = |x: &[Point; 3], mut jacobian: Option<&mut SMatrix<f64, 6, 6>>| {
        let mut r = SVector::<f64, 6>::zeros();
        for (k, &(a, b)) in PAIRS.iter().enumerate() {
            let w = x[a] - x[b];
            for i in 1..3 {
                let u = carried(motions, carriers[a], i, x[a]) - carried(motions, carriers[b], i, x[b]);
                let row = 2 * k + i - 1;
                r[row] = u.norm_sq() - w.norm_sq();
                if let Some(j) = jacobian.as_deref_mut() {
                    // d|u|²/dx = 2·Rᵀu for the joint's carrier's rotation R; d|w|²/dx = ±2w.
                    let back = |c: Option<usize>| c.map_or(u, |c| motions[c][i].unrotate(u));
                    let (da, db) = (back(carriers[a]) * 2.0 - w * 2.0, w * 2.0 - back(carriers[b]) * 2.0);
                    (j[(row, 2 * a)], j[(row, 2 * a + 1)]) = (da.x, da.y);
                    (j[(row, 2 * b)], j[(row, 2 * b + 1)]) = (db.x, db.y);
                }
            }
        }
        r
    };
    // The largest residual; infinite when one is not finite.
    let size = |r: &SVector<f64, 6>| if r.iter().all(|v| v.is_finite()) { r.amax() } else { f64::INFINITY };
    let tolerance = TERNARY_RESIDUAL * scale * scale;
    let mut x = start;
    let mut jacobian = SMatrix::<f64, 6, 6>::zeros();
    let mut r = residuals(&x, Some(&mut jacobian));
    for _ in 0..TERNARY_NEWTON_ITERATIONS {
        if size(&r) <= tolerance {
            return Some(x);
        }
        if size(&r).is_infinite() {
            return None;
        }
        let step = jacobian.lu().solve(&(-r))?;
        // A step longer than the region is heading off to a solution nobody would build.
        if step.norm().is_nan() || step.norm() > scale {
            return None;
        }
        let mut scaled = 1.0;
        let moved = |t: f64| std::array::from_fn(|j| x[j] + Vec2::new(step[2 * j], step[2 * j + 1]) * t);
        for _ in 0..4 {
            if size(&residuals(&moved(scaled), None)) < size(&r) {
                break;
            }
            scaled *= 0.5;
        }
        x = moved(scaled);
        r = residuals(&x, Some(&mut jacobian));
    }
    (size(&r) <= tolerance).then_some(x)
}

/// The topology's crank tip as a [`TurningTip`], when it has one: placed where the crank meets a
/// link to a joint carried by links only on a link turning about a ground joint.
fn turning_tip(topology: &Topology, completion: &[Completion], link_only: &[bool]) -> Option<TurningTip> {
    let (tip, pivot) = (topology.driver_tip, topology.driver_pivot);
    let fixed = topology.fixed_joints();
    let follower = completion.iter().find_map(|step| match *step {
        Completion::Dyad { joint, a, b } if joint == tip && a == pivot => Some(b),
        Completion::Dyad { joint, a, b } if joint == tip && b == pivot => Some(a),
        _ => None,
    })?;
    let (hub, arm) = completion.iter().find_map(|step| match *step {
        Completion::Attach { joint, a, b } if joint == follower && fixed.contains(&a) => Some((a, b)),
        Completion::Attach { joint, a, b } if joint == follower && fixed.contains(&b) => Some((b, a)),
        _ => None,
    })?;
    (link_only[follower] && !link_only[arm]).then_some(TurningTip { tip, pivot, follower, hub, arm })
}

/// A constructed block: its joints (in the piece's order), the slider angle if it has one, and
/// whether the fit must still polish it.
#[derive(Clone, Copy, Debug)]
struct Built {
    points: [Point; 3],
    len: usize,
    /// The slider's unit direction, for the slider piece.
    direction: Option<Vec2>,
    polish: bool,
    /// The block's relative rigidity deviation once polished (0 for a closed form).
    deviation: f64,
}

impl Built {
    fn joints(points: &[Point], polish: bool) -> Built {
        let mut all = [Point::ORIGIN; 3];
        all[..points.len()].copy_from_slice(points);
        Built { points: all, len: points.len(), direction: None, polish, deviation: 0.0 }
    }
}

/// The slider joint on `carrier` and its direction.
fn slider(
    carrier: Option<usize>,
    motions: &[Vec<Rigid>],
    poses: usize,
    rng: &mut Xoshiro256PlusPlus,
    region: &mut Region,
) -> Built {
    let drawn = (region.draw)(rng);
    let at = |i: usize, p: Point| carried(motions, carrier, i, p);
    let (point, exact) = if poses >= 3 {
        match collinear_point(drawn, region.bounds.diagonal(), |p| (at(1, p) - p).cross(at(2, p) - p)) {
            Some(p) => (p, poses == 3),
            None => (drawn, false),
        }
    } else {
        (drawn, true)
    };
    // The direction of the longest travel from the first pose, turned into the upper half-plane (an
    // angle in [0, π)).
    let travel = (1..poses).map(|i| at(i, point) - point).max_by(|a, b| a.norm_sq().total_cmp(&b.norm_sq()));
    let direction = match travel.map(|v| (v, v.norm())) {
        Some((v, length)) if length > 0.0 => {
            let unit = v / length;
            if unit.y < 0.0 || (unit.y == 0.0 && unit.x < 0.0) {
                -unit
            } else {
                unit
            }
        }
        _ => Vec2::new(1.0, 0.0),
    };
    let mut built = Built::joints(&[point], !exact);
    built.direction = Some(direction);
    built
}

/// The point nearest `near` where the quadratic `c(q) = α|q|² + β·q + γ` vanishes; `scale` is a length
/// of the scene, for conditioning.
fn collinear_point(near: Point, scale: f64, c: impl Fn(Point) -> f64) -> Option<Point> {
    // Coefficients in the frame z = (q − near) / scale, from five values.
    let at = |dx: f64, dy: f64| c(near + Vec2::new(dx, dy) * scale);
    let gamma = at(0.0, 0.0);
    let (xp, xm, yp, ym) = (at(1.0, 0.0), at(-1.0, 0.0), at(0.0, 1.0), at(0.0, -1.0));
    let beta = Vec2::new(0.5 * (xp - xm), 0.5 * (yp - ym));
    let alpha = 0.5 * (0.5 * (xp + xm) + 0.5 * (yp + ym)) - gamma;
    let size = alpha.abs() + beta.norm() + gamma.abs();
    if !(size > 0.0 && size.is_finite()) {
        return None;
    }
    let z = if alpha.abs() <= 1e-12 * size {
        // A line β·z + γ = 0.
        let b2 = beta.norm_sq();
        if b2 <= (1e-12 * size).powi(2) {
            return None;
        }
        beta * (-gamma / b2)
    } else {
        // The circle |z − o|² = ρ² with o = −β / 2α.
        let o = beta * (-0.5 / alpha);
        let rho_sq = o.norm_sq() - gamma / alpha;
        if rho_sq < 0.0 {
            return None;
        }
        let (rho, o_norm) = (rho_sq.sqrt(), o.norm());
        if o_norm == 0.0 {
            Vec2::new(rho, 0.0)
        } else {
            o * (1.0 - rho / o_norm)
        }
    };
    Some(near + z * scale)
}

/// The solution of the 3×3 system `a c = r` by Cramer's rule, `None` when it is singular (relative
/// to its entries' size).
fn solve3(a: [[f64; 3]; 3], r: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    let scale = a.iter().flatten().fold(0.0f64, |s, v| s.max(v.abs()));
    if !d.is_finite() || d.abs() <= SINGULAR * scale.powi(3) {
        return None;
    }
    let mut out = [0.0; 3];
    for (k, o) in out.iter_mut().enumerate() {
        let mut m = a;
        for i in 0..3 {
            m[i][k] = r[i];
        }
        *o = det(m) / d;
    }
    Some(out)
}

/// `p` on `carrier` (the ground when `None`) carried to pose `i`.
#[inline]
fn carried(motions: &[Vec<Rigid>], carrier: Option<usize>, i: usize, p: Point) -> Point {
    match carrier {
        Some(b) => motions[b][i].apply(p),
        None => p,
    }
}

/// The first-pose point of `carrier` that is at `p` in pose `i`.
#[inline]
fn uncarried(motions: &[Vec<Rigid>], carrier: Option<usize>, i: usize, p: Point) -> Point {
    match carrier {
        Some(b) => {
            let m = &motions[b][i];
            Point::ORIGIN + m.unrotate(p - (Point::ORIGIN + m.translation()))
        }
        None => p,
    }
}

/// Replaces `out` with the lines, one per pose after the first, on which a joint of `onto` must lie
/// to keep its distance to the joint at `m` on `from`.
fn bisectors(
    motions: &[Vec<Rigid>],
    poses: usize,
    m: Point,
    from: Option<usize>,
    onto: Option<usize>,
    out: &mut Vec<Line>,
) {
    out.clear();
    bisectors_onto(motions, poses, m, from, onto, out);
}

/// [`bisectors`], appended to `out`.
fn bisectors_onto(
    motions: &[Vec<Rigid>],
    poses: usize,
    m: Point,
    from: Option<usize>,
    onto: Option<usize>,
    out: &mut Vec<Line>,
) {
    for i in 1..poses {
        let seen = uncarried(motions, onto, i, carried(motions, from, i, m));
        let d = seen - m;
        out.push(Line { normal: d, point: m + d * 0.5 });
    }
}

/// The point of one line nearest `near`, or the least-squares point of several (rows weighted by
/// their normals' lengths, which makes it the minimiser of the links' residuals of eq. 4); `None`
/// when the lines do not determine a point.
fn nearest_on(lines: &[Line], near: Point) -> Option<Point> {
    if let [line] = lines {
        let n2 = line.normal.norm_sq();
        let scale = (line.point - near).norm_sq() + n2;
        if n2 <= 1e-24 * scale {
            // The joint does not move relative to the other body: every point keeps the length.
            return Some(near);
        }
        return Some(near - line.normal * (line.normal.dot(near - line.point) / n2));
    }
    let origin = lines.first()?.point;
    let (mut a11, mut a12, mut a22, mut b1, mut b2) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for l in lines {
        let n = l.normal;
        let c = n.dot(l.point - origin);
        a11 += n.x * n.x;
        a12 += n.x * n.y;
        a22 += n.y * n.y;
        b1 += n.x * c;
        b2 += n.y * c;
    }
    let det = a11 * a22 - a12 * a12;
    // Also refuses NaN.
    if det.abs().partial_cmp(&(SINGULAR * (a11 + a22).powi(2))) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let z = Vec2::new(a22 * b1 - a12 * b2, a11 * b2 - a12 * b1) / det;
    Some(origin + z)
}

/// Whether a link whose squared lengths at two poses differ by `residual` and sum to `sum_sq` keeps
/// its length to `tolerance`: `r² ≤ tol²·(L₁² + L₀²)` implies `|L₁ − L₀| ≤ tol`, since
/// `r = (L₁ − L₀)(L₁ + L₀)`, without a square root. False for NaN.
#[inline]
fn within(residual: f64, sum_sq: f64, tolerance: f64) -> bool {
    residual * residual <= tolerance * tolerance * sum_sq
}

/// [`project`] for one binary link through two or three poses (one or two equations), the
/// construction of nearly every sample: the same steps to the same point, up to rounding, without the
/// general elimination's loops and the zero columns of the absent third point: on the folding table
/// the construction takes a sixth of the run's instructions so, and a quarter with the general form
/// (`valgrind --tool=callgrind linkwright design examples/k1_table.json --threads 1
/// --no-print-check`, the scene's `"mechanism"` set to `"chain"`). Its 2×2 system is solved by
/// Cramer's rule: one division, where the elimination chains three that each wait for the last (5%
/// of the table's time: `perf record -e cpu-clock linkwright bench` on the same scene).
fn project_link(
    points: &mut [Point; 2],
    carriers: [Option<usize>; 2],
    motions: &[Vec<Rigid>],
    poses: usize,
    tolerance: f64,
) -> bool {
    assert!((2..=3).contains(&poses));
    let rows = poses - 1;
    let back = |c: Option<usize>, i: usize, d: Vec2| match c {
        Some(b) => motions[b][i].unrotate(d),
        None => d,
    };
    for _ in 0..12 {
        let [m, n] = *points;
        let d0 = m - n;
        // Residuals, and the link's vector at each pose.
        let mut r = [0.0; 2];
        let mut d = [Vec2::ZERO; 2];
        let mut converged = true;
        for i in 1..poses {
            d[i - 1] = carried(motions, carriers[0], i, m) - carried(motions, carriers[1], i, n);
            let (length_sq, first_sq) = (d[i - 1].norm_sq(), d0.norm_sq());
            r[i - 1] = length_sq - first_sq;
            converged &= within(r[i - 1], length_sq + first_sq, tolerance);
        }
        if converged {
            return true;
        }
        // The gradients, columns (m.x, m.y, n.x, n.y), only when a step follows (the last of the ~6
        // passes needs none).
        let mut jac = [[0.0; 4]; 2];
        for i in 1..poses {
            let d = d[i - 1];
            let (gm, gn) = ((back(carriers[0], i, d) - d0) * 2.0, (back(carriers[1], i, d) - d0) * -2.0);
            jac[i - 1] = [gm.x, gm.y, gn.x, gn.y];
        }
        let dot = |p: &[f64; 4], q: &[f64; 4]| p[0] * q[0] + p[1] * q[1] + p[2] * q[2] + p[3] * q[3];
        // Also true for NaN.
        let not_above = |v: f64, bound: f64| v.partial_cmp(&bound) != Some(std::cmp::Ordering::Greater);
        // (JJᵀ) y = r by Cramer's rule (one division), then δ = −Jᵀy.
        let y = if rows == 1 {
            let diag = dot(&jac[0], &jac[0]);
            if not_above(diag, 1e-300) {
                return false;
            }
            [r[0] / diag, 0.0]
        } else {
            let (a00, a01, a11) = (dot(&jac[0], &jac[0]), dot(&jac[0], &jac[1]), dot(&jac[1], &jac[1]));
            let det = a00 * a11 - a01 * a01;
            if not_above(det, 1e-300 * a00.max(a11)) {
                return false;
            }
            let inverse = 1.0 / det;
            [(r[0] * a11 - a01 * r[1]) * inverse, (a00 * r[1] - a01 * r[0]) * inverse]
        };
        for (k, point) in points.iter_mut().enumerate() {
            let step = Vec2::new(
                jac[0][2 * k] * y[0] + jac[1][2 * k] * y[1],
                jac[0][2 * k + 1] * y[0] + jac[1][2 * k + 1] * y[1],
            );
            *point = *point - step;
        }
        if !points.iter().all(|p| p.is_finite()) {
            return false;
        }
    }
    false
}

/// Moves `points` (carried by `carriers`) to a nearby exact solution of the link `pairs` (indices into
/// `points`) by minimum-norm Gauss–Newton steps `δ = −Jᵀ(JJᵀ)⁻¹r`: for fewer equations than unknowns
/// this converges, quadratically, to about the nearest point of the solution manifold, and stops once
/// every link keeps its length to `tolerance`. Returns false when it did not converge.
///
/// The arrays have room for `ROWS` equations (`COLS` = `ROWS` + 1: the matrix and the right side),
/// sized by each caller for its rows: a binary link through three poses has two, and zeroing and
/// eliminating six spent a fifth of its construction.
fn project<const K: usize, const ROWS: usize, const COLS: usize>(
    points: &mut [Point; K],
    carriers: &[Option<usize>; K],
    pairs: &[(usize, usize)],
    motions: &[Vec<Rigid>],
    poses: usize,
    tolerance: f64,
) -> bool {
    let rows = pairs.len() * (poses - 1);
    assert!(rows <= ROWS && COLS == ROWS + 1 && rows <= 2 * points.len());
    for _ in 0..12 {
        // Residuals and gradients (columns 2k, 2k+1 for point k).
        let mut r = [0.0; ROWS];
        let mut jac = [[0.0; 6]; ROWS];
        let mut row = 0;
        let mut converged = true;
        for &(m, n) in pairs {
            let d0 = points[m] - points[n];
            for i in 1..poses {
                let (mi, ni) =
                    (carried(motions, carriers[m], i, points[m]), carried(motions, carriers[n], i, points[n]));
                let d = mi - ni;
                let (length_sq, first_sq) = (d.norm_sq(), d0.norm_sq());
                r[row] = length_sq - first_sq;
                converged &= within(r[row], length_sq + first_sq, tolerance);
                let back = |c: Option<usize>| match c {
                    Some(b) => motions[b][i].unrotate(d),
                    None => d,
                };
                let (gm, gn) = ((back(carriers[m]) - d0) * 2.0, (back(carriers[n]) - d0) * -2.0);
                jac[row][2 * m] += gm.x;
                jac[row][2 * m + 1] += gm.y;
                jac[row][2 * n] += gn.x;
                jac[row][2 * n + 1] += gn.y;
                row += 1;
            }
        }
        if converged {
            return true;
        }
        // (JJᵀ) y = r by Gaussian elimination with partial pivoting, then δ = −Jᵀy.
        let mut a = [[0.0; COLS]; ROWS];
        for p in 0..rows {
            for q in 0..rows {
                a[p][q] = (0..6).map(|k| jac[p][k] * jac[q][k]).sum();
            }
            a[p][rows] = r[p];
        }
        for col in 0..rows {
            let pivot = (col..rows).max_by(|&p, &q| a[p][col].abs().total_cmp(&a[q][col].abs())).unwrap_or(col);
            a.swap(col, pivot);
            let diag = a[col][col];
            if diag.abs().partial_cmp(&1e-300) != Some(std::cmp::Ordering::Greater) {
                return false;
            }
            let pivot_row = a[col];
            for row in a.iter_mut().take(rows).skip(col + 1) {
                let f = row[col] / diag;
                for (v, &pv) in row.iter_mut().zip(&pivot_row).skip(col) {
                    *v -= f * pv;
                }
            }
        }
        let mut y = [0.0; ROWS];
        for p in (0..rows).rev() {
            let s: f64 = (p + 1..rows).map(|q| a[p][q] * y[q]).sum();
            y[p] = (a[p][rows] - s) / a[p][p];
        }
        for (k, point) in points.iter_mut().enumerate() {
            let step = Vec2::new(
                (0..rows).map(|p| jac[p][2 * k] * y[p]).sum(),
                (0..rows).map(|p| jac[p][2 * k + 1] * y[p]).sum(),
            );
            *point = *point - step;
        }
        if !points.iter().all(|p| p.is_finite()) {
            return false;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    /// The binary link's projection converges where the general one does, to an exact solution, in 99%
    /// of the cases the general one's point to 1e-9 of the scale (the two round differently, and
    /// near-singular systems magnify that), for links to the ground and between bodies, through two
    /// and three poses; both fail on broken motions, and on tolerances below rounding but where a
    /// residual happens to round under it.
    #[test]
    fn link_projection_is_the_general_projection() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
        let (mut converged, mut failed) = (0, 0);
        // Converged pairs, and those whose points agree to 1e-9 of the scale.
        let (mut both, mut together) = (0, 0);
        for case in 0..4000 {
            let poses = 2 + case % 2;
            let scale = 10f64.powf(rng.random_range(-2.0..3.0));
            let mut motion = || {
                let mut m = vec![Rigid::IDENTITY];
                m.extend((1..poses).map(|_| {
                    let shift = Vec2::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0)) * scale;
                    Rigid::new(rng.random_range(-3.0..3.0), shift)
                }));
                m
            };
            let mut motions = vec![motion(), motion()];
            if case % 50 == 7 {
                // A broken motion: no step is finite.
                motions[0][1] = Rigid::new(0.5, Vec2::new(f64::NAN, 0.0));
            }
            let carriers = [[None, Some(0)], [Some(0), None], [Some(0), Some(1)], [Some(1), Some(1)]][case % 4];
            let draw = |rng: &mut Xoshiro256PlusPlus| {
                Point::new(rng.random_range(-1.0..1.0) * scale, rng.random_range(-1.0..1.0) * scale)
            };
            let start = [draw(&mut rng), draw(&mut rng)];
            // A tolerance below the rounding of the lengths runs all twelve steps and fails.
            let tolerance = if case % 3 == 0 { scale * 1e-18 } else { scale * 1e-12 };
            let (mut general, mut link) = (start, start);
            let expected = project::<2, 2, 3>(&mut general, &carriers, &[(0, 1)], &motions, poses, tolerance);
            let verdict = project_link(&mut link, carriers, &motions, poses, tolerance);
            // Below rounding, a residual sometimes rounds under the tolerance in one and not the other.
            assert!(verdict == expected || case % 3 == 0, "case {case}: {verdict} against {expected}");
            if verdict {
                let length = |i: usize| {
                    carried(&motions, carriers[0], i, link[0]).distance(carried(&motions, carriers[1], i, link[1]))
                };
                // The lengths themselves round a little.
                let slack = 1e-15 * length(0);
                assert!((1..poses).all(|i| (length(i) - length(0)).abs() <= tolerance + slack), "case {case}");
            }
            if verdict && expected {
                both += 1;
                let apart = general.iter().zip(&link).map(|(g, l)| g.distance(*l)).fold(0.0, f64::max);
                together += (apart <= 1e-9 * scale) as usize;
            }
            if case % 50 == 7 && carriers.contains(&Some(0)) {
                assert!(!verdict && !expected, "case {case}: a broken motion converged");
            }
            if expected {
                converged += 1;
            } else {
                failed += 1;
            }
        }
        assert!(together * 100 >= 99 * both, "{together} of {both} converged pairs agree");
        // Both verdicts occur (a body's joint on itself never moves: no equation to satisfy).
        assert!(converged > 1000 && failed > 100, "{converged} converged, {failed} failed");
    }
}
