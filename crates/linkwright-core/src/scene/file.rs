//! The `scene/1` file as read: the drawing (fixed and moving bodies, poses, regions), the mechanism
//! asked for, the weights and the search settings, each field as the file holds it.

use super::build::{Build, Material};
use crate::geom::Point;
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use std::collections::BTreeMap;

/// The version string of the scene format this crate reads and writes.
pub const SCENE_FORMAT: &str = "scene/1";

/// A scene as the file holds it. Fields the format does not know are kept in `extra` (and reported as
/// warnings by [`validate`](super::validate())), so a scene written back loses nothing.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Scene {
    /// The format's version string, [`SCENE_FORMAT`] for a scene this crate reads.
    pub linkwright: String,
    /// What the object is called, for titles and file names (may be empty).
    #[serde(default)]
    pub name: String,
    /// The length unit of every coordinate, `mm` by default: one [`Units`](super::Units) reads (`mm`, `cm`, `m`, `in`,
    /// `ft`, `µm` or a unit's name), which validation checks. Kept as written, so the scene is written
    /// back as it was read; the [`Problem`](super::Problem) holds it read.
    #[serde(default = "default_units")]
    pub units: String,
    /// The parts of the object that never move. None is allowed (with a warning): the ground joints
    /// then stand in the world, and fabrication prints a frame to hold them.
    pub fixed_bodies: Vec<FixedBody>,
    /// The parts that move, in the order of the chain: body 1 is driven from the ground, body k from
    /// body k − 1.
    pub moving_bodies: Vec<MovingBody>,
    /// Where the joints should be at the first pose (a soft wish, the cost E_loc), world coordinates.
    /// Without it, the bounding box of the fixed bodies and of the moving bodies at their first pose.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub linkage_region: Option<Vec<Point>>,
    /// Polygons no link may enter at any moment of the motion (a hard constraint), world coordinates.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub avoid_regions: Vec<Vec<Point>>,
    /// Which kind of linkage to synthesise (default: every kind that fits, the best kept).
    #[serde(default)]
    pub mechanism: MechanismChoice,
    /// Which way gravity pulls in the drawing, a direction `[x, y]` (default `[0, -1]`: down the
    /// drawing), for the torque it takes to move the parts.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gravity: Option<[f64; 2]>,
    /// Poses (by index from 0, for every moving body at once) the linkage must reach as closely as the
    /// first and last, where the object rests: within 0.5% of a body's size and 0.5°. Other
    /// intermediate poses are guides the design may pass near.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub must_hit_poses: Vec<usize>,
    /// Joints the person placed (by name, as in a design's `mechanism.joints`), where they must be at
    /// the first pose: a ground pivot where the wall stud is, say. Every design keeps them there; a
    /// family without a joint of that name is not tried.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub pinned_joints: BTreeMap<String, Point>,
    /// Weights of the soft costs.
    #[serde(default)]
    pub weights: Weights,
    /// Settings of the search.
    #[serde(default)]
    pub settings: Settings,
    /// How the object is to be built (default `model:auto`): a printed model at a scale, which the
    /// synthesis checks every linkage can be printed at, or full size in a workshop material.
    #[serde(default, skip_serializing_if = "is_default_build")]
    pub build: Build,
    /// Top-level fields the format does not know, kept as they were read.
    #[serde(flatten)]
    pub extra: Map<String, Value>,
}

fn is_default_build(build: &Build) -> bool {
    *build == Build::default()
}

fn default_units() -> String {
    "mm".to_string()
}

/// A part of the object that never moves, as a polygon in world coordinates.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FixedBody {
    /// What the body is called (may be empty).
    #[serde(default)]
    pub name: String,
    /// The outline, a simple polygon in world coordinates (either winding).
    pub polygon: Vec<Point>,
    /// Fields the format does not know, kept as they were read.
    #[serde(flatten)]
    pub extra: Map<String, Value>,
}

/// A moving part: its outline in its own frame and the poses `[x, y, angle_deg]` it must visit in order.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MovingBody {
    /// What the body is called (may be empty).
    #[serde(default)]
    pub name: String,
    /// The outline, a simple polygon in the body's own frame.
    pub polygon: Vec<Point>,
    /// Where the body's frame is at each pose, `[x, y, angle_deg]` in world coordinates: a body point
    /// `m` sits at `R(angle)·m + (x, y)`. Every moving body has the same number of poses, pose i of all
    /// of them at the same moment. A body with a `path` has one: where it starts.
    pub poses: Vec<[f64; 3]>,
    /// A curve a point of the body follows (path synthesis), instead of poses after the first.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub path: Option<DrawnPath>,
    /// The body's real mass, kilograms, for the torque it takes to move it (default: the printed
    /// part's, from its outline and the print settings).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass_kg: Option<f64>,
    /// What the real body is made of, for its mass when `mass_kg` is not given (with `thickness`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<Material>,
    /// The real body's thickness, scene units (with `material`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness: Option<f64>,
    /// Fields the format does not know, kept as they were read.
    #[serde(flatten)]
    pub extra: Map<String, Value>,
}

/// A curve a point of a moving body must follow: the linkage carries the `tracer` along `points`, the
/// body turning as the linkage turns it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DrawnPath {
    /// The point that follows the curve, in the body's own frame. At the body's pose it is where
    /// the curve starts (an open curve's first point; anywhere on a closed one).
    pub tracer: Point,
    /// The curve, world coordinates, in the order the tracer runs along it.
    pub points: Vec<Point>,
    /// Closed: the curve is a loop, the crank turns fully and the tracer goes round it once per
    /// turn. Open (the default): the tracer runs from the first point to the last, the crank turning
    /// less than a turn.
    #[serde(default)]
    pub closed: bool,
    /// Points of `points` (indices, from 0) the tracer must pass exactly, the curve between them
    /// followed as closely as it can be.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub exact: Vec<usize>,
    /// Fields the format does not know, kept as they were read.
    #[serde(flatten)]
    pub extra: Map<String, Value>,
}

/// A family of linkages, by the word scene and design files use for it. This is the family's name
/// and the one fact a scene's validation needs (how many moving bodies it can carry); what a family
/// is and how the engine builds it lives with the family, `mechanism::Family`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MechanismType {
    /// The multi-bar chain of paper §4.2 (four-bar for one body, Watt-I six-bar for two, ...).
    Chain,
    /// The RRRP slider-crank of paper §4.3 (one moving body only).
    SliderCrank,
    /// The Watt-II six-bar: a four-bar carrying the body, driven through a second four-bar (one
    /// moving body only).
    WattTwo,
    /// The Stephenson-III six-bar: the body hangs from a four-bar's coupler and from a ground link
    /// (one moving body only).
    StephensonThree,
}

impl MechanismType {
    /// Every family, in the order an automatic choice tries them.
    pub const ALL: [MechanismType; 4] =
        [MechanismType::Chain, MechanismType::SliderCrank, MechanismType::WattTwo, MechanismType::StephensonThree];

    /// The family's word in scene and design files.
    pub const fn id(self) -> &'static str {
        match self {
            MechanismType::Chain => "chain",
            MechanismType::SliderCrank => "slider_crank",
            MechanismType::WattTwo => "watt_ii",
            MechanismType::StephensonThree => "stephenson_iii",
        }
    }

    /// The family named `id` in scene and design files.
    pub fn from_id(id: &str) -> Option<MechanismType> {
        MechanismType::ALL.into_iter().find(|t| t.id() == id)
    }

    /// Every family's word, in the order of [`MechanismType::ALL`].
    pub const IDS: [&'static str; MechanismType::ALL.len()] = {
        let mut ids = [""; MechanismType::ALL.len()];
        let mut i = 0;
        while i < ids.len() {
            ids[i] = MechanismType::ALL[i].id();
            i += 1;
        }
        ids
    };

    /// The most moving bodies a linkage of this family carries (`None`: any number).
    pub fn max_bodies(self) -> Option<usize> {
        match self {
            MechanismType::Chain => None,
            MechanismType::SliderCrank | MechanismType::WattTwo | MechanismType::StephensonThree => Some(1),
        }
    }
}

/// Which kind of linkage to synthesise: in the file, `"auto"` or a family's word
/// ([`MechanismType::id`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum MechanismChoice {
    /// Try every family that fits the number of moving bodies, keep the best.
    #[default]
    Auto,
    /// This family only.
    Only(MechanismType),
}

impl MechanismChoice {
    const AUTO: &'static str = "auto";
    /// Every word a scene may use: "auto", then each family's.
    const WORDS: [&'static str; MechanismType::ALL.len() + 1] = {
        let mut words = [MechanismChoice::AUTO; MechanismType::ALL.len() + 1];
        let mut i = 0;
        while i < MechanismType::ALL.len() {
            words[i + 1] = MechanismType::IDS[i];
            i += 1;
        }
        words
    };
}

// A family is written as its word ([`MechanismType::id`]), so the words are defined once.
impl Serialize for MechanismType {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.id())
    }
}

impl<'de> Deserialize<'de> for MechanismType {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let word = String::deserialize(deserializer)?;
        MechanismType::from_id(&word).ok_or_else(|| serde::de::Error::unknown_variant(&word, &MechanismType::IDS))
    }
}

impl Serialize for MechanismChoice {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(match self {
            MechanismChoice::Auto => MechanismChoice::AUTO,
            MechanismChoice::Only(family) => family.id(),
        })
    }
}

impl<'de> Deserialize<'de> for MechanismChoice {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let word = String::deserialize(deserializer)?;
        if word == MechanismChoice::AUTO {
            return Ok(MechanismChoice::Auto);
        }
        MechanismType::from_id(&word)
            .map(MechanismChoice::Only)
            .ok_or_else(|| serde::de::Error::unknown_variant(&word, &MechanismChoice::WORDS))
    }
}

/// Weights of the soft costs (paper eq. 14), each applied to its term in units of the body size d (the
/// smallest moving body's), so a weight means the same whatever unit the scene is drawn in.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Weights {
    /// Weight of E_acc / d², the mean squared joint error at the poses. Default 10000.
    pub accuracy: f64,
    /// Weight of E_smooth, the tortuosity of the joint paths (≥ 1, unitless). Default 1.
    pub smoothness: f64,
    /// Weight of E_loc / d, the mean distance of joints from the linkage region. Default 10.
    pub location: f64,
    /// Weight of E_size / d, the mean link length. Default 1.
    pub size: f64,
    /// Weight of E_trans, how far the smallest transmission angle along the travel falls short of
    /// `settings.comfortable_transmission_deg` (0 when it does not; 1 at a dead point). Default 10.
    pub transmission: f64,
    /// Fields the format does not know, kept as they were read.
    #[serde(flatten)]
    pub extra: Map<String, Value>,
}

impl Default for Weights {
    fn default() -> Self {
        Weights { accuracy: 10000.0, smoothness: 1.0, location: 10.0, size: 1.0, transmission: 10.0, extra: Map::new() }
    }
}

/// Search settings. Defaults are the paper's.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Settings {
    /// Seed of every random choice; the same seed gives the same design. Default 0.
    pub seed: u64,
    /// Number of candidate samples (paper §4). Default 100,000.
    pub samples: usize,
    /// Particles of the particle filter (paper §6). Default 100.
    pub particles: usize,
    /// Iterations of the particle filter. Default 20.
    pub iterations: usize,
    /// σ of the position noise on intermediate poses, as a fraction of the body size d. Default 0.5.
    pub pose_tolerance: f64,
    /// σ of the angle noise on intermediate poses, degrees. Default 3.
    pub angle_tolerance_deg: f64,
    /// Lower bound on every transmission angle's distance from 0° and 180°, degrees. Default 10.
    pub min_transmission_deg: f64,
    /// The transmission angle (distance from 0° and 180°, degrees) a design is pushed to keep along
    /// its whole travel, a soft goal weighted by `weights.transmission`: textbooks ask for 40° where
    /// the motion allows. Default 35: the term's pull vanishes at the comfortable angle, so designs
    /// that trade it against the others settle just under it (docs/quality.md).
    pub comfortable_transmission_deg: f64,
    /// Fields the format does not know, kept as they were read.
    #[serde(flatten)]
    pub extra: Map<String, Value>,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            seed: 0,
            samples: 100_000,
            particles: 100,
            iterations: 20,
            pose_tolerance: 0.5,
            angle_tolerance_deg: 3.0,
            min_transmission_deg: 10.0,
            comfortable_transmission_deg: 35.0,
            extra: Map::new(),
        }
    }
}

/// Why a scene file could not be read at all (before validation).
#[derive(Debug, thiserror::Error)]
#[error("{path}: {message}")]
pub struct ParseError {
    /// Where in the document the problem is, e.g. `moving_bodies[0].poses[1]`, or `.` for the root.
    pub path: String,
    /// What is wrong there (for text that is not JSON at all, the parser's message).
    pub message: String,
}

impl Scene {
    /// Parses a scene from JSON text. Structural problems (a missing field, a string where a number
    /// belongs, an unknown mechanism) are reported with the path of the offending field; everything
    /// else is left to [`validate`](super::validate()).
    ///
    /// ```
    /// use linkwright_core::{MechanismChoice, Scene};
    ///
    /// let scene = Scene::from_json(
    ///     r#"{"linkwright": "scene/1", "name": "lid",
    ///         "fixed_bodies": [{"name": "ground", "polygon": [[0, 0], [200, 0], [200, 20], [0, 20]]}],
    ///         "moving_bodies": [{"name": "lid", "polygon": [[0, 0], [20, 0], [20, 80], [0, 80]],
    ///                            "poses": [[50, 100, 0], [120, 60, -90]]}]}"#,
    /// )?;
    /// assert_eq!(scene.moving_bodies[0].poses[1], [120.0, 60.0, -90.0]);
    /// // What the file leaves out takes its default.
    /// assert_eq!((scene.units.as_str(), scene.mechanism), ("mm", MechanismChoice::Auto));
    /// assert_eq!(scene.settings.samples, 100_000);
    ///
    /// // A pose without its angle: the error names the field.
    /// let error = Scene::from_json(
    ///     r#"{"linkwright": "scene/1", "fixed_bodies": [],
    ///         "moving_bodies": [{"polygon": [[0, 0], [1, 0], [0, 1]], "poses": [[0, 0]]}]}"#,
    /// )
    /// .unwrap_err();
    /// assert_eq!(error.path, "moving_bodies[0].poses[0]");
    /// # Ok::<(), linkwright_core::ParseError>(())
    /// ```
    pub fn from_json(text: &str) -> Result<Scene, ParseError> {
        let de = &mut serde_json::Deserializer::from_str(text);
        serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            let inner = e.into_inner();
            let message = if inner.is_syntax() || inner.is_eof() {
                format!("not valid JSON: {inner}")
            } else {
                inner.to_string()
            };
            ParseError { path, message }
        })
    }

    /// The scene as pretty JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a scene always serializes")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mechanism_words_read_and_write_as_the_format_says() {
        let read = |word: &str| serde_json::from_value::<MechanismChoice>(Value::String(word.into()));
        assert_eq!(read("auto").unwrap(), MechanismChoice::Auto);
        assert_eq!(read("chain").unwrap(), MechanismChoice::Only(MechanismType::Chain));
        assert_eq!(read("slider_crank").unwrap(), MechanismChoice::Only(MechanismType::SliderCrank));
        assert_eq!(read("watt_ii").unwrap(), MechanismChoice::Only(MechanismType::WattTwo));
        let unknown = read("four_bar").unwrap_err().to_string();
        assert_eq!(
            unknown,
            "unknown variant `four_bar`, expected one of `auto`, `chain`, `slider_crank`, `watt_ii`, `stephenson_iii`"
        );
        for t in MechanismType::ALL {
            let written = serde_json::to_value(MechanismChoice::Only(t)).unwrap();
            assert_eq!(written, Value::String(t.id().into()));
            assert_eq!(serde_json::from_value::<MechanismType>(written).unwrap(), t);
        }
        assert_eq!(serde_json::to_value(MechanismChoice::Auto).unwrap(), Value::String("auto".into()));
        assert!(serde_json::from_value::<MechanismType>(Value::String("auto".into())).is_err());
    }
}
