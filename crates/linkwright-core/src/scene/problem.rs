//! The immutable problem derived once from a valid scene: everything every sample needs.

use super::file::{MechanismChoice, Scene, Settings, Weights};
use super::units::Units;
use super::validate::{validate, Issue, Severity};
use crate::geom::{Aabb, Point, Polygon, Rigid};
use crate::issues::IssueList;

/// Penetration depth, as a fraction of the smallest body size, below which bodies only touch.
pub(crate) const CONTACT_FRACTION: f64 = 1e-3;

/// One moving body, ready for the engine.
#[derive(Clone, Debug)]
pub struct MovingBodyProblem {
    /// The body's name in the scene.
    pub name: String,
    /// Outline in the body's own frame.
    pub outline: Polygon,
    /// `body_to_world` at each pose.
    pub poses: Vec<Rigid>,
    /// The body size d: the shorter side of the outline's bounding box (paper §4.1).
    pub size: f64,
    /// The scene's mass for the body, kilograms, when it gives one.
    pub mass_kg: Option<f64>,
    /// The scene's material and thickness (scene units) for the body, when it gives them.
    pub stock: Option<(super::Material, f64)>,
    /// The curve a point of the body follows, when the scene gives one (the body then has one pose:
    /// where it starts).
    pub path: Option<PathTarget>,
}

/// A curve a point of a moving body must follow, ready for the engine.
#[derive(Clone, Debug, PartialEq)]
pub struct PathTarget {
    /// The point that follows the curve, in the body's own frame.
    pub tracer: Point,
    /// The curve, world coordinates, in the order the tracer runs along it.
    pub points: Vec<Point>,
    /// A loop the tracer goes round once per turn of the crank.
    pub closed: bool,
    /// Points of `points` (indices, ascending, each once) the tracer must pass exactly.
    pub exact: Vec<usize>,
    /// The diagonal of the curve's bounding box: the length a path's distances are fractions of.
    pub size: f64,
}

impl MovingBodyProblem {
    /// The world motion that carries points attached to this body from the first pose to pose `i`.
    pub fn motion_from_first(&self, i: usize) -> Rigid {
        self.poses[0].to(&self.poses[i])
    }

    /// Each pose drawn where an earlier one is, as `(pose, earlier pose)`: within a thousandth of d
    /// and a twentieth of a degree. A linkage reaches one pose twice only after its crank has turned
    /// a whole turn, so a repeat is most often a pose placed on another by mistake.
    pub fn repeated_poses(&self) -> Vec<(usize, usize)> {
        (1..self.poses.len())
            .filter_map(|i| {
                (0..i)
                    .find(|&j| {
                        let miss = self.miss(i, &self.poses[j]);
                        miss.position_rel_d <= 1e-3 && miss.angle_deg <= 0.05
                    })
                    .map(|j| (i, j))
            })
            .collect()
    }

    /// How far `reached` (a `body_to_world`) is from input pose `i`.
    pub fn miss(&self, i: usize, reached: &Rigid) -> PoseMiss {
        let wanted = &self.poses[i];
        let position =
            self.outline.vertices().iter().map(|&v| reached.apply(v).distance(wanted.apply(v))).fold(0.0, f64::max);
        let turn = (reached.angle() - wanted.angle()).rem_euclid(std::f64::consts::TAU);
        let angle = turn.min(std::f64::consts::TAU - turn);
        PoseMiss { position, position_rel_d: position / self.size, angle_deg: angle.to_degrees() }
    }
}

/// What is wrong with pose `i` of `body` repeating its pose `j`, and what to do.
pub(crate) fn repeated_pose_words(body: &MovingBodyProblem, i: usize, j: usize) -> String {
    format!(
        "pose {} of {} is the same as pose {}: a four-bar reaches one pose twice only after its crank has turned \
         a whole turn, and only a six-bar whose body goes out and comes back the way it went returns sooner; \
         move pose {} to where the body should be then, or leave it out (to come back, end the motion just \
         short of pose {})",
        i + 1,
        body.name,
        j + 1,
        i + 1,
        j + 1
    )
}

/// How far a body is from one of its input poses.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PoseMiss {
    /// The largest distance between a vertex of the body's outline and where the input pose puts it,
    /// a length (scene units).
    pub position: f64,
    /// `position` as a fraction of the body's size d.
    pub position_rel_d: f64,
    /// The rotation between the two, degrees in [0, 180].
    pub angle_deg: f64,
}

impl PoseMiss {
    /// The largest of each field over `misses` (zero when there are none).
    pub fn worst<'a>(misses: impl IntoIterator<Item = &'a PoseMiss>) -> PoseMiss {
        misses.into_iter().fold(PoseMiss::default(), |w, m| PoseMiss {
            position: w.position.max(m.position),
            position_rel_d: w.position_rel_d.max(m.position_rel_d),
            angle_deg: w.angle_deg.max(m.angle_deg),
        })
    }
}

/// A validated scene in the engine's terms.
#[derive(Clone, Debug)]
pub struct Problem {
    /// The scene's name.
    pub name: String,
    /// The length unit of the drawing: its size in millimetres, and its word for labels.
    pub units: Units,
    /// The unit direction gravity pulls in (down the drawing unless the scene says otherwise).
    pub gravity: crate::geom::Vec2,
    /// The fixed bodies' outlines, world coordinates.
    pub fixed: Vec<Polygon>,
    /// The moving bodies, in the scene's order (the chain's).
    pub bodies: Vec<MovingBodyProblem>,
    /// Where the joints should be at the first pose (soft).
    pub region: Polygon,
    /// Where no link may go (hard).
    pub avoid: Vec<Polygon>,
    /// Which kind of linkage to synthesise.
    pub mechanism: MechanismChoice,
    /// The scene's pinned joints by name, in name order, each where it must be at the first pose.
    pub pinned: Vec<(String, Point)>,
    /// The scene's weights of the soft costs.
    pub weights: Weights,
    /// The scene's search settings.
    pub settings: Settings,
    /// Number of poses N, the same for every body.
    pub pose_count: usize,
    /// Per pose, whether the linkage must reach it (within 0.5% of d and 0.5°): the first, the last
    /// and the scene's must-hit poses.
    pub must_hit: Vec<bool>,
    /// The diagonal of everything drawn: the length every absolute tolerance is a fraction of.
    pub scale: f64,
    /// How the object is to be built.
    pub build: super::Build,
    /// Warnings found while validating (errors make [`Problem::new`] fail).
    pub warnings: IssueList<Issue>,
}

/// The unit vector along `(x, y)`, scaled by its larger component first so that squaring neither
/// underflows to 0 nor overflows to infinity, whatever the length validation let through.
fn unit_direction(x: f64, y: f64) -> crate::geom::Vec2 {
    let scale = x.abs().max(y.abs());
    crate::geom::Vec2::new(x / scale, y / scale).normalized()
}

impl Problem {
    /// Validates `scene` and derives the problem, or returns every issue when any is an error.
    pub fn new(scene: &Scene) -> Result<Problem, IssueList<Issue>> {
        let mut issues = validate(scene);
        if issues.iter().any(|i| i.severity == Severity::Error) {
            return Err(issues);
        }
        let fixed: Vec<Polygon> = scene.fixed_bodies.iter().map(|b| Polygon::new(b.polygon.clone())).collect();
        let bodies: Vec<MovingBodyProblem> = scene
            .moving_bodies
            .iter()
            .map(|b| {
                let outline = Polygon::new(b.polygon.clone());
                let bb = outline.aabb();
                MovingBodyProblem {
                    name: b.name.clone(),
                    size: bb.width().min(bb.height()),
                    mass_kg: b.mass_kg,
                    stock: b.material.zip(b.thickness),
                    poses: b.poses.iter().map(|&p| Rigid::from_pose(p)).collect(),
                    path: b.path.as_ref().map(|path| PathTarget {
                        tracer: path.tracer,
                        size: crate::geom::curve_size(&path.points),
                        points: path.points.clone(),
                        closed: path.closed,
                        exact: {
                            let mut exact: Vec<usize> =
                                path.exact.iter().copied().filter(|&i| i < path.points.len()).collect();
                            exact.sort_unstable();
                            exact.dedup();
                            exact
                        },
                    }),
                    outline,
                }
            })
            .collect();
        for (k, body) in bodies.iter().enumerate() {
            for (i, j) in body.repeated_poses() {
                issues.push(Issue {
                    severity: Severity::Warning,
                    field: format!("moving_bodies[{k}].poses[{i}]"),
                    message: repeated_pose_words(body, i, j),
                });
            }
        }
        let mut drawn: Option<Aabb> = None;
        let mut add = |bb: Aabb| drawn = Some(drawn.map_or(bb, |d| d.union(&bb)));
        for f in &fixed {
            add(f.aabb());
        }
        let mut first_pose_box: Option<Aabb> = fixed.iter().map(|f| f.aabb()).reduce(|a, b| a.union(&b));
        for b in &bodies {
            for pose in &b.poses {
                add(b.outline.transformed(pose).aabb());
            }
            let mut first = b.outline.transformed(&b.poses[0]).aabb();
            if let Some(path) = Aabb::around(b.path.iter().flat_map(|p| p.points.iter().copied())) {
                add(path);
                first = first.union(&path);
            }
            first_pose_box = Some(first_pose_box.map_or(first, |d| d.union(&first)));
        }
        let region = match &scene.linkage_region {
            Some(r) => Polygon::new(r.clone()),
            None => {
                let b = first_pose_box.expect("validation ensures at least one body");
                Polygon::new(vec![
                    b.min,
                    crate::geom::Point::new(b.max.x, b.min.y),
                    b.max,
                    crate::geom::Point::new(b.min.x, b.max.y),
                ])
            }
        };
        add(region.aabb());
        let avoid: Vec<Polygon> = scene.avoid_regions.iter().map(|r| Polygon::new(r.clone())).collect();
        Ok(Problem {
            name: scene.name.clone(),
            units: scene.units.parse().expect("validation refuses units it cannot read"),
            gravity: scene.gravity.map_or(crate::geom::Vec2::new(0.0, -1.0), |[x, y]| unit_direction(x, y)),
            fixed,
            pose_count: bodies[0].poses.len(),
            must_hit: (0..bodies[0].poses.len())
                .map(|i| i == 0 || i + 1 == bodies[0].poses.len() || scene.must_hit_poses.contains(&i))
                .collect(),
            bodies,
            region,
            avoid,
            mechanism: scene.mechanism,
            pinned: scene.pinned_joints.iter().map(|(name, &p)| (name.clone(), p)).collect(),
            weights: scene.weights.clone(),
            settings: scene.settings.clone(),
            scale: drawn.map_or(1.0, |d| d.diagonal()),
            build: scene.build,
            warnings: issues,
        })
    }

    /// Penetration shallower than this (a length) is contact, not collision: a thousandth of the
    /// smallest body size, so drawing imprecision never counts as overlap.
    pub fn contact_tolerance(&self) -> f64 {
        CONTACT_FRACTION * self.bodies.iter().map(|b| b.size).fold(f64::INFINITY, f64::min)
    }

    /// Number of moving bodies K.
    pub fn body_count(&self) -> usize {
        self.bodies.len()
    }

    /// Whether a crank travel from `start` to `end` (degrees) is one this scene's designs may have:
    /// finite and less than a full turn (a linkage repeats itself after one), or exactly one for a
    /// closed path, which the tracer goes round once per turn.
    pub fn travel_fits(&self, start: f64, end: f64) -> bool {
        let span = (end - start).abs();
        match self.path() {
            Some(path) if path.closed => (span - 360.0).abs() <= 1e-9,
            _ => span < 360.0,
        }
    }

    /// The curve the scene's moving body follows, when it is a path scene (one moving body, one pose,
    /// a path).
    pub fn path(&self) -> Option<&PathTarget> {
        self.bodies.iter().find_map(|b| b.path.as_ref())
    }
}
