//! # linkwright-core
//!
//! The engine of Linkwright: from a sketched scene (fixed bodies, moving bodies and their key poses) to a
//! one-degree-of-freedom linkage that carries every moving body through its poses in order, after the
//! paper "Multi-Pose Interactive Linkage Design". All computation, no I/O.
//!
//! The way through the crate, in the order data flows:
//! - a [`Scene`] (the `scene/1` format) is read with [`Scene::from_json`], checked with
//!   [`validate_scene`] and turned into the [`Problem`] every later stage reads ([`Problem::new`]);
//! - [`synthesize`] (or [`synthesize_with`], with [`Options`]) searches for linkages and returns an
//!   [`Outcome`]: the best [`Candidate`] and its alternatives, each a [`Mechanism`] with its motion;
//! - [`DesignFile::from_outcome`] writes the `design/1` answer, [`DesignFile::from_json`] reads one
//!   back, [`DesignFile::validate`] and [`DesignFile::violations`] check it against its scene;
//! - [`design_svg`] and [`animation_svg`] draw it; [`analysis`] replays its motion for display;
//!   [`fab`] turns it into printable parts.
//!
//! Namespaces hold what a flat root would crowd: [`geom`] (points, vectors, rigid transforms,
//! polygons), [`kinematics`] (a mechanism compiled into dyad steps and solved along its crank),
//! [`analysis`], [`fab`] (printed parts), [`statics`] (the crank's torque against gravity),
//! [`balance`] (counterbalance springs), [`hooked`] (those springs' hooks on the printed parts),
//! [`workshop`] (the full-size build), [`testbed`] (scenes made from known mechanisms, for measuring
//! designs) and [`kernels`] (the synthesis's inner loops, for benchmarks). Everything `pub` is
//! reachable from this root (the `unreachable_pub` lint holds it): the re-exports below are the
//! surface, each namespace its own.
//!
//! # Example
//!
//! A bundled example scene, a garbage truck's lid, to a four-bar that carries the lid through its three
//! poses, with a search far smaller than the default (3,000 samples instead of 100,000) so that it takes
//! a fraction of a second:
//!
//! ```
//! use linkwright_core::{synthesize, DesignFile, MechanismChoice, MechanismType, Problem, Scene, Silent, Status};
//!
//! let mut scene = Scene::from_json(include_str!("../../../examples/k1_garbage_truck.json"))?;
//! // A four-bar: not the default `Auto`, which may pick a slider-crank.
//! scene.mechanism = MechanismChoice::Only(MechanismType::Chain);
//! scene.settings.samples = 3000;
//! scene.settings.iterations = 5;
//! let problem = Problem::new(&scene).expect("the example is a valid scene");
//!
//! // `Silent` ignores progress and never cancels; the search runs on the current rayon pool.
//! let outcome = synthesize(&problem, &Silent)?;
//! let best = outcome.best.as_ref().expect("a linkage through every pose");
//! assert_eq!(best.mechanism.topology.joint_count(), 4, "a four-bar: q0, r0 on the ground, p1, q1 on the lid");
//!
//! // The answer as a `design/1` file, which passes its own check against the scene.
//! let design = DesignFile::from_outcome(&problem, &outcome);
//! assert_eq!(design.status, Status::Ok);
//! assert!(design.violations(&problem).is_empty());
//! // The lid reaches every pose to within 1% of its size and 1°.
//! let worst = design.metrics.as_ref().and_then(|m| m.worst_pose_error).expect("pose errors are written");
//! assert!(worst.position_rel_d < 0.01 && worst.angle_deg < 1.0, "{worst:?}");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Conventions: world coordinates, y up; angles counter-clockwise, radians inside the library and
//! degrees in files; "the first pose" is pose 0 of every moving body, the configuration in which the
//! mechanism's joints are given. Every threshold is relative to the scene's size.

#![warn(missing_docs)]
// No public signature may mention a type the surface does not name.
#![warn(unnameable_types)]
// Unit tests link every dev-dependency, which they do not all use; the library must use all of its own.
#![cfg_attr(not(test), warn(unused_crate_dependencies))]

mod design;
mod issues;
mod mechanism;
mod render;
mod scene;
mod synth;
mod verify;
mod xml;

pub mod analysis;
pub mod balance;
pub mod fab;
pub mod geom;
pub mod hooked;
pub mod kernels;
pub mod kinematics;
pub mod statics;
pub mod testbed;
pub mod workshop;

// The `scene/1` format, its validation, and the problem every later stage reads.
pub use scene::{
    limits, validate as validate_scene, Build, BuildParseError, DrawnPath, FixedBody, Issue, KnownUnit, Material,
    MechanismChoice, ModelScale, MovingBody, MovingBodyProblem, ParseError, PathTarget, PoseMiss, Problem, Ratio,
    Scene, Settings, Severity, Units, UnitsParseError, Weights, MAX_RATIO_TERM, SCENE_FORMAT,
};

// Every validation's answer: the first problems in full and how many more.
pub use issues::{IssueList, MAX_LISTED_ISSUES};

// Linkages: their families, structure (topology) and dimensions (joints at the first pose).
pub use mechanism::{Family, Loop, Mechanism, MechanismType, Part, PartKind, SliderLine, Topology};

// The synthesis: its entry points, what steers and observes a run, and what a run finds.
pub use synth::{
    assess, synthesize, synthesize_with, transmission_shortfall, Acceptance, Cancelled, Candidate, Observer, Options,
    Outcome, Progress, Reject, RunStats, Silent, SoftTerms, Stage, Start, Term, FOLLOW_COST_SLACK, SCREENING_DIVISOR,
    SWITCH_COST_FACTOR, WARM_SAMPLES,
};

// The `design/1` format: the engine's answer, read back, validated and checked.
pub use design::{
    Alternative, BuildRecord, DesignError, DesignFile, DesignIssue, DesignParseError, DriverJson, EditError,
    MechanismJson, Metrics, Motion, PartJson, PartKindJson, Seconds, SliderJson, Stats, Status, DESIGN_FORMAT,
};

// A path design's distance from the drawn curve.
pub use geom::{ExactMiss, PathError};

// Checking a design against its scene.
pub use verify::{
    far_from_pose, missed_exact_point, pose_misses, FarFromPose, Violation, EXACT_POINT_TOLERANCE, FAR_ANGLE_DEG,
    FAR_POSITION_REL_D,
};

// Pictures of a design.
pub use render::{animation_svg, design_svg, RenderInput};
