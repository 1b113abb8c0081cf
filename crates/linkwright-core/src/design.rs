//! The `design/1` format: what the engine answers, and the reader that turns a design file's parts
//! back into a [`Mechanism`] (so any design can be re-simulated from the file alone).

use crate::geom::{Point, Vec2};
use crate::mechanism::{Mechanism, MechanismType, Part, PartKind, SliderLine, Topology};
use crate::scene::{PoseMiss, Problem};
use crate::verify::{pose_misses, verify_travel, Travel, Violation};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::sync::Arc;

mod validate;
pub use validate::{DesignIssue, MAX_TRAVEL_DEG};

/// The version string of the design format this crate reads and writes.
pub const DESIGN_FORMAT: &str = "design/1";

/// A design file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DesignFile {
    pub linkwright: String,
    /// The scene's name.
    pub scene: String,
    pub status: Status,
    /// Why there is no design, and what to change (only with `no_solution`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    pub mechanism: Option<MechanismJson>,
    pub motion: Option<Motion>,
    pub metrics: Option<Metrics>,
    #[serde(default)]
    pub alternatives: Vec<Alternative>,
    pub stats: Stats,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    Ok,
    NoSolution,
}

/// A mechanism as the file writes it: joints at the first pose, parts, driver, slider.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MechanismJson {
    #[serde(rename = "type")]
    pub mechanism_type: MechanismType,
    pub joints: BTreeMap<String, Point>,
    pub parts: Vec<PartJson>,
    pub driver: DriverJson,
    pub slider: Option<SliderJson>,
    /// What a person calls the linkage ("four-bar linkage"); written for display, never read.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub label: Option<String>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PartJson {
    pub name: String,
    pub kind: PartKindJson,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub body: Option<usize>,
    pub joints: Vec<String>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PartKindJson {
    Fixed,
    Body,
    Link,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DriverJson {
    pub pivot: String,
    pub tip: String,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SliderJson {
    pub joint: String,
    pub point: Point,
    pub direction: [f64; 2],
    /// Signed distances from `point` along `direction` between which the joint travels.
    pub stroke: [f64; 2],
}

/// The driver's travel, degrees, unwrapped.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Motion {
    pub crank_start_deg: f64,
    pub crank_end_deg: f64,
    pub pose_crank_deg: Vec<f64>,
}

/// The soft terms of paper eq. 10–13, their weighted sum (eq. 14) and the worst transmission angle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Metrics {
    pub accuracy: f64,
    pub smoothness: f64,
    pub location: f64,
    pub size: f64,
    pub cost: f64,
    pub min_transmission_deg: f64,
    /// `pose_errors[i][b]`: how far body b is from its input pose i in the configuration the design
    /// offers for it (absent in files written before it was added).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pose_errors: Vec<Vec<PoseMiss>>,
    /// The largest of each field of `pose_errors`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub worst_pose_error: Option<PoseMiss>,
}

/// Another valid design.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Alternative {
    pub mechanism: MechanismJson,
    pub motion: Motion,
    pub metrics: Metrics,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Stats {
    pub samples: usize,
    pub candidates: usize,
    pub valid: usize,
    pub seconds: Seconds,
    /// The seed the run used.
    #[serde(default)]
    pub seed: u64,
    /// Designs the run dropped because its independent re-simulation (what `check` runs) rejected them.
    #[serde(default)]
    pub failed_check: usize,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Seconds {
    pub sampling: f64,
    pub collision: f64,
    pub pfo: f64,
    /// Checking designs for printability (added to `design/1`; 0 when not asked).
    #[serde(default)]
    pub printability: f64,
    /// Refining the kept designs to local optima, and checking them again.
    #[serde(default)]
    pub refinement: f64,
    pub total: f64,
}

/// Why a design file's mechanism cannot be used.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum DesignError {
    #[error("unknown format \"{0}\"; this version reads \"{DESIGN_FORMAT}\"")]
    Format(String),
    #[error("the design has status no_solution: there is no mechanism to use")]
    NoMechanism,
    #[error("mechanism.{field}: names the joint \"{joint}\", which is not in mechanism.joints")]
    UnknownJoint { field: String, joint: String },
    #[error("mechanism.{0}: {1}")]
    Invalid(String, String),
}

impl MechanismJson {
    /// The file form of a mechanism.
    pub fn from_mechanism(m: &Mechanism) -> MechanismJson {
        let t = &m.topology;
        let name = |j: usize| t.joint_names[j].clone();
        MechanismJson {
            mechanism_type: t.mechanism_type,
            joints: t.joint_names.iter().cloned().zip(m.joints.iter().copied()).collect(),
            parts: t
                .parts
                .iter()
                .map(|p| PartJson {
                    name: p.name.clone(),
                    kind: match p.kind {
                        PartKind::Fixed => PartKindJson::Fixed,
                        PartKind::Body(_) => PartKindJson::Body,
                        PartKind::Link => PartKindJson::Link,
                    },
                    body: match p.kind {
                        PartKind::Body(b) => Some(b),
                        _ => None,
                    },
                    joints: p.joints.iter().map(|&j| name(j)).collect(),
                })
                .collect(),
            driver: DriverJson { pivot: name(t.driver_pivot), tip: name(t.driver_tip) },
            slider: None,
            label: Some(t.mechanism_type.linkage_label(t.body_count)),
        }
    }

    /// Rebuilds the mechanism from the file's parts alone (joints, parts, driver, slider), so any
    /// reader can re-simulate it.
    pub fn to_mechanism(&self) -> Result<Mechanism, DesignError> {
        let joint_names: Vec<String> = self.joints.keys().cloned().collect();
        let index = |field: &str, n: &str| {
            joint_names
                .iter()
                .position(|x| x == n)
                .ok_or_else(|| DesignError::UnknownJoint { field: field.to_string(), joint: n.to_string() })
        };
        let invalid = |f: &str, m: &str| DesignError::Invalid(f.to_string(), m.to_string());
        let mut parts = Vec::new();
        let mut body_count = 0;
        for (i, p) in self.parts.iter().enumerate() {
            let field = format!("parts[{i}]");
            let kind = match (p.kind, p.body) {
                (PartKindJson::Fixed, _) => PartKind::Fixed,
                (PartKindJson::Link, _) => PartKind::Link,
                (PartKindJson::Body, Some(b)) => {
                    body_count = body_count.max(b + 1);
                    PartKind::Body(b)
                }
                (PartKindJson::Body, None) => return Err(invalid(&field, "a body part needs \"body\": its index")),
            };
            let joints = p.joints.iter().map(|j| index(&field, j)).collect::<Result<Vec<_>, _>>()?;
            parts.push(Part { name: p.name.clone(), kind, joints });
        }
        if parts.iter().filter(|p| p.kind == PartKind::Fixed).count() != 1 {
            return Err(invalid("parts", "there must be exactly one part of kind \"fixed\""));
        }
        for b in 0..body_count {
            match parts.iter().find(|p| p.kind == PartKind::Body(b)) {
                Some(p) if p.joints.len() >= 2 => {}
                Some(_) => return Err(invalid("parts", &format!("body {b} must carry at least two joints"))),
                None => return Err(invalid("parts", &format!("no part for body {b}"))),
            }
        }
        let driver_pivot = index("driver.pivot", &self.driver.pivot)?;
        let driver_tip = index("driver.tip", &self.driver.tip)?;
        let (slider_joint, slider) = match &self.slider {
            None => (None, None),
            Some(s) => {
                let d = Vec2::new(s.direction[0], s.direction[1]);
                if !(d.norm() > 0.0 && d.is_finite()) {
                    return Err(invalid("slider.direction", "must be a non-zero vector"));
                }
                (Some(index("slider.joint", &s.joint)?), Some(SliderLine { point: s.point, direction: d.normalized() }))
            }
        };
        let joints: Vec<Point> = self.joints.values().copied().collect();
        if joints.iter().any(|p| !p.is_finite()) {
            return Err(invalid("joints", "every joint must have finite coordinates"));
        }
        let topology = Topology {
            mechanism_type: self.mechanism_type,
            body_count,
            joint_names,
            parts,
            driver_pivot,
            driver_tip,
            slider_joint,
        };
        Ok(Mechanism { topology: Arc::new(topology), joints, slider })
    }
}

/// Why a design file could not be read at all (before validation).
#[derive(Debug, thiserror::Error)]
#[error("{path}: {message}")]
pub struct DesignParseError {
    /// Where in the document the problem is, e.g. `mechanism.joints[2]`, or `.` for the root.
    pub path: String,
    pub message: String,
}

impl DesignFile {
    /// Parses a design file, naming the offending field on failure.
    pub fn from_json(text: &str) -> Result<DesignFile, DesignParseError> {
        let de = &mut serde_json::Deserializer::from_str(text);
        serde_path_to_error::deserialize(de)
            .map_err(|e| DesignParseError { path: e.path().to_string(), message: e.into_inner().to_string() })
    }
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a design always serializes")
    }
}

impl DesignFile {
    /// Every violated constraint of this design's best mechanism against `problem` (empty when it is
    /// sound; a `no_solution` design has none): the file's own consistency (a file that
    /// [`DesignFile::validate`] refuses is one `format` violation per problem), then an independent
    /// re-simulation of every hard constraint at finer crank steps than the synthesis takes (the one the
    /// synthesis runs on every design before returning it), and the reported accuracy against it.
    pub fn violations(&self, problem: &Problem) -> Vec<Violation> {
        let fail = |constraint, message: String| vec![Violation { constraint, message }];
        let issues = self.validate(problem);
        if !issues.is_empty() {
            return issues.into_iter().map(|i| Violation { constraint: "format", message: i.to_string() }).collect();
        }
        if self.status == Status::NoSolution {
            return Vec::new();
        }
        let (Some(mj), Some(motion), Some(metrics)) = (&self.mechanism, &self.motion, &self.metrics) else {
            return fail("format", "status is ok but mechanism, motion or metrics is missing".into());
        };
        let mechanism = match mj.to_mechanism() {
            Ok(m) => m,
            Err(e) => return fail("format", e.to_string()),
        };
        let travel = Travel { start: motion.crank_start_deg, end: motion.crank_end_deg, poses: &motion.pose_crank_deg };
        let (mut out, accuracy) = verify_travel(problem, &mechanism, travel);
        if let Some(accuracy) = accuracy {
            let scale = problem.scale * problem.scale;
            let agrees = |value: f64| (value - metrics.accuracy).abs() <= 1e-9 * scale + 1e-6 * value;
            // Files written before E_acc counted the outlines carry the joints' part alone.
            if !agrees(accuracy.total()) && !agrees(accuracy.joints) {
                out.push(Violation {
                    constraint: "accuracy",
                    message: format!(
                        "metrics.accuracy is {} but the poses' misses give {}",
                        metrics.accuracy,
                        accuracy.total()
                    ),
                });
            }
        }
        out
    }

    /// The design file of a synthesis outcome.
    pub fn from_outcome(problem: &Problem, outcome: &crate::synth::Outcome) -> DesignFile {
        let s = &outcome.stats;
        let (mechanism, motion, metrics) = match &outcome.best {
            Some(c) => {
                let (m, mo, me) = describe(problem, c);
                (Some(m), Some(mo), Some(me))
            }
            None => (None, None, None),
        };
        DesignFile {
            linkwright: DESIGN_FORMAT.to_string(),
            scene: problem.name.clone(),
            status: if outcome.best.is_some() { Status::Ok } else { Status::NoSolution },
            reason: outcome.reason.clone(),
            mechanism,
            motion,
            metrics,
            alternatives: outcome
                .alternatives
                .iter()
                .map(|c| {
                    let (mechanism, motion, metrics) = describe(problem, c);
                    Alternative { mechanism, motion, metrics }
                })
                .collect(),
            stats: Stats {
                samples: s.samples,
                candidates: s.candidates,
                valid: s.valid,
                seconds: Seconds {
                    sampling: s.seconds_sampling,
                    collision: s.seconds_collision,
                    pfo: s.seconds_pfo,
                    printability: s.seconds_printability,
                    refinement: s.seconds_refinement,
                    total: s.seconds_total,
                },
                seed: problem.settings.seed,
                failed_check: s.failed_verification,
            },
        }
    }
}

/// The file's mechanism, motion and metrics of a candidate.
fn describe(problem: &Problem, c: &crate::synth::Candidate) -> (MechanismJson, Motion, Metrics) {
    let mut mechanism = MechanismJson::from_mechanism(&c.mechanism);
    if let (Some(line), Some(j)) = (c.mechanism.slider, c.mechanism.topology.slider_joint) {
        let along = (0..c.trace.len()).map(|r| (c.trace.row(r)[j] - line.point).dot(line.direction));
        let (lo, hi) = along.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| (lo.min(s), hi.max(s)));
        mechanism.slider = Some(SliderJson {
            joint: c.mechanism.topology.joint_names[j].clone(),
            point: line.point,
            direction: [line.direction.x, line.direction.y],
            stroke: [lo, hi],
        });
    }
    let pose_errors = pose_misses(problem, &c.mechanism, &c.trace, &c.pose_rows);
    let thetas = &c.trace.thetas;
    let motion = Motion {
        crank_start_deg: thetas[0].to_degrees(),
        crank_end_deg: thetas[thetas.len() - 1].to_degrees(),
        pose_crank_deg: c.pose_thetas().map(f64::to_degrees).collect(),
    };
    let metrics = Metrics {
        accuracy: c.soft.accuracy,
        smoothness: c.soft.smoothness,
        location: c.soft.location,
        size: c.soft.size,
        cost: c.cost,
        min_transmission_deg: c.trace.min_transmission(&c.plan).to_degrees(),
        worst_pose_error: Some(PoseMiss::worst(pose_errors.iter().flatten())),
        pose_errors,
    };
    (mechanism, motion, metrics)
}
