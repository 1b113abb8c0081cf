//! Validation of a design file against its scene, before anything simulates, draws or fabricates it.
//!
//! A design file is input like a scene: a person may edit it, and a server receives it from anyone. So
//! [`DesignFile::validate`] checks everything the later stages take for granted, names the field of
//! every problem and says what to change, and never stops at the first problem. It runs in time and
//! memory bounded by the file's size: the crank's travel is bounded before any motion is simulated, and
//! the motion it simulates (to catch a linkage that cannot move) has at most one row per degree.

use super::file::{DesignFile, MechanismJson, Metrics, Motion, PartJson, PartKindJson, Status, DESIGN_FORMAT};
use crate::geom::{Point, Vec2};
use crate::issues::IssueList;
use crate::kinematics::Plan;
use crate::mechanism::{Mechanism, MechanismType, PartKind};
use crate::scene::Problem;
use std::collections::BTreeMap;

/// One problem of a design file.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct DesignIssue {
    /// The field, as a path: `mechanism.parts[2].joints[0]`, `alternatives[1].motion.crank_end_deg`.
    pub field: String,
    /// What is wrong and what to change.
    pub message: String,
}

impl std::fmt::Display for DesignIssue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.field, self.message)
    }
}

/// Largest coordinate accepted: ten times the scenes' bound (a linkage may reach beyond the drawing,
/// never this far), which keeps every product (areas, squared lengths) far from overflow.
pub(crate) const MAX_COORDINATE: f64 = 10.0 * crate::scene::limits::MAX_COORDINATE;
/// The crank's travel from the first pose to the last is less than this, degrees (exactly this for a
/// closed path, traced once per turn). A one-degree-of-freedom linkage driven by a crank is back in
/// the same configuration after a full turn, so every motion through poses in order fits within one
/// turn; more could only repeat configurations. It also bounds what a travel costs to simulate: at
/// the fabrication's 1° steps, at most 361 rows.
pub(crate) const MAX_TRAVEL_DEG: f64 = 360.0;
/// Largest crank angle accepted, degrees. The engine writes the start as the crank's direction in
/// (−180°, 180°] and a travel under a turn, so every angle it writes is within ±540°.
pub(crate) const MAX_CRANK_DEG: f64 = 720.0;
/// Most joints and parts of one mechanism. The engine's chain for K bodies has 3K + 1 joints and 2K + 2
/// parts; a scene with dozens of moving bodies is already far past anything drawable.
pub(crate) const MAX_JOINTS: usize = 256;
pub(crate) const MAX_PARTS: usize = 256;
/// Most alternatives in one file (the engine writes at most 10); each
/// is simulated when the file is validated.
pub(crate) const MAX_ALTERNATIVES: usize = 100;
/// Part lengths may drift along the simulated motion by this fraction of the linkage's size before
/// the part counts as deformed (the solver's rounding over 360 steps is some 10⁻¹² of it).
const RIGIDITY_TOLERANCE: f64 = 1e-6;

impl DesignFile {
    /// Every problem that makes this design unusable with `problem` (empty when there is none; the
    /// first [`MAX_LISTED_ISSUES`](crate::MAX_LISTED_ISSUES) listed, the rest counted): the
    /// format version, the status and what it requires, then for the design and each alternative
    /// the mechanism (names, joint references, coordinates, one ground, one part per moving body of
    /// the scene, a driver on the ground, the slider of a slider-crank), a linkage with exactly one
    /// degree of freedom that keeps every part rigid along its motion, a bounded crank travel with one
    /// angle per pose of the scene, and finite metrics.
    ///
    /// This is what every reader of a design runs first; [`DesignFile::violations`] (the constraints
    /// against the scene) assumes it passed.
    pub fn validate(&self, problem: &Problem) -> IssueList<DesignIssue> {
        let mut out = Issues::default();
        if self.linkwright != DESIGN_FORMAT {
            // The rest of a file of another version may mean other things: nothing more is checked.
            out.add(
                "linkwright",
                format!("unknown format \"{}\"; this version reads \"{DESIGN_FORMAT}\"", self.linkwright),
            );
            return out.0;
        }
        // A design with status "ok" has all three; one with "no_solution" none of them.
        let solved = self.status == Status::Ok;
        for (name, present) in [
            ("mechanism", self.mechanism.is_some()),
            ("motion", self.motion.is_some()),
            ("metrics", self.metrics.is_some()),
        ] {
            match (solved, present) {
                (true, false) => {
                    out.add(name, "is missing; a design with status \"ok\" has a mechanism, its motion and metrics")
                }
                (false, true) => {
                    out.add(name, "a design with status \"no_solution\" has none; set status to \"ok\" or remove it")
                }
                _ => {}
            }
        }
        if let (Some(m), Some(motion), Some(metrics)) = (&self.mechanism, &self.motion, &self.metrics) {
            check_entry(&mut out, "", problem, m, motion, metrics);
        }
        if self.alternatives.len() > MAX_ALTERNATIVES {
            out.add(
                "alternatives",
                format!(
                    "has {} designs; at most {MAX_ALTERNATIVES} are read, remove the others",
                    self.alternatives.len()
                ),
            );
        } else {
            for (i, a) in self.alternatives.iter().enumerate() {
                check_entry(&mut out, &format!("alternatives[{i}]."), problem, &a.mechanism, &a.motion, &a.metrics);
            }
        }
        out.0
    }

    /// The mechanisms of this design (its own and its alternatives') that are sound on their own,
    /// whatever the scene: what a new search may start from. The rest are left out.
    pub fn usable_mechanisms(&self) -> Vec<Mechanism> {
        let all = self.mechanism.iter().chain(self.alternatives.iter().map(|a| &a.mechanism));
        all.take(1 + MAX_ALTERNATIVES)
            .filter_map(|m| {
                let mut out = Issues::default();
                check_mechanism(&mut out, "mechanism", None, m).filter(|_| out.0.is_empty())
            })
            .collect()
    }
}

/// The problems found so far.
#[derive(Default)]
struct Issues(IssueList<DesignIssue>);

impl Issues {
    fn add(&mut self, field: impl Into<String>, message: impl Into<String>) {
        self.0.push_with(|| DesignIssue { field: field.into(), message: message.into() });
    }

    /// A name used as a label and in file names: the scenes' rule ([`crate::scene::name_problems`]).
    fn name(&mut self, field: &str, what: &str, name: &str) {
        for message in crate::scene::name_problems(what, name) {
            self.add(field, message);
        }
    }

    /// A coordinate pair within [`MAX_COORDINATE`].
    fn point(&mut self, field: &str, p: Point) -> bool {
        let ok = p.is_finite() && p.x.abs().max(p.y.abs()) <= MAX_COORDINATE;
        if !ok {
            self.add(field, format!("[{}, {}] must be two finite numbers within ±{MAX_COORDINATE:e}", p.x, p.y));
        }
        ok
    }
}

/// Checks one mechanism with its motion and metrics (`prefix` is `""` or `alternatives[i].`).
fn check_entry(
    out: &mut Issues,
    prefix: &str,
    problem: &Problem,
    m: &MechanismJson,
    motion: &Motion,
    metrics: &Metrics,
) {
    let before = out.0.total();
    let mechanism = check_mechanism(out, &format!("{prefix}mechanism"), Some(problem), m);
    let travel = check_motion(out, &format!("{prefix}motion"), problem, motion);
    check_metrics(out, &format!("{prefix}metrics"), metrics);
    if let (Some(mechanism), Some((start, end)), true) = (mechanism, travel, out.0.total() == before) {
        check_rigid_motion(out, &format!("{prefix}mechanism"), &mechanism, start, end);
    }
}

/// Checks a mechanism's parts and joints; returns it when it is sound enough to simulate.
/// `problem` is the scene it must match (its number of moving bodies), when there is one.
fn check_mechanism(out: &mut Issues, at: &str, problem: Option<&Problem>, m: &MechanismJson) -> Option<Mechanism> {
    let before = out.0.total();
    if !check_sizes(out, at, m) {
        return None;
    }
    for (name, &p) in &m.joints {
        let f = format!("{at}.joints[{name:?}]");
        out.name(&f, "joint", name);
        out.point(&f, p);
    }
    let joints = JointIndex::new(at, m);
    let parts = check_parts(out, at, problem.map(Problem::body_count), m, &joints);
    check_driver(out, at, m, &joints, &parts.fixed);
    check_slider(out, at, m, &joints);
    if out.0.total() > before || !check_mobility(out, at, m, &parts.carriers) {
        return None;
    }
    let mechanism = match m.to_mechanism() {
        Ok(mechanism) => mechanism,
        Err(e) => {
            out.add(at, e.to_string());
            return None;
        }
    };
    if let Err(e) = Plan::compile(&mechanism) {
        out.add(at, format!("the linkage cannot be simulated: {e}"));
        return None;
    }
    Some(mechanism)
}

/// Whether the numbers of joints and parts are within bounds; nothing else is read when they are not.
fn check_sizes(out: &mut Issues, at: &str, m: &MechanismJson) -> bool {
    let joint_count = m.joints.len();
    if joint_count == 0 || joint_count > MAX_JOINTS {
        out.add(format!("{at}.joints"), format!("has {joint_count} joints; a linkage has from 2 to {MAX_JOINTS}"));
        return false;
    }
    if m.parts.is_empty() || m.parts.len() > MAX_PARTS {
        out.add(format!("{at}.parts"), format!("has {} parts; a linkage has from 3 to {MAX_PARTS}", m.parts.len()));
        return false;
    }
    true
}

/// A mechanism's joints by name, for the references of its parts, driver and slider.
struct JointIndex<'a> {
    /// Where the mechanism is in the file, for the messages.
    at: &'a str,
    /// Each joint's index: its place in the file's (sorted) joints.
    index: BTreeMap<&'a str, usize>,
}

impl<'a> JointIndex<'a> {
    fn new(at: &'a str, m: &'a MechanismJson) -> Self {
        JointIndex { at, index: m.joints.keys().enumerate().map(|(i, n)| (n.as_str(), i)).collect() }
    }

    /// The joint `name`, or an issue at `field` when the mechanism has none of that name.
    fn resolve(&self, out: &mut Issues, field: String, name: &str) -> Option<usize> {
        let j = self.index.get(name).copied();
        if j.is_none() {
            out.add(
                field,
                format!("names the joint {name:?}, which is not in {}.joints; use one of its names", self.at),
            );
        }
        j
    }

    /// Whether `part` carries joint `j`.
    fn carried_by(&self, part: &PartJson, j: usize) -> bool {
        part.joints.iter().any(|n| self.index.get(n.as_str()) == Some(&j))
    }
}

/// What the parts tell the checks after them.
struct PartCensus {
    /// How many parts carry each joint.
    carriers: Vec<usize>,
    /// The parts of kind "fixed" (a sound linkage has one).
    fixed: Vec<usize>,
}

/// Checks the parts: their names, joint references and kinds, one ground, one part per moving body
/// of the scene (`scene_bodies`, when there is a scene), and every joint carried.
fn check_parts(
    out: &mut Issues,
    at: &str,
    scene_bodies: Option<usize>,
    m: &MechanismJson,
    joints: &JointIndex,
) -> PartCensus {
    let mut carriers = vec![0usize; m.joints.len()];
    let mut fixed = Vec::new();
    let mut body_parts: BTreeMap<usize, usize> = BTreeMap::new();
    for (i, p) in m.parts.iter().enumerate() {
        let pf = format!("{at}.parts[{i}]");
        out.name(&format!("{pf}.name"), "part", &p.name);
        check_part_joints(out, &pf, p, joints, &mut carriers);
        match p.kind {
            PartKindJson::Fixed => fixed.push(i),
            PartKindJson::Link if p.joints.len() < 2 => {
                out.add(format!("{pf}.joints"), "a link carries at least two joints; add one or remove the link")
            }
            PartKindJson::Link => {}
            PartKindJson::Body => check_body_part(out, &pf, i, p, scene_bodies, &mut body_parts),
        }
    }
    if fixed.len() != 1 {
        out.add(
            format!("{at}.parts"),
            format!("has {} parts of kind \"fixed\"; a linkage has exactly one ground", fixed.len()),
        );
    }
    if let Some(n) = scene_bodies {
        if let Some(b) = (0..n).find(|b| !body_parts.contains_key(b)) {
            out.add(
                format!("{at}.parts"),
                format!(
                    "no part carries moving body {b}, but the scene has {n} moving bodies: the design belongs to \
                     another scene, or lacks the body's part"
                ),
            );
        }
    }
    for (name, &j) in &joints.index {
        if carriers[j] == 0 {
            out.add(format!("{at}.joints[{name:?}]"), "no part carries this joint; remove it or add it to a part");
        }
    }
    PartCensus { carriers, fixed }
}

/// Checks the joints part `p` (at `pf`) names, each once, and counts it as a carrier of each.
fn check_part_joints(out: &mut Issues, pf: &str, p: &PartJson, joints: &JointIndex, carriers: &mut [usize]) {
    let mut seen = Vec::new();
    for (k, name) in p.joints.iter().enumerate() {
        if let Some(j) = joints.resolve(out, format!("{pf}.joints[{k}]"), name) {
            if seen.contains(&j) {
                out.add(format!("{pf}.joints[{k}]"), format!("the part carries joint {name:?} twice; list it once"));
            } else {
                seen.push(j);
                carriers[j] += 1;
            }
        }
    }
}

/// Checks body part `i` (at `pf`): it names a moving body of the scene that no other part carries
/// (`body_parts`, each body's part so far) and holds it by at least two joints.
fn check_body_part(
    out: &mut Issues,
    pf: &str,
    i: usize,
    p: &PartJson,
    scene_bodies: Option<usize>,
    body_parts: &mut BTreeMap<usize, usize>,
) {
    match p.body {
        None => out.add(format!("{pf}.body"), "a body part needs \"body\": the index of its moving body"),
        Some(b) if scene_bodies.is_some_and(|n| b >= n) => out.add(
            format!("{pf}.body"),
            format!(
                "is {b} but the scene has {} moving bodies (numbered from 0); the design belongs to another scene",
                scene_bodies.unwrap_or(0)
            ),
        ),
        Some(b) => {
            if let Some(first) = body_parts.insert(b, i) {
                out.add(
                    format!("{pf}.body"),
                    format!("moving body {b} already has parts[{first}]; give each moving body one part"),
                );
            }
            if p.joints.len() < 2 {
                out.add(format!("{pf}.joints"), "a body part carries at least two joints (where links hold it)");
            }
        }
    }
}

/// Checks the driver: a link turning about a joint of the ground (`fixed`, when there is exactly one).
fn check_driver(out: &mut Issues, at: &str, m: &MechanismJson, joints: &JointIndex, fixed: &[usize]) {
    let field = |f: &str| format!("{at}.{f}");
    let pivot = joints.resolve(out, field("driver.pivot"), &m.driver.pivot);
    let tip = joints.resolve(out, field("driver.tip"), &m.driver.tip);
    let (Some(pivot), Some(tip), [ground]) = (pivot, tip, fixed) else { return };
    let ground = &m.parts[*ground];
    if !joints.carried_by(ground, pivot) {
        out.add(field("driver.pivot"), "the crank turns about a joint of the ground; name one of its joints");
    }
    if joints.carried_by(ground, tip) {
        out.add(field("driver.tip"), "the crank's moving end cannot be a joint of the ground; name another joint");
    }
    let crank = m
        .parts
        .iter()
        .any(|p| p.kind == PartKindJson::Link && joints.carried_by(p, pivot) && joints.carried_by(p, tip));
    if !crank {
        out.add(field("driver"), "no link carries both the pivot and the tip; the crank is a link joining them");
    }
}

/// Checks the slider, which a family's linkage has or has not.
fn check_slider(out: &mut Issues, at: &str, m: &MechanismJson, joints: &JointIndex) {
    let field = |f: &str| format!("{at}.{f}");
    let family = m.mechanism_type.family();
    let has_slider = family.topology(1).slider_joint.is_some();
    match (&m.slider, has_slider) {
        (None, true) => out
            .add(field("slider"), format!("a {} needs its slider: the joint, the line and the stroke", family.label())),
        (Some(_), false) => {
            let with_slider: Vec<String> = MechanismType::ALL
                .into_iter()
                .filter(|t| t.family().topology(1).slider_joint.is_some())
                .map(|t| format!("\"{}\"", t.id()))
                .collect();
            let message =
                format!("a {} has no slider; remove it or set type to {}", family.label(), with_slider.join(" or "));
            out.add(field("slider"), message)
        }
        (Some(s), true) => {
            joints.resolve(out, field("slider.joint"), &s.joint);
            out.point(&field("slider.point"), s.point);
            let d = Vec2::new(s.direction[0], s.direction[1]);
            if !(d.is_finite() && d.norm() > 0.0 && d.x.abs().max(d.y.abs()) <= MAX_COORDINATE) {
                out.add(field("slider.direction"), "must be a non-zero vector of finite numbers");
            }
            if !s.stroke.iter().all(|v| v.is_finite() && v.abs() <= MAX_COORDINATE) {
                out.add(field("slider.stroke"), format!("must be two finite numbers within ±{MAX_COORDINATE:e}"));
            }
        }
        (None, false) => {}
    }
}

/// Whether the parts and joints (`carriers`: how many parts carry each joint) give one degree of
/// freedom by the mobility count (Grübler): 3 per moving part, less 2 per revolute pair (a joint
/// carried by m parts is m − 1 pairs) and 1 for the slider's pin in its line.
fn check_mobility(out: &mut Issues, at: &str, m: &MechanismJson, carriers: &[usize]) -> bool {
    let pairs: usize = carriers.iter().map(|c| c - 1).sum();
    let dof = 3 * (m.parts.len() as i64 - 1) - 2 * pairs as i64 - i64::from(m.slider.is_some());
    if dof != 1 {
        let hint = if dof < 1 {
            "a part too many locks the linkage (or over-constrains it): remove the extra link or joint"
        } else {
            "a part is missing, so the linkage moves loosely: connect every part so the crank alone drives it"
        };
        out.add(format!("{at}.parts"), format!("the parts and joints give {dof} degrees of freedom, not 1; {hint}"));
        return false;
    }
    true
}

/// Checks the motion; returns the travel (degrees) when it is bounded.
fn check_motion(out: &mut Issues, at: &str, problem: &Problem, motion: &Motion) -> Option<(f64, f64)> {
    let before = out.0.total();
    let angle = |out: &mut Issues, f: String, v: f64| {
        if !(v.is_finite() && v.abs() <= MAX_CRANK_DEG) {
            out.add(f, format!("is {v}; crank angles are finite degrees within ±{MAX_CRANK_DEG}"));
        }
    };
    let (start, end) = (motion.crank_start_deg, motion.crank_end_deg);
    angle(out, format!("{at}.crank_start_deg"), start);
    angle(out, format!("{at}.crank_end_deg"), end);
    let span = (end - start).abs();
    if out.0.total() == before && problem.path().is_some_and(|p| p.closed) {
        if (span - MAX_TRAVEL_DEG).abs() > 1e-9 {
            out.add(
                format!("{at}.crank_end_deg"),
                format!(
                    "the crank travels {span:.1}° from crank_start_deg; the scene's path is closed, traced once \
                     per turn, so the travel is {MAX_TRAVEL_DEG}°"
                ),
            );
        }
    } else if out.0.total() == before && span >= MAX_TRAVEL_DEG {
        out.add(
            format!("{at}.crank_end_deg"),
            format!(
                "the crank travels {span:.1}° from crank_start_deg; a linkage repeats itself after a full turn, so the \
                 travel through the poses is less than {MAX_TRAVEL_DEG}°"
            ),
        );
    }
    let poses = &motion.pose_crank_deg;
    if poses.len() != problem.pose_count {
        out.add(
            format!("{at}.pose_crank_deg"),
            format!(
                "has {} angles but the scene has {} poses; the design belongs to another scene",
                poses.len(),
                problem.pose_count
            ),
        );
    } else {
        for (i, &a) in poses.iter().enumerate() {
            angle(out, format!("{at}.pose_crank_deg[{i}]"), a);
        }
    }
    (out.0.total() == before).then_some((start, end))
}

/// Checks that every metric is a finite number.
fn check_metrics(out: &mut Issues, at: &str, m: &Metrics) {
    let named = [
        ("accuracy", m.accuracy),
        ("smoothness", m.smoothness),
        ("location", m.location),
        ("size", m.size),
        ("transmission", m.transmission),
        ("cost", m.cost),
        ("min_transmission_deg", m.min_transmission_deg),
    ];
    let optional = m.min_transmission_crank_deg.map(|v| ("min_transmission_crank_deg", v));
    for (name, v) in named.into_iter().chain(optional) {
        if !v.is_finite() {
            out.add(format!("{at}.{name}"), format!("is {v}; write a finite number"));
        }
    }
    let misses = m.pose_errors.iter().flatten().chain(m.worst_pose_error.iter());
    if misses.into_iter().any(|p| ![p.position, p.position_rel_d, p.angle_deg].iter().all(|v| v.is_finite())) {
        out.add(format!("{at}.pose_errors"), "every pose error is three finite numbers");
    }
}

/// Simulates the travel at 1° steps and checks that every part keeps its shape: the mobility count
/// holds for the usual linkages, but a part whose joints the motion pulls apart (a link joining two
/// joints that the rest of the linkage already moves) means the linkage is locked.
fn check_rigid_motion(out: &mut Issues, at: &str, mechanism: &Mechanism, start_deg: f64, end_deg: f64) {
    let Ok(plan) = Plan::compile(mechanism) else { return };
    let joints = &mechanism.joints;
    let (lo, hi) = joints.iter().fold((joints[0], joints[0]), |(lo, hi), p| {
        (Point::new(lo.x.min(p.x), lo.y.min(p.y)), Point::new(hi.x.max(p.x), hi.y.max(p.y)))
    });
    let tolerance = RIGIDITY_TOLERANCE * lo.distance(hi).max(f64::MIN_POSITIVE);
    let steps = ((end_deg - start_deg).abs().ceil() as usize).max(1);
    let mut row = vec![Point::ORIGIN; plan.joint_count()];
    for s in 0..=steps {
        let deg = start_deg + (end_deg - start_deg) * s as f64 / steps as f64;
        // A configuration where the linkage does not assemble is the check's to report.
        if plan.solve(deg.to_radians(), &mut row).is_err() {
            continue;
        }
        for (i, part) in mechanism.topology.parts.iter().enumerate() {
            for (k, &a) in part.joints.iter().enumerate() {
                for &b in &part.joints[k + 1..] {
                    let (was, is) = (joints[a].distance(joints[b]), row[a].distance(row[b]));
                    if (was - is).abs() > tolerance {
                        let names = &mechanism.topology.joint_names;
                        out.add(
                            format!("{at}.parts[{i}]"),
                            format!(
                                "{} is not rigid along the motion: joints {:?} and {:?} are {was:.4} apart at the first \
                                 pose and would have to be {is:.4} apart at crank {deg:.1}°, so the linkage is locked; \
                                 remove the part or one of its joints",
                                part_label(&part.name, part.kind),
                                names[a],
                                names[b]
                            ),
                        );
                        return;
                    }
                }
            }
        }
    }
}

fn part_label(name: &str, kind: PartKind) -> String {
    let kind = match kind {
        PartKind::Fixed => "the ground",
        PartKind::Body(_) => "the body part",
        PartKind::Link => "the link",
    };
    format!("{kind} {name:?}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mechanism::{Part, Topology};
    use std::sync::Arc;

    /// A scene may pin every joint a design file's linkage may have, and no more.
    #[test]
    fn a_scene_pins_at_most_the_joints_a_design_may_have() {
        assert_eq!(crate::scene::limits::MAX_PINNED_JOINTS, MAX_JOINTS);
    }

    /// A four-bar (joints p1, q0, q1, r0) that moves, and the same with a brace from the ground pivot
    /// q0 to the body's joint q1, which the dyad plan never reads (both ends are placed without it).
    fn four_bar(braced: bool) -> Mechanism {
        let mut topology = Topology::chain(1);
        if braced {
            topology.parts.push(Part { name: "brace".into(), kind: PartKind::Link, joints: vec![1, 2] });
        }
        let joints = vec![Point::new(1.0, 2.0), Point::new(0.0, 0.0), Point::new(4.0, 3.0), Point::new(5.0, 0.0)];
        Mechanism { topology: Arc::new(topology), joints, slider: None }
    }

    #[test]
    fn a_part_the_motion_would_stretch_is_found_by_simulating() {
        let mut out = Issues::default();
        check_rigid_motion(&mut out, "mechanism", &four_bar(false), 60.0, 80.0);
        assert_eq!(out.0, vec![]);
        check_rigid_motion(&mut out, "mechanism", &four_bar(true), 60.0, 80.0);
        assert_eq!(out.0.total(), 1, "{:?}", out.0);
        assert_eq!(out.0[0].field, "mechanism.parts[4]");
        assert!(out.0[0].message.contains("\"brace\"") && out.0[0].message.contains("locked"), "{}", out.0[0]);
    }
}
