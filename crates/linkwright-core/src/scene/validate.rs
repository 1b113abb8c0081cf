//! Validation of a parsed scene: every problem found, each naming its field and what to change.

use super::{Scene, SCENE_FORMAT};
use crate::geom::{Point, Polygon};

/// How bad a finding is: errors stop the run, warnings are reported and the run goes on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Severity {
    Error,
    Warning,
}

/// One finding about a scene.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Issue {
    pub severity: Severity,
    /// The field, as a path: `moving_bodies[1].poses`, `settings.samples`.
    pub field: String,
    /// What is wrong and what to change.
    pub message: String,
}

impl std::fmt::Display for Issue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let tag = match self.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        write!(f, "{tag}: {}: {}", self.field, self.message)
    }
}

/// Every problem found in `scene`, errors and warnings, in document order.
pub fn validate(scene: &Scene) -> Vec<Issue> {
    let mut out = Vec::new();
    let mut error = |field: String, message: String| out.push(Issue { severity: Severity::Error, field, message });
    if scene.linkwright != SCENE_FORMAT {
        error(
            "linkwright".into(),
            format!("unknown format \"{}\"; this version reads \"{SCENE_FORMAT}\"", scene.linkwright),
        );
    }
    for (i, b) in scene.fixed_bodies.iter().enumerate() {
        if let Err(e) = Polygon::new(b.polygon.clone()).validate() {
            error(format!("fixed_bodies[{i}].polygon"), format!("{e}; draw a simple closed outline"));
        }
    }
    for (i, b) in scene.moving_bodies.iter().enumerate() {
        if let Err(e) = Polygon::new(b.polygon.clone()).validate() {
            error(format!("moving_bodies[{i}].polygon"), format!("{e}; draw a simple closed outline"));
        }
    }
    if scene.moving_bodies.is_empty() {
        error("moving_bodies".into(), "there is no moving body; add at least one".into());
    }
    let _ = Point::ORIGIN;
    out
}
