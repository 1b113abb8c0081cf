//! Statics: the torque the driver must supply to hold a linkage against gravity at every point of its
//! travel (quasi-static: no inertia, no friction), from each moving part's mass and the kinematics.
//!
//! By virtual work, the torque is the derivative of the potential energy along the crank:
//! `τ(θ) = Σ mᵢ g · dhᵢ/dθ`, hᵢ the height of part i's centre of mass. The heights' derivatives come
//! from the joints' exact velocities ([`Plan::velocities`]): a body or link moves rigidly with two of
//! its joints, so its centre's velocity follows from theirs. Gravity pulls down the drawing (−y)
//! unless the scene gives another direction.

use crate::fab::PrintSettings;
use crate::geom::{Point, Vec2};
use crate::kinematics::{carried_velocity, BodyFrames, Plan, Trace};
use crate::mechanism::{Mechanism, PartKind};
use crate::scene::{Build, Material, ModelScale, Problem, Ratio, Units};
use serde::Serialize;

/// Standard gravity, m/s².
pub const GRAVITY: f64 = 9.80665;

/// How a moving body is weighed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyMass {
    /// As printed: its outline × [`Masses::body_thickness`] × [`Masses::kg_per_mm3`], whatever the
    /// scene says of the real body (a model: the real object's mass does not act on it).
    Printed,
    /// The real body: the scene's `mass_kg`, else its `material` × `thickness` × outline (its stock),
    /// else its outline × [`Masses::body_thickness`] × [`Masses::kg_per_mm3`].
    Scene,
}

/// What each moving part weighs, and how long a unit of the drawing is in the thing that moves: a
/// printed model (at its scale) or the object at full size.
///
/// Every length of the statics is the built one: a 1:10 model's centres of mass move a tenth as far
/// as the drawing's, so its torque is the model's torque, N·m at the model's size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Masses {
    /// Millimetres of the built thing per unit of the drawing (a model's scale included).
    pub millimetres_per_unit: f64,
    /// Kilograms per cubic millimetre of a part weighed from its volume (a printed part: the
    /// material's density times the part filled; full size: the build material's density).
    pub kg_per_mm3: f64,
    /// Thickness of a body weighed from its outline, mm.
    pub body_thickness: f64,
    /// Width and thickness of a link, mm.
    pub link_section: [f64; 2],
    /// Whether a body's real mass (the scene's `mass_kg` or stock) counts.
    pub bodies: BodyMass,
}

/// The stock a full-size build is cut from: the material, the thickness of a body the scene gives
/// no mass or stock for, and the section of the link bars (which the workshop fabrication may choose
/// otherwise). [`FullSize::new`] gives common stock sizes for each material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FullSize {
    /// The material every link (and a body without its own stock) is made of.
    pub material: Material,
    /// Thickness of a body the scene gives neither `mass_kg` nor a material and thickness for, mm.
    /// Default: 18 for plywood, 6 for aluminium, 3 for steel.
    pub body_thickness_mm: f64,
    /// Width and thickness of a link's bar, mm. Default: 60 × 18 for plywood, 40 × 6 for
    /// aluminium, 30 × 5 for steel.
    pub link_section_mm: [f64; 2],
}

impl FullSize {
    /// Common stock of `material`: an 18 mm plywood sheet (the usual furniture board) and 60 mm strips
    /// of it, leaving two hole diameters of wood beside a 12 mm bolt; 6 mm aluminium plate and
    /// 40 × 6 mm flat bar; 3 mm steel sheet and 30 × 5 mm flat bar (sizes the metal stockists list
    /// as standard flat bar).
    pub fn new(material: Material) -> FullSize {
        let (body_thickness_mm, link_section_mm) = match material {
            Material::Plywood => (18.0, [60.0, 18.0]),
            Material::Aluminium => (6.0, [40.0, 6.0]),
            Material::Steel => (3.0, [30.0, 5.0]),
        };
        FullSize { material, body_thickness_mm, link_section_mm }
    }

    /// The same stock with bodies `thickness_mm` thick.
    pub fn with_body_thickness_mm(mut self, thickness_mm: f64) -> FullSize {
        self.body_thickness_mm = thickness_mm;
        self
    }

    /// The same stock with link bars of `[width, thickness]` mm.
    pub fn with_link_section_mm(mut self, section_mm: [f64; 2]) -> FullSize {
        self.link_section_mm = section_mm;
        self
    }
}

/// Why parts cannot be weighed for a build.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MassesError {
    /// A model's scale is `auto`, which is decided when a design is checked for the build.
    #[error(
        "the model's scale is auto: weigh the model at the scale its design was checked for (the design \
         file's build.checked)"
    )]
    UndecidedScale,
    /// A model's scale has a zero term.
    #[error("the model's scale {0} has a zero term; both sides of a scale are whole numbers from 1")]
    Scale(Ratio),
    /// A size of the full-size stock is not a positive number of millimetres.
    #[error("the full-size stock's {field} is {value}; give a positive number of millimetres")]
    Stock {
        /// `body_thickness_mm` or `link_section_mm`.
        field: &'static str,
        /// The value given.
        value: f64,
    },
}

impl Masses {
    /// The 1:1 model: parts as printed with `settings` at the drawing's size, for a drawing in
    /// `units`, except that a body the scene gives a real mass (`mass_kg`, or a material and
    /// thickness) weighs that. Kept for the front ends that weigh a design without its build, where
    /// a scene's real mass is the load a person asked about (`analyze` on the full-size wall bed).
    /// A model at its scale is weighed by [`Masses::model`], the full-size object by [`Masses::full`].
    pub fn printed(settings: &PrintSettings, units: &Units) -> Masses {
        Masses { bodies: BodyMass::Scene, ..Masses::model(settings, units, Ratio::ONE).expect("1:1 is a scale") }
    }

    /// A model printed with `settings` at `scale` of the object drawn in `units`: every length of the
    /// model is the drawing's times the scale's factor, and every part, bodies included, weighs what
    /// its print does (the print settings are the model's own millimetres). The real object's masses
    /// are ignored: the model's springs are chosen for the model, and a 60 kg bed's 1:10 model weighs
    /// grams.
    pub fn model(settings: &PrintSettings, units: &Units, scale: Ratio) -> Result<Masses, MassesError> {
        let factor = scale.factor();
        if !(factor.is_finite() && factor > 0.0) {
            return Err(MassesError::Scale(scale));
        }
        Ok(Masses {
            millimetres_per_unit: units.model_millimetres(scale),
            // g/cm³ is 10⁻⁶ kg/mm³.
            kg_per_mm3: settings.density * settings.fill_fraction * 1e-6,
            body_thickness: settings.body_thickness,
            link_section: [settings.link_width, settings.link_thickness],
            bodies: BodyMass::Printed,
        })
    }

    /// The object at its drawn size, cut from `stock`: a body weighs the scene's `mass_kg`, else its
    /// own material × thickness × outline, else the stock's material at its body thickness; links
    /// are solid bars of the stock's section and material.
    pub fn full(stock: &FullSize, units: &Units) -> Result<Masses, MassesError> {
        let positive = |field: &'static str, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(MassesError::Stock { field, value })
            }
        };
        positive("body_thickness_mm", stock.body_thickness_mm)?;
        for value in stock.link_section_mm {
            positive("link_section_mm", value)?;
        }
        Ok(Masses {
            millimetres_per_unit: units.millimetres(),
            kg_per_mm3: stock.material.density_kg_m3() * KG_PER_MM3_PER_KG_M3,
            body_thickness: stock.body_thickness_mm,
            link_section: stock.link_section_mm,
            bodies: BodyMass::Scene,
        })
    }

    /// The masses of `build` (a model at its decided scale, or full size in [`FullSize::new`]'s stock
    /// of its material), for a drawing in `units`.
    pub fn for_build(build: Build, settings: &PrintSettings, units: &Units) -> Result<Masses, MassesError> {
        match build {
            Build::Model(ModelScale::Fixed(scale)) => Masses::model(settings, units, scale),
            Build::Model(ModelScale::Auto) => Err(MassesError::UndecidedScale),
            Build::Full(material) => Masses::full(&FullSize::new(material), units),
        }
    }

    /// The masses of `design` built as its scene says (`problem.build`): a full-size build's real
    /// masses, or its printed model's at the scale the design is printed at
    /// ([`crate::fab::model_scale`]: a fixed scale, the one the design was checked at, or the one the
    /// drawing decides).
    pub fn for_design(
        problem: &Problem,
        design: Option<&crate::design::DesignFile>,
        settings: &PrintSettings,
    ) -> Result<Masses, MassesError> {
        match problem.build {
            Build::Full(material) => Masses::full(&FullSize::new(material), &problem.units),
            Build::Model(_) => {
                Masses::model(settings, &problem.units, crate::fab::model_scale(problem, design, settings))
            }
        }
    }
}

/// kg/mm³ in one kg/m³.
const KG_PER_MM3_PER_KG_M3: f64 = 1e-9;

/// One moving part's weight and its share of the torque.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PartLoad {
    /// The part's name, as in the design's `mechanism.parts`.
    pub name: String,
    /// Its mass, kilograms.
    pub mass_kg: f64,
    /// Its centre of mass at the first pose, scene units.
    pub com: Point,
    /// The torque its weight asks of the driver at each row of the travel, N·m.
    pub torque_nm: Vec<f64>,
}

/// The driving torque along a travel.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Torque {
    /// The crank angle of each row, degrees, unwrapped, in travel order.
    pub crank_deg: Vec<f64>,
    /// The torque the driver supplies at each row, N·m, positive along the travel (it lifts the
    /// parts as the crank advances) and negative where the weight drives the crank forward.
    pub torque_nm: Vec<f64>,
    /// Every moving part (bodies and links; the ground does not move).
    pub parts: Vec<PartLoad>,
    /// The largest |torque|, N·m.
    pub peak_nm: f64,
    /// Where it occurs, degrees of crank.
    pub peak_crank_deg: f64,
}

/// Why the torque cannot be computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StaticsError {
    /// The travel passes a dead point, where the crank cannot hold the linkage at all.
    #[error("the linkage passes a dead point at crank {crank_deg:.1}°, where no torque holds it")]
    DeadPoint {
        /// The crank angle there, degrees.
        crank_deg: f64,
    },
    /// The travel has no rows.
    #[error("the travel is empty")]
    Empty,
}

/// A moving part: its mass and how its centre of mass is found from a row of joints.
struct Part {
    name: String,
    mass_kg: f64,
    centre: Centre,
}

enum Centre {
    /// A point fixed in body b's frame (body coordinates).
    Body { body: usize, local: Point },
    /// The mean of these joints (a bar's middle, a triangle's centroid).
    Joints(Vec<usize>),
}

/// The parts of `mechanism` that move, weighed as [`Masses`] says: bodies as [`BodyMass`] says, links
/// as bars of the link section (a ternary link as its triangle, link thickness thick).
fn parts(problem: &Problem, mechanism: &Mechanism, masses: &Masses) -> Vec<Part> {
    let mm = masses.millimetres_per_unit;
    let joints = &mechanism.joints;
    let mut out = Vec::new();
    for part in &mechanism.topology.parts {
        match part.kind {
            PartKind::Fixed => {}
            PartKind::Body(b) => {
                let body = &problem.bodies[b];
                let area_mm2 = body.outline.area() * mm * mm;
                let from_outline = area_mm2 * masses.body_thickness * masses.kg_per_mm3;
                let mass_kg = match masses.bodies {
                    BodyMass::Printed => from_outline,
                    BodyMass::Scene => body.mass_kg.unwrap_or_else(|| match body.stock {
                        Some((material, thickness)) => {
                            area_mm2 * thickness * mm * material.density_kg_m3() * KG_PER_MM3_PER_KG_M3
                        }
                        None => from_outline,
                    }),
                };
                let local = body.outline.centroid();
                out.push(Part { name: part.name.clone(), mass_kg, centre: Centre::Body { body: b, local } });
            }
            PartKind::Link => {
                let [width, thickness] = masses.link_section;
                let volume = match part.joints[..] {
                    [a, b] => joints[a].distance(joints[b]) * mm * width * thickness,
                    [a, b, c] => 0.5 * (joints[b] - joints[a]).cross(joints[c] - joints[a]).abs() * mm * mm * thickness,
                    _ => 0.0,
                };
                let mass_kg = volume * masses.kg_per_mm3;
                out.push(Part { name: part.name.clone(), mass_kg, centre: Centre::Joints(part.joints.clone()) });
            }
        }
    }
    out
}

impl Part {
    /// The centre of mass in `row`, and its velocity per radian of crank given the joints' `velocity`.
    fn centre(&self, frames: &BodyFrames, row: &[Point], velocity: &[Vec2]) -> (Point, Vec2) {
        match &self.centre {
            Centre::Body { body, local } => {
                let at = frames.pose(*body, row).apply(*local);
                // The body turns with the two joints its frame is built from.
                let (a, b, _) = frames.frame(*body);
                (at, carried_velocity([row[a], row[b]], [velocity[a], velocity[b]], at))
            }
            Centre::Joints(joints) => {
                let n = joints.len() as f64;
                let at = joints.iter().fold(Vec2::ZERO, |s, &j| s + (row[j] - Point::ORIGIN)) / n;
                let v = joints.iter().fold(Vec2::ZERO, |s, &j| s + velocity[j]) / n;
                (Point::ORIGIN + at, v)
            }
        }
    }
}

/// Where a torque is largest in magnitude along a travel, and that magnitude (0 for no rows).
pub(crate) fn peak(torque_nm: &[f64]) -> (usize, f64) {
    let at = (0..torque_nm.len()).max_by(|&a, &b| torque_nm[a].abs().total_cmp(&torque_nm[b].abs())).unwrap_or(0);
    (at, torque_nm.get(at).map_or(0.0, |t| t.abs()))
}

/// The torque the driver of `mechanism` (compiled as `plan`) supplies at every row of `trace` to hold
/// its moving parts against gravity, with each part's share.
pub fn driving_torque(
    problem: &Problem,
    mechanism: &Mechanism,
    plan: &Plan,
    trace: &Trace,
    masses: &Masses,
) -> Result<Torque, StaticsError> {
    if trace.is_empty() {
        return Err(StaticsError::Empty);
    }
    let first_poses: Vec<_> = problem.bodies.iter().map(|b| b.poses[0]).collect();
    let frames = BodyFrames::new(mechanism, &first_poses);
    let parts = parts(problem, mechanism, masses);
    let metres = masses.millimetres_per_unit / 1000.0;
    // Positive along the travel: the crank may turn either way.
    let along = if trace.thetas[trace.len() - 1] >= trace.thetas[0] { 1.0 } else { -1.0 };
    let mut velocity = vec![Vec2::ZERO; plan.joint_count()];
    let mut loads: Vec<PartLoad> = parts
        .iter()
        .map(|p| {
            let (com, _) = p.centre(&frames, trace.row(0), &velocity);
            PartLoad { name: p.name.clone(), mass_kg: p.mass_kg, com, torque_nm: Vec::with_capacity(trace.len()) }
        })
        .collect();
    let mut torque_nm = Vec::with_capacity(trace.len());
    for r in 0..trace.len() {
        let (theta, row) = (trace.thetas[r], trace.row(r));
        if plan.velocities(theta, row, &mut velocity).is_none() {
            return Err(StaticsError::DeadPoint { crank_deg: theta.to_degrees() });
        }
        let mut total = 0.0;
        for (part, load) in parts.iter().zip(&mut loads) {
            let (_, v) = part.centre(&frames, row, &velocity);
            // The potential energy grows as the centre moves against gravity.
            let share = -along * part.mass_kg * GRAVITY * v.dot(problem.gravity) * metres;
            load.torque_nm.push(share);
            total += share;
        }
        torque_nm.push(total);
    }
    let (at, peak_nm) = peak(&torque_nm);
    Ok(Torque {
        crank_deg: trace.thetas.iter().map(|t| t.to_degrees()).collect(),
        peak_nm,
        peak_crank_deg: trace.thetas[at].to_degrees(),
        torque_nm,
        parts: loads,
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::mechanism::Topology;
    use crate::scene::{FixedBody, MovingBody, Scene};
    use crate::testbed::{known_scene, Known};
    use std::sync::Arc;

    /// Grams per cubic centimetre of 1, solid; 6 mm bodies, 10 × 3 mm links; drawn in millimetres.
    pub(crate) const MASSES: Masses = Masses {
        millimetres_per_unit: 1.0,
        kg_per_mm3: 1e-6,
        body_thickness: 6.0,
        link_section: [10.0, 3.0],
        bodies: BodyMass::Scene,
    };

    /// The moving parts' potential energy in the scene's gravity, J, with the joints at `row`: from
    /// their positions alone, what the driving torque is the derivative of.
    pub(crate) fn weight_energy(
        problem: &Problem,
        mechanism: &Mechanism,
        frames: &BodyFrames,
        masses: &Masses,
        row: &[Point],
    ) -> f64 {
        let still = vec![Vec2::ZERO; row.len()];
        let height = |p: Point| -(p - Point::ORIGIN).dot(problem.gravity) * masses.millimetres_per_unit / 1000.0;
        parts(problem, mechanism, masses)
            .iter()
            .map(|p| p.mass_kg * GRAVITY * height(p.centre(frames, row, &still).0))
            .sum()
    }

    /// A parallelogram four-bar: crank `q0 p1` and rocker `r0 q1` of length `r` turn together from 30°
    /// to 120°, so the body (a 60 × 10 plate between them) translates along a circle of radius r.
    pub(crate) fn parallelogram() -> (Problem, Mechanism, Plan, Trace) {
        let (r, base) = (PARALLELOGRAM_R, 60.0);
        let (from, to) = (30f64.to_radians(), 120f64.to_radians());
        let at = |theta: f64| Point::new(r * theta.cos(), r * theta.sin());
        let scene = Scene {
            linkwright: crate::scene::SCENE_FORMAT.to_string(),
            name: "parallelogram".into(),
            units: "mm".into(),
            fixed_bodies: vec![FixedBody {
                name: "base".into(),
                polygon: vec![
                    Point::new(-20.0, -90.0),
                    Point::new(100.0, -90.0),
                    Point::new(100.0, -70.0),
                    Point::new(-20.0, -70.0),
                ],
                extra: Default::default(),
            }],
            moving_bodies: vec![MovingBody {
                name: "plate".into(),
                polygon: vec![
                    Point::new(0.0, -5.0),
                    Point::new(base, -5.0),
                    Point::new(base, 5.0),
                    Point::new(0.0, 5.0),
                ],
                poses: vec![[at(from).x, at(from).y, 0.0], [at(to).x, at(to).y, 0.0]],
                path: None,
                mass_kg: None,
                material: None,
                thickness: None,
                extra: Default::default(),
            }],
            linkage_region: None,
            avoid_regions: Vec::new(),
            mechanism: Default::default(),
            gravity: None,
            must_hit_poses: Vec::new(),
            pinned_joints: Default::default(),
            weights: Default::default(),
            settings: Default::default(),
            build: Default::default(),
            extra: Default::default(),
        };
        let problem = Problem::new(&scene).expect("a valid scene");
        let topology = Arc::new(Topology::chain(1));
        let mut joints = vec![Point::ORIGIN; topology.joint_count()];
        for (name, p) in [
            ("q0", Point::ORIGIN),
            ("r0", Point::new(base, 0.0)),
            ("p1", at(from)),
            ("q1", at(from) + Vec2::new(base, 0.0)),
        ] {
            joints[topology.joint(name).unwrap()] = p;
        }
        let mechanism = Mechanism { topology, joints, slider: None };
        let plan = Plan::compile(&mechanism).unwrap();
        let mut trace = Trace::default();
        trace.sweep(&plan, from, to, 1f64.to_radians()).unwrap();
        (problem, mechanism, plan, trace)
    }

    /// Crank and rocker length of [`parallelogram`].
    pub(crate) const PARALLELOGRAM_R: f64 = 30.0;

    /// Each bar of the parallelogram is a single body on one pivot, τ = m g (r/2) cos θ, and the
    /// plate's height changes by r sin θ, τ = m g r cos θ.
    #[test]
    fn a_parallelogram_needs_the_closed_form_torque() {
        let r = PARALLELOGRAM_R;
        let (problem, mechanism, plan, trace) = parallelogram();
        let torque = driving_torque(&problem, &mechanism, &plan, &trace, &MASSES).unwrap();

        let plate = 600.0 * 6.0 * 1e-6;
        let bar = r * 10.0 * 3.0 * 1e-6;
        let mass = |name: &str| torque.parts.iter().find(|p| p.name == name).unwrap().mass_kg;
        assert!((mass("body1") - plate).abs() < 1e-15 && (mass("crank") - bar).abs() < 1e-15);
        let metres = 1e-3;
        for (k, &theta) in trace.thetas.iter().enumerate() {
            let share = |name: &str| torque.parts.iter().find(|p| p.name == name).unwrap().torque_nm[k];
            let cos = theta.cos();
            let expected = [
                ("crank", bar * GRAVITY * r / 2.0 * metres * cos),
                ("rocker", bar * GRAVITY * r / 2.0 * metres * cos),
                ("body1", plate * GRAVITY * r * metres * cos),
            ];
            for (name, value) in expected {
                assert!(
                    (share(name) - value).abs() <= 1e-12,
                    "{name} at {:.1}°: {} against {value}",
                    theta.to_degrees(),
                    share(name)
                );
            }
            let total: f64 = expected.iter().map(|e| e.1).sum();
            assert!((torque.torque_nm[k] - total).abs() <= 1e-12);
        }
        // The peak is where the bars lie flat: the start, at 30° (cos 30° > |cos 120°|).
        assert!((torque.peak_crank_deg - 30.0).abs() < 1e-9);
        // Gravity along +x instead: the parts' potential energy is −m g x, x = r cos θ + const.
        let mut sideways = problem.clone();
        sideways.gravity = Vec2::new(1.0, 0.0);
        let torque = driving_torque(&sideways, &mechanism, &plan, &trace, &MASSES).unwrap();
        for (k, &theta) in trace.thetas.iter().enumerate() {
            let expected = (plate * r + bar * r / 2.0 * 2.0) * GRAVITY * metres * theta.sin();
            assert!((torque.torque_nm[k] - expected).abs() <= 1e-12, "{} against {expected}", torque.torque_nm[k]);
        }
    }

    /// Virtual work along every bundled example: the torque on a design of each (a short search,
    /// weighed as printed with the default settings, or by the masses the scene gives) against central
    /// differences of the energy from the parts' positions alone.
    #[test]
    fn torque_is_the_derivative_of_the_potential_energy_along_every_bundled_example() {
        // Every scene in examples/, so an example added is covered too.
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
        let mut names: Vec<std::path::PathBuf> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "json"))
            .collect();
        names.sort();
        assert!(names.len() >= 13, "the bundled examples: {names:?}");
        for path in &names {
            let (name, json) = (path.display().to_string(), std::fs::read_to_string(path).unwrap());
            let mut scene = Scene::from_json(&json).unwrap();
            scene.settings.samples = 3000;
            scene.settings.iterations = 2;
            let problem = Problem::new(&scene).unwrap();
            let outcome = crate::synthesize(&problem, &crate::Silent).unwrap();
            let design = crate::DesignFile::from_outcome(&problem, &outcome);
            assert!(design.mechanism.is_some(), "{name}: {:?}", design.reason);
            let masses = Masses::printed(&PrintSettings::default(), &problem.units);
            assert_virtual_work(&name, &problem, &design, &masses);
        }
    }

    /// Virtual work: the torque is the derivative of the potential energy Σ m g h along the crank,
    /// here against central differences of the energy from the parts' positions alone, on linkages of
    /// every family (known mechanisms, so each design exists), turning either way.
    #[test]
    fn torque_is_the_derivative_of_the_potential_energy() {
        let families =
            [Known::chain(1), Known::chain(2), Known::chain(3), Known::one(crate::MechanismType::SliderCrank)];
        for (seed, family) in families.into_iter().enumerate() {
            let known = known_scene(family, 3, seed as u64, 100.0).unwrap();
            let problem = Problem::new(&known.scene).unwrap();
            assert_virtual_work(&format!("{family:?}"), &problem, &known.design(), &MASSES);
        }
    }

    /// Virtual work on the best mechanism of `design`: its driving torque against central differences
    /// of the parts' potential energy from their positions alone.
    fn assert_virtual_work(label: &str, problem: &Problem, design: &crate::DesignFile, masses: &Masses) {
        let replay = crate::analysis::Replay::new(problem, design, crate::analysis::Which::Best, 90).unwrap();
        let torque = driving_torque(problem, &replay.mechanism, &replay.plan, &replay.trace, masses).unwrap();
        assert_energy_derivative(label, &replay.plan, &replay.trace, &torque.torque_nm, 1e-5 * torque.peak_nm, |row| {
            weight_energy(problem, &replay.mechanism, &replay.frames, masses, row)
        });
    }

    /// Asserts that `torque_nm` (N·m, one value per row of `trace`) is, at every row but the ends, the
    /// central difference along the travel of `energy` (J, from a row of joints) to within `bound`.
    pub(crate) fn assert_energy_derivative(
        label: &str,
        plan: &Plan,
        trace: &Trace,
        torque_nm: &[f64],
        bound: f64,
        energy: impl Fn(&[Point]) -> f64,
    ) {
        let at = |theta: f64| {
            let mut row = vec![Point::ORIGIN; plan.joint_count()];
            plan.solve(theta, &mut row).unwrap();
            energy(&row)
        };
        let thetas = &trace.thetas;
        let along = (thetas[thetas.len() - 1] - thetas[0]).signum();
        let h = 1e-6;
        for (&theta, &tau) in thetas.iter().zip(torque_nm).skip(1).take(thetas.len() - 2) {
            let difference = along * (at(theta + h) - at(theta - h)) / (2.0 * h);
            assert!(
                (tau - difference).abs() <= bound,
                "{label} at {:.2}°: {tau} against {difference}",
                theta.to_degrees()
            );
        }
    }
}
