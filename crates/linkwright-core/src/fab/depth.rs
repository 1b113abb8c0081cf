//! Depth ordering (paper §7.2, eq. 16–19): record along the whole motion which member passes over
//! which connector post or joint pin, then give every member a layer (and a face of the bodies) with
//! the Pumpkin constraint solver, minimising the number of layers, or prove that none exists.
//!
//! Every printed member is the hull of discs of radius `w/2` around a convex core (its joints, and its
//! post for connectors), so "overlaps in projection" is exactly "the cores are closer than the sum of
//! the radii"; the test adds the radial clearance. The constraints recorded, for members `a`, `m` and
//! joint `j` with members `L_j`:
//! - [`Constraint::Distinct`] (eq. 18–19, over the whole motion rather than the first pose only): two
//!   members whose outlines overlap at some step lie on different layers;
//! - [`Constraint::Below`] (eq. 16): a member passing over the post of connector `c` lies above `c`;
//! - [`Constraint::Around`] (eq. 17): a member passing over the pin of joint `j` lies below every
//!   member of `L_j` or above every one; [`Constraint::Above`] when the pin stands on a body (nothing
//!   can pass under it);
//! - [`Constraint::Outermost`]: the slider guide (or the frame holding the slot) is the outermost member
//!   on its joint (the pin comes from the body side and runs in the slot);
//! - [`Constraint::OppositeFaces`]: two pillars (posts or pins standing on different bodies) that meet
//!   during the motion must stand on opposite faces of the bodies;
//! - [`Constraint::UnderHook`]: a member passing over a spring's hook lies below what the hook stands
//!   on (the springs hang beyond the outermost layer of their face, so the hook rises through every
//!   layer above its base), or on the other face;
//! - [`Constraint::SpringsApart`]: two springs whose coils meet during the motion hang on opposite faces
//!   or at different levels beyond the layers; [`Constraint::SpringOverHook`]: a spring passing over
//!   another's hook hangs on the other face or at a higher level.
//!
//! All members on one joint share a face, and so do both hooks of a spring and whatever they stand on.
//! The solver minimises the layers on the busier face.

use super::error::FabError;
use super::layout::{HookBase, Layout};
use super::settings::Faces;
use crate::geom::{point_segment_distance, Point, Rigid};
use crate::kinematics::Trace;
use pumpkin_conflict_resolvers::resolvers::ResolutionResolver;
use pumpkin_core::proof::ConstraintTag;
use pumpkin_core::results::{ProblemSolution, SatisfactionResult};
use pumpkin_core::termination::TerminationCondition;
use pumpkin_core::variables::{DomainId, Literal};
use pumpkin_core::Solver;
use serde::Serialize;
use std::collections::BTreeMap;

/// A pillar: something standing on a body's face up through the layers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PillarRef {
    /// The post of this connector (or guide) member.
    Post(usize),
    /// The pin of this joint, fused to a body or the ground.
    Pin(usize),
    /// This spring hook, standing on a body or the ground ([`HookBase::Body`]).
    Hook(usize),
}

/// One recorded ordering constraint (indices are members of the [`Layout`] and joints).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Constraint {
    /// `z(a) ≠ z(b)` when on the same face: the two members overlap somewhere along the motion (paper
    /// eq. 18–19).
    Distinct {
        /// One member.
        a: usize,
        /// The other member.
        b: usize,
    },
    /// `z(lower) < z(upper)` when on the same face: `upper` passes over the post of `lower` (eq. 16).
    Below {
        /// The member whose post is passed over.
        lower: usize,
        /// The member that passes over it.
        upper: usize,
    },
    /// `z(member) < min z(L_joint) ∨ z(member) > max z(L_joint)` when on the same face: `member` passes
    /// over the pin at `joint` (eq. 17).
    Around {
        /// The member that passes over the pin.
        member: usize,
        /// The joint whose pin it passes over.
        joint: usize,
    },
    /// `z(member) > max z(L_joint)` when on the same face: `member` passes over a pin standing on a body
    /// (nothing can pass under it).
    Above {
        /// The member that passes over the pin.
        member: usize,
        /// The joint whose pin it passes over.
        joint: usize,
    },
    /// `z(member) > z(l)` for every other `l` of `L_joint`: the slider guide (or the frame holding the
    /// slot) is the outermost member on its joint.
    Outermost {
        /// The member that must be outermost.
        member: usize,
        /// The joint it is outermost on.
        joint: usize,
    },
    /// The two pillars (posts or pins standing on different bodies) meet during the motion, so they
    /// stand on opposite faces.
    OppositeFaces {
        /// One pillar.
        a: PillarRef,
        /// The other pillar.
        b: PillarRef,
    },
    /// `member` passes over spring hook `hook`, so when on the hook's face it lies below what the hook
    /// stands on (below every member on the joint, for a hook on a joint's pin; nowhere, for a hook
    /// standing on a body).
    UnderHook {
        /// The member that passes over the hook.
        member: usize,
        /// The hook, an index into [`Layout::hooks`].
        hook: usize,
    },
    /// The coils of springs `a` and `b` meet along the motion, so on one face they hang at different
    /// levels.
    SpringsApart {
        /// One spring.
        a: usize,
        /// The other.
        b: usize,
    },
    /// Spring `spring` passes over `hook` of another spring, so on one face it hangs at a higher level.
    SpringOverHook {
        /// The spring that passes over.
        spring: usize,
        /// The hook, an index into [`Layout::hooks`].
        hook: usize,
    },
    /// Every member of `L_joint` is on one face (always imposed; never recorded, only reported broken).
    SameFace {
        /// The joint.
        joint: usize,
    },
}

/// The constraints of one motion, each with the first crank angle (degrees) where it was seen.
#[derive(Clone, Debug, Default)]
pub struct Recorded {
    /// Each constraint, with the first crank angle where it was seen, degrees.
    pub constraints: BTreeMap<Constraint, f64>,
}

/// A face of the bodies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Face {
    /// The face the bodies' outlines are drawn on (`z = 0`), facing the viewer.
    Front,
    /// The opposite face (`z = -body_thickness`).
    Back,
}

/// A depth ordering: every member's face and layer (1 = next to the bodies).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Ordering {
    /// Each member's face, indexed like [`Layout::members`].
    pub face: Vec<Face>,
    /// Each member's layer on its face (1 next to the bodies), indexed like [`Layout::members`].
    pub layer: Vec<u32>,
    /// The face each spring hangs on, beyond its outermost layer.
    pub spring_face: Vec<Face>,
    /// Each spring's level beyond the layers of its face (0 nearest), so that springs of one face
    /// pass over each other and over each other's hooks ([`Dims::spring_axis`](super::settings::Dims::spring_axis)).
    pub spring_level: Vec<u32>,
    /// The most layers on either face.
    pub layers: u32,
    /// True when the solver proved that fewer layers are impossible.
    pub optimal: bool,
}

/// Records every constraint along the motion `trace` (paper §7.2: a 2D kinematic simulation).
pub(crate) fn record(layout: &Layout, trace: &Trace) -> Recorded {
    let mut recording = Recording::new(layout);
    for r in 0..trace.len() {
        let row = trace.row(r);
        let deg = trace.thetas[r].to_degrees();
        recording.place(row);
        // Parts on one carrier keep their places: what they meet, they meet at the first row.
        let first_row = r == 0;
        for a in 0..layout.members.len() {
            recording.members_overlapping(a, first_row, deg);
            recording.pillars_passed_over(a, first_row, deg);
            recording.hooks_passed_over(a, first_row, deg);
            recording.pins_passed_over(a, row, deg);
        }
        recording.pillars_meeting(deg);
        recording.springs_meeting(deg);
    }
    let mut out = recording.out;
    if let Some(j) = layout.slider_joint {
        let slotted = |i: &usize| layout.members[*i].slot.is_some_and(|s| s.joint == j);
        if let Some(g) = layout.joint_members[j].iter().copied().find(slotted) {
            out.constraints
                .entry(Constraint::Outermost { member: g, joint: j })
                .or_insert(trace.thetas[0].to_degrees());
        }
    }
    out
}

/// What [`record`] carries from row to row: the pillars, where everything is at the current row
/// (world frame), and the constraints seen so far.
struct Recording<'a> {
    layout: &'a Layout,
    /// Every pillar (the posts, the pins fused to bodies, the hooks standing on bodies) with its
    /// carrier.
    pillars: Vec<(PillarRef, usize)>,
    /// Every carrier's pose.
    poses: Vec<Rigid>,
    /// Every member's core.
    cores: Vec<Vec<Point>>,
    /// Every member's core box, for a cheap test before the exact distance.
    boxes: Vec<(Point, Point)>,
    /// Where each pillar stands.
    pillar_at: Vec<Point>,
    /// Where each spring hook stands.
    hook_at: Vec<Point>,
    out: Recorded,
}

impl<'a> Recording<'a> {
    fn new(layout: &'a Layout) -> Recording<'a> {
        let members = &layout.members;
        let pillars: Vec<(PillarRef, usize)> = members
            .iter()
            .enumerate()
            .filter(|(_, x)| x.post.is_some())
            .map(|(i, x)| (PillarRef::Post(i), x.carrier))
            .chain(layout.body_pins.iter().enumerate().filter_map(|(j, p)| p.map(|p| (PillarRef::Pin(j), p.carrier))))
            .chain(
                layout
                    .hooks
                    .iter()
                    .enumerate()
                    .filter(|(_, h)| h.base == HookBase::Body)
                    .map(|(k, h)| (PillarRef::Hook(k), h.carrier)),
            )
            .collect();
        Recording {
            layout,
            poses: Vec::new(),
            cores: members.iter().map(|x| x.core.clone()).collect(),
            boxes: vec![(Point::ORIGIN, Point::ORIGIN); members.len()],
            pillar_at: vec![Point::ORIGIN; pillars.len()],
            hook_at: vec![Point::ORIGIN; layout.hooks.len()],
            pillars,
            out: Recorded::default(),
        }
    }

    /// The radius of a pillar's widest part.
    fn pillar_radius(&self, p: PillarRef) -> f64 {
        let d = &self.layout.dims;
        match p {
            PillarRef::Post(_) => d.post_collar_radius,
            PillarRef::Pin(_) => d.boss_radius,
            PillarRef::Hook(_) => d.cap_base_radius,
        }
    }

    /// Places every carrier, member core, pillar and hook in the configuration `row`.
    fn place(&mut self, row: &[Point]) {
        let layout = self.layout;
        layout.carrier_poses(row, &mut self.poses);
        for (i, x) in layout.members.iter().enumerate() {
            let pose = &self.poses[x.carrier];
            for (k, &c) in x.core.iter().enumerate() {
                self.cores[i][k] = pose.apply(c);
            }
            let (mut lo, mut hi) = (self.cores[i][0], self.cores[i][0]);
            for q in &self.cores[i] {
                lo = Point::new(lo.x.min(q.x), lo.y.min(q.y));
                hi = Point::new(hi.x.max(q.x), hi.y.max(q.y));
            }
            self.boxes[i] = (lo, hi);
        }
        for (k, &(p, carrier)) in self.pillars.iter().enumerate() {
            self.pillar_at[k] = match p {
                PillarRef::Post(i) => self.poses[carrier].apply(layout.members[i].post.unwrap_or_default()),
                PillarRef::Pin(j) => row[j],
                PillarRef::Hook(h) => self.poses[carrier].apply(layout.hooks[h].at),
            };
        }
        for (k, at) in self.hook_at.iter_mut().enumerate() {
            *at = layout.hook_at(k, row, &self.poses);
        }
    }

    /// [`Constraint::Distinct`]: the members after `a` whose outlines overlap it.
    fn members_overlapping(&mut self, a: usize, first_row: bool, deg: f64) {
        let (members, d) = (&self.layout.members, &self.layout.dims);
        let reach = 2.0 * d.half_width + d.clearance;
        for b in a + 1..members.len() {
            if !(first_row || members[a].carrier != members[b].carrier) {
                continue;
            }
            if box_gap(&self.boxes[a], &self.boxes[b]) < reach
                && super::shapes::core_distance(&self.cores[a], &self.cores[b]) < reach
            {
                self.out.note(Constraint::Distinct { a, b }, deg);
            }
        }
    }

    /// [`Constraint::Below`] and [`Constraint::Above`]: the posts and the pins fused to bodies that
    /// member `a` passes over.
    fn pillars_passed_over(&mut self, a: usize, first_row: bool, deg: f64) {
        let layout = self.layout;
        let d = &layout.dims;
        for (k, &(p, carrier)) in self.pillars.iter().enumerate() {
            if !(first_row || layout.members[a].carrier != carrier) {
                continue;
            }
            let reach = d.half_width + self.pillar_radius(p) + d.clearance;
            let at = self.pillar_at[k];
            if box_gap(&self.boxes[a], &(at, at)) >= reach {
                continue;
            }
            let over = || super::shapes::point_core_distance(at, &self.cores[a]) < reach;
            match p {
                PillarRef::Post(c) if c != a && over() => {
                    self.out.note(Constraint::Below { lower: c, upper: a }, deg);
                }
                PillarRef::Pin(j) if !layout.joint_members[j].contains(&a) && over() => {
                    self.out.note(Constraint::Above { member: a, joint: j }, deg);
                }
                _ => {}
            }
        }
    }

    /// [`Constraint::UnderHook`]: the spring hooks member `a` passes over (other than its own).
    fn hooks_passed_over(&mut self, a: usize, first_row: bool, deg: f64) {
        let layout = self.layout;
        let d = &layout.dims;
        let hook_reach = d.half_width + d.cap_base_radius + d.clearance;
        for (k, hook) in layout.hooks.iter().enumerate() {
            let own = match hook.base {
                HookBase::Member(i) => i == a,
                HookBase::Joint(j) => layout.joint_members[j].contains(&a),
                HookBase::Body => false,
            };
            let at = self.hook_at[k];
            if own
                || !(first_row || layout.members[a].carrier != hook.carrier)
                || box_gap(&self.boxes[a], &(at, at)) >= hook_reach
            {
                continue;
            }
            if super::shapes::point_core_distance(at, &self.cores[a]) < hook_reach {
                self.out.note(Constraint::UnderHook { member: a, hook: k }, deg);
            }
        }
    }

    /// [`Constraint::Around`]: the pins carried by members (not fused to a body) that member `a`
    /// passes over, the joints in the configuration `row`.
    fn pins_passed_over(&mut self, a: usize, row: &[Point], deg: f64) {
        let layout = self.layout;
        let d = &layout.dims;
        for (j, lj) in layout.joint_members.iter().enumerate() {
            if layout.body_pins[j].is_some() || lj.contains(&a) || lj.is_empty() {
                continue;
            }
            let reach = d.half_width + d.boss_radius + d.clearance;
            if box_gap(&self.boxes[a], &(row[j], row[j])) < reach
                && super::shapes::point_core_distance(row[j], &self.cores[a]) < reach
            {
                self.out.note(Constraint::Around { member: a, joint: j }, deg);
            }
        }
    }

    /// [`Constraint::OppositeFaces`]: pillars on different carriers that meet.
    fn pillars_meeting(&mut self, deg: f64) {
        let margin = self.layout.dims.clearance;
        for k in 0..self.pillars.len() {
            for l in k + 1..self.pillars.len() {
                let (pk, ck) = self.pillars[k];
                let (pl, cl) = self.pillars[l];
                if ck == cl {
                    continue;
                }
                if self.pillar_at[k].distance(self.pillar_at[l])
                    < self.pillar_radius(pk) + self.pillar_radius(pl) + margin
                {
                    self.out.note(Constraint::OppositeFaces { a: pk, b: pl }, deg);
                }
            }
        }
    }

    /// [`Constraint::SpringsApart`] and [`Constraint::SpringOverHook`]: springs whose coils meet, and
    /// springs passing over another's hook. Spring s hangs between hooks 2s and 2s + 1.
    fn springs_meeting(&mut self, deg: f64) {
        let layout = self.layout;
        let d = &layout.dims;
        // A spring's coil meets what comes within its radius and the clearance of its axis.
        let coil_reach = d.spring_radius() + d.clearance;
        let springs = layout.spring_count();
        let hook_at = &self.hook_at;
        let ends = |s: usize| [hook_at[2 * s], hook_at[2 * s + 1]];
        for a in 0..springs {
            for b in a + 1..springs {
                if super::shapes::core_distance(&ends(a), &ends(b)) < coil_reach + d.spring_radius() {
                    self.out.note(Constraint::SpringsApart { a, b }, deg);
                }
            }
            for k in (0..layout.hooks.len()).filter(|&k| layout.hooks[k].spring != a) {
                let [p, q] = ends(a);
                if point_segment_distance(hook_at[k], p, q) < coil_reach + d.cap_base_radius {
                    self.out.note(Constraint::SpringOverHook { spring: a, hook: k }, deg);
                }
            }
        }
    }
}

/// The distance between two boxes (`(min, max)` corners), 0 when they overlap.
fn box_gap(a: &(Point, Point), b: &(Point, Point)) -> f64 {
    let dx = (a.0.x - b.1.x).max(b.0.x - a.1.x).max(0.0);
    let dy = (a.0.y - b.1.y).max(b.0.y - a.1.y).max(0.0);
    dx.hypot(dy)
}

impl Recorded {
    /// Notes constraint `c`, seen at crank angle `deg` unless it was seen earlier.
    fn note(&mut self, c: Constraint, deg: f64) {
        self.constraints.entry(c).or_insert(deg);
    }
}

/// Why no ordering was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum NoOrdering {
    /// Proven: no ordering exists with the faces allowed.
    Infeasible,
    /// The solver used its whole step budget without an answer.
    TimedOut,
}

/// The solver's budget for [`feasible`], in solver steps (one propagation and decision, or one
/// conflict). Counted in steps rather than seconds so that whether a candidate passes the print check
/// does not depend on the machine's load, and the same scene and seed give the same design. The budget
/// is several times what any candidate of the bundled examples and the reference scenes needs, and
/// small enough that a candidate which uses it all costs at most a fraction of a second.
pub(crate) const FEASIBILITY_STEPS: u64 = 2_000;

/// The solver's budget for [`solve`] when fabricating, in solver steps: the layer count is minimised
/// there and a design is fabricated once, so it may take seconds.
pub(crate) const FABRICATION_STEPS: u64 = 200_000;

/// Solves the ordering, minimising the layers: the smallest layer count is found by asking the
/// solver for each count from a lower bound upwards, so the first satisfiable count is proven optimal.
/// With [`Faces::Auto`], one face is tried first and both faces only when one face has no ordering.
/// `steps` bounds the solver's steps over all of these questions together.
pub(crate) fn solve(layout: &Layout, recorded: &Recorded, faces: Faces, steps: u64) -> Result<Ordering, NoOrdering> {
    let m = layout.members.len();
    if m == 0 {
        // Nothing to hang beyond: each spring on the front face, one level each.
        let springs = layout.spring_count();
        let (spring_face, spring_level) = (vec![Face::Front; springs], (0..springs as u32).collect());
        return Ok(Ordering { face: vec![], layer: vec![], spring_face, spring_level, layers: 0, optimal: true });
    }
    let mut budget = StepBudget { left: steps };
    let lower = layout.joint_members.iter().map(Vec::len).max().unwrap_or(1).max(1) as i32;
    let attempts: &[bool] = match faces {
        Faces::One => &[false],
        Faces::Both => &[true],
        Faces::Auto => &[false, true],
    };
    let mut timed_out = false;
    for &two in attempts {
        // Feasibility first (with as many layers as members, which any ordering can be compressed to).
        match solve_with(layout, recorded, two, m as i32, &mut budget) {
            Outcome::Unsat => continue,
            Outcome::Unknown => {
                timed_out = true;
                continue;
            }
            Outcome::Sat(mut best) => {
                let mut optimal = true;
                for upper in lower..best.layers as i32 {
                    match solve_with(layout, recorded, two, upper, &mut budget) {
                        Outcome::Sat(o) => {
                            best = o;
                            break;
                        }
                        Outcome::Unsat => {}
                        Outcome::Unknown => {
                            optimal = false;
                            break;
                        }
                    }
                }
                best.optimal = optimal;
                return Ok(best);
            }
        }
    }
    Err(if timed_out { NoOrdering::TimedOut } else { NoOrdering::Infeasible })
}

/// Whether any ordering exists with the faces allowed (no minimisation).
pub(crate) fn feasible(layout: &Layout, recorded: &Recorded, faces: Faces, steps: u64) -> bool {
    let m = layout.members.len() as i32;
    let attempts: &[bool] = match faces {
        Faces::One => &[false],
        Faces::Both | Faces::Auto => &[true],
    };
    let mut budget = StepBudget { left: steps };
    attempts.iter().any(|&two| matches!(solve_with(layout, recorded, two, m.max(1), &mut budget), Outcome::Sat(_)))
}

enum Outcome {
    Sat(Ordering),
    Unsat,
    Unknown,
}

/// One satisfaction problem: every member on a layer in `1..=upper`, on one face or (with `two`) on
/// either face.
fn solve_with(layout: &Layout, recorded: &Recorded, two: bool, upper: i32, budget: &mut StepBudget) -> Outcome {
    let mut model = Model::new(layout, two, upper);
    for &c in recorded.constraints.keys() {
        if model.impose(c).is_err() {
            return Outcome::Unsat;
        }
    }
    model.satisfy(budget)
}

/// Stops the solver after a number of its steps, shared by the questions of one [`solve`].
struct StepBudget {
    left: u64,
}

impl TerminationCondition for StepBudget {
    fn should_stop(&mut self) -> bool {
        // Polled once per step of the solver's search loop.
        match self.left.checked_sub(1) {
            Some(left) => {
                self.left = left;
                false
            }
            None => true,
        }
    }
}

/// A satisfaction problem being built: a layer and a face for every member, a face and a level
/// beyond the layers for every spring.
struct Model<'a> {
    layout: &'a Layout,
    solver: Solver,
    tag: ConstraintTag,
    /// Whether the members may be on either face (otherwise all are on the front).
    two: bool,
    /// Each member's layer.
    z: Vec<DomainId>,
    /// Each member's face: true on the front.
    front: Vec<Literal>,
    /// A literal that always holds.
    truth: Literal,
    /// The literals "members a and b are on the same face" made so far, by `(min, max)`.
    same_cache: BTreeMap<(usize, usize), Literal>,
    /// Each spring's face: true on the front.
    spring_front: Vec<Literal>,
    /// Each spring's level beyond the layers of its face.
    level: Vec<DomainId>,
}

impl<'a> Model<'a> {
    /// Every member on a layer in `1..=upper` and a face (the front unless `two`), the members of a
    /// joint on one face, and each spring on the face of what its hooks stand on.
    fn new(layout: &'a Layout, two: bool, upper: i32) -> Model<'a> {
        let m = layout.members.len();
        let mut solver = Solver::default();
        let tag = solver.new_constraint_tag();
        let z: Vec<DomainId> = (0..m).map(|_| solver.new_bounded_integer(1, upper)).collect();
        let front: Vec<Literal> = (0..m).map(|_| solver.new_literal()).collect();
        let t = |l: Literal| l.get_true_predicate();
        let f = |l: Literal| l.get_false_predicate();
        let truth = solver.get_true_literal();
        if two {
            // Symmetry: the first member is on the front.
            solver.add_clause([t(front[0])], tag);
        } else {
            for &s in &front {
                solver.add_clause([t(s)], tag);
            }
        }
        // Members on one joint share a face.
        for lj in &layout.joint_members {
            for w in lj.windows(2) {
                let (a, b) = (front[w[0]], front[w[1]]);
                solver.add_clause([f(a), t(b)], tag);
                solver.add_clause([t(a), f(b)], tag);
            }
        }
        // Each spring's face, shared with whatever its hooks stand on.
        let springs = layout.spring_count();
        let spring_front: Vec<Literal> = (0..springs).map(|_| if two { solver.new_literal() } else { truth }).collect();
        let level: Vec<DomainId> = (0..springs).map(|_| solver.new_bounded_integer(0, springs as i32 - 1)).collect();
        for hook in &layout.hooks {
            let base = match hook.base {
                HookBase::Member(i) => Some(i),
                HookBase::Joint(j) => layout.joint_members[j].first().copied(),
                HookBase::Body => None,
            };
            if let (Some(i), true) = (base, two) {
                let (a, b) = (spring_front[hook.spring], front[i]);
                solver.add_clause([f(a), t(b)], tag);
                solver.add_clause([t(a), f(b)], tag);
            }
        }
        Model { layout, solver, tag, two, z, front, truth, same_cache: BTreeMap::new(), spring_front, level }
    }

    /// A literal true exactly when members `a` and `b` are on the same face (made once per pair).
    fn same(&mut self, a: usize, b: usize) -> Literal {
        if !self.two {
            return self.truth;
        }
        let key = (a.min(b), a.max(b));
        if let Some(&l) = self.same_cache.get(&key) {
            return l;
        }
        let e = equal_literal(&mut self.solver, self.front[a], self.front[b], self.tag);
        self.same_cache.insert(key, e);
        e
    }

    /// A literal true exactly when springs `a` and `b` hang on the same face.
    fn spring_same(&mut self, a: usize, b: usize) -> Literal {
        if self.two {
            equal_literal(&mut self.solver, self.spring_front[a], self.spring_front[b], self.tag)
        } else {
            self.truth
        }
    }

    /// The face of what a pillar stands on (none for a pin on a joint no member carries).
    fn pillar_face(&self, p: PillarRef) -> Option<Literal> {
        match p {
            PillarRef::Post(i) => Some(self.front[i]),
            PillarRef::Pin(j) => self.layout.joint_members[j].first().map(|&i| self.front[i]),
            PillarRef::Hook(k) => Some(self.spring_front[self.layout.hooks[k].spring]),
        }
    }

    /// Adds recorded constraint `c` to the problem; [`NoOrdering::Infeasible`] when it alone makes the
    /// problem unsatisfiable with the faces allowed.
    fn impose(&mut self, c: Constraint) -> Result<(), NoOrdering> {
        let (layout, tag) = (self.layout, self.tag);
        let (t, f) = (|l: Literal| l.get_true_predicate(), |l: Literal| l.get_false_predicate());
        match c {
            Constraint::Distinct { a, b } => {
                let e = self.same(a, b);
                let z = &self.z;
                self.solver.add_constraint(pumpkin_constraints::binary_not_equals(z[a], z[b], tag)).implied_by(e);
            }
            Constraint::Below { lower, upper } => {
                let e = self.same(lower, upper);
                let z = &self.z;
                self.solver
                    .add_constraint(pumpkin_constraints::binary_less_than(z[lower], z[upper], tag))
                    .implied_by(e);
            }
            Constraint::Above { member, joint } | Constraint::Outermost { member, joint } => {
                let Some(&first) = layout.joint_members[joint].first() else { return Ok(()) };
                let e = self.same(member, first);
                let z = &self.z;
                for &l in layout.joint_members[joint].iter().filter(|&&l| l != member) {
                    self.solver
                        .add_constraint(pumpkin_constraints::binary_less_than(z[l], z[member], tag))
                        .implied_by(e);
                }
            }
            Constraint::Around { member, joint } => {
                let Some(&first) = layout.joint_members[joint].first() else { return Ok(()) };
                let e = self.same(member, first);
                let z = &self.z;
                let solver = &mut self.solver;
                let below = solver.new_literal();
                let above = solver.new_literal();
                solver.add_clause([f(e), t(below), t(above)], tag);
                for &l in &layout.joint_members[joint] {
                    solver
                        .add_constraint(pumpkin_constraints::binary_less_than(z[member], z[l], tag))
                        .implied_by(below);
                    solver
                        .add_constraint(pumpkin_constraints::binary_less_than(z[l], z[member], tag))
                        .implied_by(above);
                }
            }
            Constraint::UnderHook { member, hook } => {
                let on = self.spring_front[layout.hooks[hook].spring];
                let below: Vec<usize> = match layout.hooks[hook].base {
                    HookBase::Member(i) => vec![i],
                    HookBase::Joint(j) => layout.joint_members[j].clone(),
                    HookBase::Body => {
                        // Nothing can pass over a hook standing on a body: the member is on the other face.
                        if !self.two {
                            return Err(NoOrdering::Infeasible);
                        }
                        self.solver.add_clause([f(on), f(self.front[member])], tag);
                        self.solver.add_clause([t(on), t(self.front[member])], tag);
                        return Ok(());
                    }
                };
                let Some(&first) = below.first() else { return Ok(()) };
                let e = self.same(member, first);
                let z = &self.z;
                for l in below {
                    self.solver
                        .add_constraint(pumpkin_constraints::binary_less_than(z[member], z[l], tag))
                        .implied_by(e);
                }
            }
            Constraint::SpringsApart { a, b } => {
                let e = self.spring_same(a, b);
                let level = &self.level;
                self.solver
                    .add_constraint(pumpkin_constraints::binary_not_equals(level[a], level[b], tag))
                    .implied_by(e);
            }
            Constraint::SpringOverHook { spring, hook } => {
                let other = layout.hooks[hook].spring;
                let e = self.spring_same(spring, other);
                let level = &self.level;
                self.solver
                    .add_constraint(pumpkin_constraints::binary_less_than(level[other], level[spring], tag))
                    .implied_by(e);
            }
            // Imposed for every joint by `Model::new`.
            Constraint::SameFace { .. } => {}
            Constraint::OppositeFaces { a, b } => {
                let (Some(fa), Some(fb)) = (self.pillar_face(a), self.pillar_face(b)) else { return Ok(()) };
                if !self.two {
                    return Err(NoOrdering::Infeasible);
                }
                self.solver.add_clause([t(fa), t(fb)], tag);
                self.solver.add_clause([f(fa), f(fb)], tag);
            }
        }
        Ok(())
    }

    /// Asks the solver, within the steps left in `budget`, for every member's layer and face and
    /// every spring's face and level.
    fn satisfy(mut self, budget: &mut StepBudget) -> Outcome {
        let mut brancher = self.solver.default_brancher();
        let mut resolver = ResolutionResolver::default();
        let result = self.solver.satisfy(&mut brancher, budget, &mut resolver);
        match result {
            SatisfactionResult::Satisfiable(s) => {
                let sol = s.solution();
                let layer: Vec<u32> = self.z.iter().map(|&v| sol.get_integer_value(v).max(1) as u32).collect();
                let face: Vec<Face> = self
                    .front
                    .iter()
                    .map(|&l| if sol.get_literal_value(l) { Face::Front } else { Face::Back })
                    .collect();
                let (layer, layers) = compress(&layer, &face);
                let spring_face = self
                    .spring_front
                    .iter()
                    .map(|&l| if sol.get_literal_value(l) { Face::Front } else { Face::Back })
                    .collect();
                let spring_level = self.level.iter().map(|&v| sol.get_integer_value(v).max(0) as u32).collect();
                Outcome::Sat(Ordering { face, layer, spring_face, spring_level, layers, optimal: false })
            }
            SatisfactionResult::Unsatisfiable(..) => Outcome::Unsat,
            SatisfactionResult::Unknown(..) => Outcome::Unknown,
        }
    }
}

/// A new literal true exactly when `a` and `b` are equal (two faces' literals: the same face).
fn equal_literal(solver: &mut Solver, a: Literal, b: Literal, tag: ConstraintTag) -> Literal {
    let (t, f) = (|l: Literal| l.get_true_predicate(), |l: Literal| l.get_false_predicate());
    let e = solver.new_literal();
    solver.add_clause([t(e), t(a), t(b)], tag);
    solver.add_clause([t(e), f(a), f(b)], tag);
    solver.add_clause([f(e), f(a), t(b)], tag);
    solver.add_clause([f(e), t(a), f(b)], tag);
    e
}

/// Renumbers the layers of each face to 1, 2, ... keeping their order (the constraints only compare
/// layers, so this keeps every one of them), and returns the most layers on a face.
fn compress(layer: &[u32], face: &[Face]) -> (Vec<u32>, u32) {
    let mut out = layer.to_vec();
    let mut most = 0;
    for side in [Face::Front, Face::Back] {
        let mut used: Vec<u32> = (0..layer.len()).filter(|&i| face[i] == side).map(|i| layer[i]).collect();
        used.sort_unstable();
        used.dedup();
        for i in (0..layer.len()).filter(|&i| face[i] == side) {
            out[i] = used.binary_search(&layer[i]).map_or(layer[i], |k| k as u32 + 1);
        }
        most = most.max(used.len() as u32);
    }
    (out, most)
}

/// Which recorded constraints an ordering breaks (empty when it satisfies them all).
pub fn violations(layout: &Layout, recorded: &Recorded, o: &Ordering) -> Vec<Constraint> {
    let z = |i: usize| o.layer[i];
    let same = |a: usize, b: usize| o.face[a] == o.face[b];
    let lj = |j: usize| &layout.joint_members[j];
    let mut out = Vec::new();
    for (joint, l) in layout.joint_members.iter().enumerate() {
        if l.windows(2).any(|w| !same(w[0], w[1])) {
            out.push(Constraint::SameFace { joint });
        }
    }
    for &c in recorded.constraints.keys() {
        let ok = match c {
            Constraint::Distinct { a, b } => !same(a, b) || z(a) != z(b),
            Constraint::Below { lower, upper } => !same(lower, upper) || z(lower) < z(upper),
            Constraint::Above { member, joint } | Constraint::Outermost { member, joint } => {
                lj(joint).iter().all(|&l| l == member || !same(l, member) || z(l) < z(member))
            }
            Constraint::Around { member, joint } => {
                let l = lj(joint);
                l.is_empty()
                    || !same(l[0], member)
                    || l.iter().all(|&x| z(member) < z(x))
                    || l.iter().all(|&x| z(member) > z(x))
            }
            Constraint::OppositeFaces { a, b } => {
                let face = |p: PillarRef| match p {
                    PillarRef::Post(i) => Some(o.face[i]),
                    PillarRef::Pin(j) => lj(j).first().map(|&i| o.face[i]),
                    PillarRef::Hook(k) => o.spring_face.get(layout.hooks[k].spring).copied(),
                };
                face(a) != face(b) || face(a).is_none()
            }
            Constraint::UnderHook { member, hook } => {
                let h = &layout.hooks[hook];
                let on = o.spring_face.get(h.spring).copied();
                on != Some(o.face[member])
                    || match h.base {
                        HookBase::Member(i) => z(member) < z(i),
                        HookBase::Joint(j) => lj(j).iter().all(|&l| z(member) < z(l)),
                        HookBase::Body => false,
                    }
            }
            Constraint::SpringsApart { a, b } => {
                o.spring_face.get(a) != o.spring_face.get(b) || o.spring_level.get(a) != o.spring_level.get(b)
            }
            Constraint::SpringOverHook { spring, hook } => {
                let other = layout.hooks[hook].spring;
                o.spring_face.get(spring) != o.spring_face.get(other)
                    || o.spring_level.get(other) < o.spring_level.get(spring)
            }
            Constraint::SameFace { joint } => lj(joint).windows(2).all(|w| same(w[0], w[1])),
        };
        if !ok {
            out.push(c);
        }
    }
    out
}

impl Ordering {
    /// The most layers of any member on `face` (0 when none is there).
    pub fn layers_on(&self, face: Face) -> u32 {
        self.face.iter().zip(&self.layer).filter(|(f, _)| **f == face).map(|(_, &l)| l).max().unwrap_or(0)
    }
}

impl From<NoOrdering> for FabError {
    fn from(e: NoOrdering) -> FabError {
        match e {
            NoOrdering::Infeasible => FabError::NoOrdering,
            NoOrdering::TimedOut => FabError::OrderingTimedOut,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fab::posts::SceneShapes;
    use crate::fab::settings::{Dims, PrintSettings};
    use crate::statics::tests::parallelogram;

    /// Whether an ordering is found depends on the solver's steps alone, never on the clock: the
    /// smallest budget that finds one finds the same one every time, and one step fewer never does.
    #[test]
    fn the_ordering_depends_on_the_step_budget_not_on_time() {
        let (problem, mechanism, _, trace) = parallelogram();
        let shapes = SceneShapes::new(&problem, Dims::new(&PrintSettings::default(), 1.0));
        let layout = Layout::new(&shapes, &mechanism, &trace, true, &[]).unwrap();
        let recorded = record(&layout, &trace);
        assert!(layout.members.len() >= 3, "the links, and a connector for each body");
        assert_eq!(solve(&layout, &recorded, Faces::One, 0), Err(NoOrdering::TimedOut));
        let enough = (1..FEASIBILITY_STEPS).find(|&n| solve(&layout, &recorded, Faces::One, n).is_ok()).unwrap();
        let first = solve(&layout, &recorded, Faces::One, enough).unwrap();
        for _ in 0..10 {
            assert_eq!(solve(&layout, &recorded, Faces::One, enough).as_ref(), Ok(&first));
            assert_eq!(solve(&layout, &recorded, Faces::One, enough - 1), Err(NoOrdering::TimedOut));
        }
        assert!(violations(&layout, &recorded, &first).is_empty());
        assert!(feasible(&layout, &recorded, Faces::One, FEASIBILITY_STEPS));
    }
}
