//! The design file's fields, how an outcome of the engine becomes one, and how its parts become a
//! [`Mechanism`] again.

use crate::geom::{PathError, Point, Vec2};
use crate::mechanism::{Mechanism, MechanismType, Part, PartKind, SliderLine, Topology};
use crate::scene::{Build, PoseMiss, Problem};
use crate::verify::{pose_misses, verify_travel, Travel, Violation};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::sync::Arc;

/// The version string of the design format this crate reads and writes.
pub const DESIGN_FORMAT: &str = "design/1";

/// A design file: the engine's answer for one scene (docs/formats.md describes every field).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DesignFile {
    /// The format's version string, [`DESIGN_FORMAT`] for a file this crate reads.
    pub linkwright: String,
    /// The scene's name.
    pub scene: String,
    /// Whether the file holds a design.
    pub status: Status,
    /// Why there is no design, and what to change (only with `no_solution`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// The best design's linkage (absent with `no_solution`).
    pub mechanism: Option<MechanismJson>,
    /// The best design's crank travel (absent with `no_solution`).
    pub motion: Option<Motion>,
    /// The best design's soft costs and pose errors (absent with `no_solution`).
    pub metrics: Option<Metrics>,
    /// Other valid designs, best first, each distinct from the others.
    #[serde(default)]
    pub alternatives: Vec<Alternative>,
    /// What the run that made the file did.
    pub stats: Stats,
    /// The build the design was checked for and whether it can be built so (absent in files written
    /// before builds, and for a design edited by hand).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub build: Option<BuildRecord>,
}

/// The build a design was checked for.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BuildRecord {
    /// The build as the scene asked for it (`model:auto`, `model:1:10`, `full:plywood`).
    pub asked: Build,
    /// The build the design was checked for: the asked one with an `auto` scale decided
    /// (`model:1:5`).
    pub checked: Build,
    /// Whether the design can be built that way (a model: it passed the print check at its scale;
    /// full size: always). A design that cannot is still the best valid linkage.
    pub buildable: bool,
    /// Why it cannot, and what would help, in numbers (only when it cannot).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// The model's extent, width and height in millimetres: everything drawn at the model's scale
    /// (a model only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model_mm: Option<[f64; 2]>,
}

/// Whether a design file holds a design.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// A design that passes every hard constraint.
    Ok,
    /// No linkage was found; `reason` says what to change.
    NoSolution,
}

/// A mechanism as the file writes it: joints at the first pose, parts, driver, slider.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MechanismJson {
    /// The linkage's family (`type` in the file).
    #[serde(rename = "type")]
    pub mechanism_type: MechanismType,
    /// Every joint's position at the first pose, world coordinates, by name.
    pub joints: BTreeMap<String, Point>,
    /// Every rigid part with the joints it carries.
    pub parts: Vec<PartJson>,
    /// The link the motion is driven by.
    pub driver: DriverJson,
    /// The line the slider joint runs on (the slider-crank only).
    pub slider: Option<SliderJson>,
    /// What a person calls the linkage ("four-bar linkage"); written for display, never read.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub label: Option<String>,
}

/// A rigid part as the file writes it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PartJson {
    /// The part's name (`ground`, `body1`, `crank`, ...).
    pub name: String,
    /// What the part is.
    pub kind: PartKindJson,
    /// For a body part, the moving body it is (0-based index into the scene's `moving_bodies`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub body: Option<usize>,
    /// The names of the joints it carries.
    pub joints: Vec<String>,
}

/// What a part is, as the file writes it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PartKindJson {
    /// The ground (all fixed bodies).
    Fixed,
    /// A moving body (which one: [`PartJson::body`]).
    Body,
    /// A binary or ternary link.
    Link,
}

/// The driver link: it turns about a fixed joint.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DriverJson {
    /// The fixed joint it turns about.
    pub pivot: String,
    /// Its moving joint.
    pub tip: String,
}

/// The fixed line a slider joint runs on, and how far along it the joint travels.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SliderJson {
    /// The name of the joint that runs on the line.
    pub joint: String,
    /// A point of the line: the joint's position at the first pose.
    pub point: Point,
    /// The line's direction `[dx, dy]` (unit length as the engine writes it; any non-zero length is
    /// read).
    pub direction: [f64; 2],
    /// Signed distances from `point` along `direction` between which the joint travels.
    pub stroke: [f64; 2],
}

/// The driver's travel: its angle (atan2 of tip − pivot), degrees, unwrapped, so it may leave
/// [−180, 180].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Motion {
    /// The angle at the first pose.
    pub crank_start_deg: f64,
    /// The angle at the last pose; the linkage moves from start to end without turning back.
    pub crank_end_deg: f64,
    /// The angle at each input pose, in pose order: the configuration there is what the design offers
    /// for the pose.
    pub pose_crank_deg: Vec<f64>,
}

/// The soft terms of paper eq. 10–13 and E_trans, their weighted sum (eq. 14) and the worst
/// transmission angle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Metrics {
    /// E_acc (eq. 10) against the unperturbed poses: the mean squared miss of the body-carried joints
    /// plus that of the outline vertices, a length².
    pub accuracy: f64,
    /// E_smooth (eq. 11): the ratio of the joints' path lengths to their straight distances between
    /// poses, unitless.
    pub smoothness: f64,
    /// E_loc (eq. 12): the mean distance of the joints from the linkage region at the first pose, a
    /// length.
    pub location: f64,
    /// E_size (eq. 13): the mean link length, a length.
    pub size: f64,
    /// E_trans: how far the smallest transmission angle falls short of the scene's comfortable one,
    /// (1 − sin μ / sin μ_c)² below it and 0 above, unitless (0 in files written before it was added).
    #[serde(default)]
    pub transmission: f64,
    /// The weighted sum of the soft terms (eq. 14) under the scene's weights.
    pub cost: f64,
    /// The smallest transmission angle along the whole travel, as its distance from 0° and 180°,
    /// degrees.
    pub min_transmission_deg: f64,
    /// The crank angle (as `motion`'s, degrees) where the transmission is smallest (absent in files
    /// written before it was added).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_transmission_crank_deg: Option<f64>,
    /// `pose_errors[i][b]`: how far body b is from its input pose i in the configuration the design
    /// offers for it (absent in files written before it was added).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pose_errors: Vec<Vec<PoseMiss>>,
    /// The largest of each field of `pose_errors`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub worst_pose_error: Option<PoseMiss>,
    /// When the design is far from a pose drawn (by more than a quarter of its body's size or 5°):
    /// the pose it misses most, and by how much. The search found no design closer.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub far_from_pose: Option<crate::verify::FarFromPose>,
    /// For a path scene: how far the tracer's curve along the travel is from the drawn one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub path_error: Option<crate::geom::PathError>,
}

/// Another valid design.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Alternative {
    /// Its linkage.
    pub mechanism: MechanismJson,
    /// Its crank travel.
    pub motion: Motion,
    /// Its soft costs and pose errors.
    pub metrics: Metrics,
}

/// Counts and seconds of the run that made a design file.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Stats {
    /// Samples drawn.
    pub samples: usize,
    /// Linkages without kinematic defects, before the collision check.
    pub candidates: usize,
    /// Candidates without collisions.
    pub valid: usize,
    /// Seconds per stage.
    pub seconds: Seconds,
    /// The seed the run used.
    #[serde(default)]
    pub seed: u64,
    /// Designs the run dropped because its independent re-simulation (what `check` runs) rejected them.
    #[serde(default)]
    pub failed_check: usize,
}

/// Seconds a run spent in each stage.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Seconds {
    /// Drawing, fitting and checking samples.
    pub sampling: f64,
    /// Checking candidates for collisions.
    pub collision: f64,
    /// The particle filter.
    pub pfo: f64,
    /// Checking designs for printability (added to `design/1`; 0 when not asked).
    #[serde(default)]
    pub printability: f64,
    /// Refining the kept designs to local optima, and checking them again.
    #[serde(default)]
    pub refinement: f64,
    /// The whole run.
    pub total: f64,
}

/// Why joints of a design could not be moved ([`DesignFile::with_joints_moved`]).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EditError {
    /// The design's mechanism is unusable (or there is none).
    #[error(transparent)]
    Design(DesignError),
    /// The alternative asked for (first) is not among the design's (how many, second).
    #[error("alternative {0} does not exist (the design has {1})")]
    NoAlternative(usize, usize),
    /// The design has no joint of this name.
    #[error("the design has no joint called \"{0}\"")]
    UnknownJoint(String),
    /// The place given for this joint is not two finite numbers within the coordinate bound.
    #[error("joint {0}: a place is two finite numbers of at most 1e6 in size")]
    BadPlace(String),
    /// The mechanism is not its family's linkage for the scene (another number of bodies, or parts
    /// the family does not build).
    #[error("the design's linkage is not one its family builds for this scene")]
    NotItsFamilys,
    /// The moved linkage fails this kinematic check: it no longer carries the bodies through the
    /// poses (the front end words what to change).
    #[error("the moved linkage fails the {0:?} check")]
    Rejected(crate::synth::Reject),
}

/// Why a design file's mechanism cannot be used.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum DesignError {
    /// The file's version string (given) is not [`DESIGN_FORMAT`].
    #[error("unknown format \"{0}\"; this version reads \"{DESIGN_FORMAT}\"")]
    Format(String),
    /// The file has status `no_solution`.
    #[error("the design has status no_solution: there is no mechanism to use")]
    NoMechanism,
    /// A part, the driver or the slider names a joint that `mechanism.joints` does not have.
    #[error("mechanism.{field}: names the joint \"{joint}\", which is not in mechanism.joints")]
    UnknownJoint {
        /// The field that names it, under `mechanism` (`parts[2]`, `driver.tip`, ...).
        field: String,
        /// The joint's name.
        joint: String,
    },
    /// A field under `mechanism` (first) is unusable, and why (second).
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
    /// What is wrong there.
    pub message: String,
}

impl DesignFile {
    /// Parses a design file, naming the offending field on failure.
    ///
    /// [`DesignFile::to_json`] writes what this reads:
    ///
    /// ```
    /// use linkwright_core::testbed::{known_scene, Known};
    /// use linkwright_core::{DesignFile, Problem, Status};
    ///
    /// // A scene drawn from a known four-bar through three poses, and that four-bar as a design file.
    /// let known = known_scene(Known::chain(1), 3, 7, 100.0)?;
    /// let problem = Problem::new(&known.scene).expect("a valid scene");
    /// let text = known.design().to_json();
    ///
    /// // The file alone is the design: read back, it passes its check against the scene.
    /// let design = DesignFile::from_json(&text)?;
    /// assert_eq!(design.status, Status::Ok);
    /// assert_eq!(design.mechanism.as_ref().map(|m| m.joints.len()), Some(4));
    /// assert_eq!(design.violations(&problem), vec![]);
    ///
    /// // A status the format does not have: the error names the field.
    /// let error = DesignFile::from_json(r#"{"linkwright": "design/1", "scene": "", "status": "maybe"}"#)
    ///     .unwrap_err();
    /// assert_eq!(error.path, "status");
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn from_json(text: &str) -> Result<DesignFile, DesignParseError> {
        let de = &mut serde_json::Deserializer::from_str(text);
        serde_path_to_error::deserialize(de)
            .map_err(|e| DesignParseError { path: e.path().to_string(), message: e.into_inner().to_string() })
    }
    /// The design file as pretty JSON.
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
    ///
    /// ```
    /// use linkwright_core::geom::Point;
    /// use linkwright_core::testbed::{known_scene, Known};
    /// use linkwright_core::Problem;
    ///
    /// // A scene drawn from a known four-bar through three poses: the four-bar passes.
    /// let known = known_scene(Known::chain(1), 3, 7, 100.0)?;
    /// let problem = Problem::new(&known.scene).expect("a valid scene");
    /// let mut design = known.design();
    /// assert_eq!(design.violations(&problem), vec![]);
    ///
    /// // The rocker's ground pivot moved by a tenth of the body's size.
    /// let d = problem.bodies[0].size;
    /// let r0 = design.mechanism.as_mut().and_then(|m| m.joints.get_mut("r0")).expect("a four-bar's r0");
    /// *r0 = Point::new(r0.x + 0.1 * d, r0.y);
    /// // The linkage still moves, but the body misses its poses by far more than the file's metrics say.
    /// let violations = design.violations(&problem);
    /// assert!(violations.iter().any(|v| v.constraint == "accuracy"), "{violations:?}");
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
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
        if let Some(error) = accuracy.and_then(|a| a.path) {
            let agrees = metrics.path_error.is_some_and(|written| {
                let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * problem.scale + 1e-6 * b.abs();
                let exact = |e: PathError| e.exact.map(|x| x.distance);
                close(written.max, error.max)
                    && close(written.mean, error.mean)
                    && match (exact(written), exact(error)) {
                        (Some(a), Some(b)) => close(a, b),
                        (a, b) => a.is_none() && b.is_none(),
                    }
            });
            if !agrees {
                out.push(Violation {
                    constraint: "accuracy",
                    message: format!(
                        "metrics.path_error is {:?} but the traced curve is {:.6} (largest) and {:.6} (mean) \
                         from the drawn one, and passes its exact points within {:?}",
                        metrics.path_error.map(|e| (e.max, e.mean, e.exact.map(|x| x.distance))),
                        error.max,
                        error.mean,
                        error.exact.map(|x| x.distance)
                    ),
                });
            }
        }
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

    /// The design (`alternative` `None`) or one of its alternatives with the joints `moves` placed
    /// anew (first-pose positions by name), as a design of its own: its motion through the poses
    /// found again and its metrics recomputed, with no alternatives and no search statistics. What a
    /// person who drags a joint of a result gets; [`DesignFile::violations`] then says which hard
    /// constraint the moved linkage breaks and where.
    pub fn with_joints_moved(
        &self,
        problem: &Problem,
        alternative: Option<usize>,
        moves: &BTreeMap<String, Point>,
    ) -> Result<DesignFile, EditError> {
        let chosen = match alternative {
            None => self.mechanism.as_ref(),
            Some(i) => {
                Some(&self.alternatives.get(i).ok_or(EditError::NoAlternative(i, self.alternatives.len()))?.mechanism)
            }
        };
        let mut edited = chosen.ok_or(EditError::Design(DesignError::NoMechanism))?.clone();
        let bound = crate::scene::limits::MAX_COORDINATE;
        for (name, &p) in moves {
            let joint = edited.joints.get_mut(name).ok_or_else(|| EditError::UnknownJoint(name.clone()))?;
            if !(p.x.is_finite() && p.y.is_finite() && p.x.abs() <= bound && p.y.abs() <= bound) {
                return Err(EditError::BadPlace(name.clone()));
            }
            *joint = p;
            // The slider's guide goes through its joint's first-pose place.
            if let Some(slider) = edited.slider.as_mut().filter(|s| &s.joint == name) {
                slider.point = p;
            }
        }
        let mechanism = edited.to_mechanism().map_err(EditError::Design)?;
        let candidate = crate::synth::assess(problem, &mechanism).ok_or(EditError::NotItsFamilys)?;
        let outcome = crate::synth::Outcome {
            best: Some(candidate.map_err(EditError::Rejected)?),
            alternatives: Vec::new(),
            stats: Default::default(),
            reason: None,
            unbuildable: false,
        };
        let mut file = DesignFile::from_outcome(problem, &outcome);
        file.stats.seed = self.stats.seed;
        Ok(file)
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
            build: None,
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
    let (least_row, least_sine) = c.trace.least_transmission(&c.plan);
    let motion = Motion {
        crank_start_deg: thetas[0].to_degrees(),
        crank_end_deg: thetas[thetas.len() - 1].to_degrees(),
        pose_crank_deg: c.pose_thetas().map(f64::to_degrees).collect(),
    };
    let metrics = Metrics {
        accuracy: c.soft[crate::synth::Term::Accuracy],
        smoothness: c.soft[crate::synth::Term::Smoothness],
        location: c.soft[crate::synth::Term::Location],
        size: c.soft[crate::synth::Term::Size],
        transmission: c.soft[crate::synth::Term::Transmission],
        cost: c.cost,
        min_transmission_deg: least_sine.asin().to_degrees(),
        min_transmission_crank_deg: Some(thetas[least_row].to_degrees()),
        worst_pose_error: Some(PoseMiss::worst(pose_errors.iter().flatten())),
        far_from_pose: crate::verify::far_from_pose(problem, &pose_errors),
        pose_errors,
        path_error: c.path,
    };
    (mechanism, motion, metrics)
}
