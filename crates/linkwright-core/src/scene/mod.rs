//! The `scene/1` format: what a person wants (bodies, poses, regions, settings), its validation, and
//! the immutable [`Problem`] every later stage reads.

mod build;
mod file;
mod problem;
mod units;
mod validate;

pub use build::{Build, BuildParseError, Material, ModelScale, Ratio, MAX_RATIO_TERM};
pub use file::{
    DrawnPath, FixedBody, MechanismChoice, MechanismType, MovingBody, ParseError, Scene, Settings, Weights,
    SCENE_FORMAT,
};
pub(crate) use problem::repeated_pose_words;
pub(crate) use problem::CONTACT_FRACTION;
pub use problem::{MovingBodyProblem, PathTarget, PoseMiss, Problem};
pub use units::{KnownUnit, Units, UnitsParseError};
pub(crate) use validate::name_problems;
pub use validate::{limits, validate, Issue, Severity};
