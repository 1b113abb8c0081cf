//! `fabrication.json`: the parts, layers, sizes, volumes and mass estimate of a fabrication.

use super::check::CheckReport;
use super::depth::{Constraint, Face};
use super::parts::Role;
use super::plates::Plates;
use super::Fabrication;
use serde::Serialize;

/// The version string of the report.
pub const FABRICATION_FORMAT: &str = "fabrication/1";

#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub linkwright: &'static str,
    pub scene: String,
    /// Millimetres per scene unit.
    pub mm_per_unit: f64,
    pub settings: super::PrintSettings,
    pub layers: Layers,
    pub parts: Vec<PartReport>,
    pub plates: Vec<PlateReport>,
    /// Parts larger than the bed in every turn (print them on a larger printer or scale the scene).
    pub oversized: Vec<String>,
    pub totals: Totals,
    /// The recorded ordering constraints, with member and joint names.
    pub constraints: Vec<ConstraintReport>,
    pub assembly: Vec<String>,
    pub seconds: super::Timings,
    pub checks: CheckReport,
}

#[derive(Clone, Debug, Serialize)]
pub struct Layers {
    pub front: u32,
    pub back: u32,
    /// Most layers on a face (what the solver minimised).
    pub count: u32,
    /// Whether the solver proved that fewer layers are impossible.
    pub optimal: bool,
}

#[derive(Clone, Debug, Serialize)]
pub struct PartReport {
    pub name: String,
    pub role: Role,
    pub face: Face,
    pub layer: u32,
    pub file: String,
    /// Size laid flat for printing, mm.
    pub size_mm: [f64; 3],
    pub volume_mm3: f64,
    pub mass_g: f64,
    pub triangles: usize,
}

#[derive(Clone, Debug, Serialize)]
pub struct PlateReport {
    pub file: String,
    pub parts: Vec<String>,
}

#[derive(Clone, Debug, Serialize)]
pub struct Totals {
    pub parts: usize,
    pub volume_mm3: f64,
    pub mass_g: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct ConstraintReport {
    /// Paper equation: 16, 17 or 18-19 (or "structure").
    pub equation: &'static str,
    pub text: String,
    /// First crank angle where it was seen, degrees.
    pub at_deg: f64,
}

/// Mass in grams of `volume_mm3` with the settings' density and fill.
pub fn mass_g(fab: &Fabrication, volume_mm3: f64) -> f64 {
    volume_mm3 / 1000.0 * fab.settings.density * fab.settings.fill_fraction
}

/// The report of a fabrication, its plates (files named `plate_N.3mf`) and its checks.
pub fn report(fab: &Fabrication, plates: &Plates, checks: CheckReport) -> Report {
    let s = fab.dims.mm_per_unit;
    let parts: Vec<PartReport> = fab
        .parts
        .iter()
        .map(|p| {
            let (lo, hi) = p.print_mesh.bounds();
            let volume = p.mesh.volume() * s * s * s;
            PartReport {
                name: p.name.clone(),
                role: p.role,
                face: p.face,
                layer: p.layer,
                file: format!("parts/{}.stl", p.name),
                size_mm: [(hi[0] - lo[0]) * s, (hi[1] - lo[1]) * s, (hi[2] - lo[2]) * s],
                volume_mm3: volume,
                mass_g: mass_g(fab, volume),
                triangles: p.mesh.triangles.len(),
            }
        })
        .collect();
    let per_face = |f: Face| {
        (0..fab.ordering.layer.len())
            .filter(|&i| fab.ordering.face[i] == f)
            .map(|i| fab.ordering.layer[i])
            .max()
            .unwrap_or(0)
    };
    let names = |i: usize| fab.layout.members[i].name.clone();
    let joint = |j: usize| fab.layout_joint_name(j);
    let constraints = fab
        .recorded
        .constraints
        .iter()
        .map(|(c, &at)| {
            let (equation, text) = match *c {
                Constraint::Distinct { a, b } => {
                    ("18-19", format!("{} and {} overlap: different layers", names(a), names(b)))
                }
                Constraint::Below { lower, upper } => {
                    ("16", format!("{} passes over the post of {}: above it", names(upper), names(lower)))
                }
                Constraint::Around { member, joint: j } => (
                    "17",
                    format!("{} passes over the pin at {}: below or above all its parts", names(member), joint(j)),
                ),
                Constraint::Above { member, joint: j } => {
                    ("17", format!("{} passes over the body pin at {}: above all its parts", names(member), joint(j)))
                }
                Constraint::Outermost { member, joint: j } => {
                    ("structure", format!("{} is the outermost part at {}", names(member), joint(j)))
                }
                Constraint::OppositeFaces { a, b } => {
                    ("structure", format!("pillars {a:?} and {b:?} meet: opposite faces"))
                }
                Constraint::SameFace { joint: j } => ("structure", format!("every part on {} on one face", joint(j))),
            };
            ConstraintReport { equation, text, at_deg: at }
        })
        .collect();
    let volume: f64 = parts.iter().map(|p| p.volume_mm3).sum();
    Report {
        linkwright: FABRICATION_FORMAT,
        scene: fab.scene_name.clone(),
        mm_per_unit: s,
        settings: fab.settings.clone(),
        layers: Layers {
            front: per_face(Face::Front),
            back: per_face(Face::Back),
            count: fab.ordering.layers,
            optimal: fab.ordering.optimal,
        },
        totals: Totals { parts: parts.len(), volume_mm3: volume, mass_g: mass_g(fab, volume) },
        plates: plates
            .plates
            .iter()
            .enumerate()
            .map(|(k, p)| PlateReport {
                file: format!("plate_{}.3mf", k + 1),
                parts: p.placements.iter().map(|x| fab.parts[x.part].name.clone()).collect(),
            })
            .collect(),
        oversized: plates.oversized.iter().map(|&k| fab.parts[k].name.clone()).collect(),
        parts,
        constraints,
        assembly: super::sheet::steps(fab),
        seconds: fab.timings,
        checks,
    }
}
