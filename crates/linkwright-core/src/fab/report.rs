//! `fabrication.json`: the parts, layers, sizes, volumes and mass estimate of a fabrication.

use super::check::CheckReport;
use super::depth::{Constraint, Face};
use super::fabrication::{Fabrication, Timings};
use super::layout::Anchor;
use super::parts::Role;
use super::plates::{misfit, Misfit, Plates};
use super::settings::PrintSettings;
use crate::geom::Point;
use serde::Serialize;

/// The version string of the report.
pub const FABRICATION_FORMAT: &str = "fabrication/1";

/// `fabrication.json`: what was made, how it is layered and laid out, what it weighs, and the checks.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// The report's version string, [`FABRICATION_FORMAT`].
    pub linkwright: &'static str,
    /// The scene's name.
    pub scene: String,
    /// Millimetres of the printed parts per scene unit (the object's millimetres per unit times the
    /// model's scale).
    pub mm_per_unit: f64,
    /// The model's scale (`1:10`: a tenth of the object's size).
    pub scale: String,
    /// The model's extent at its first pose, width and height in millimetres: everything drawn, at
    /// the model's scale.
    pub model_mm: [f64; 2],
    /// The print settings used.
    pub settings: PrintSettings,
    /// How many layers the depth ordering uses on each face.
    pub layers: Layers,
    /// Every printed part, with its file and size.
    pub parts: Vec<PartReport>,
    /// The print beds the parts are laid out on, one 3MF file each.
    pub plates: Vec<PlateReport>,
    /// Parts larger than the bed in every turn, each with what it would take to print it.
    pub oversized: Vec<Oversized>,
    /// Part count, volume and mass of the whole linkage.
    pub totals: Totals,
    /// The counterbalance springs hooked, each with its hooks.
    pub springs: Vec<SpringReport>,
    /// The recorded ordering constraints, with member and joint names.
    pub constraints: Vec<ConstraintReport>,
    /// The assembly steps, in order, as sentences.
    pub assembly: Vec<String>,
    /// Seconds spent in each stage of the fabrication.
    pub seconds: Timings,
    /// What the fabrication's checks found ([`super::check`]).
    pub checks: CheckReport,
}

/// A part larger than the bed in every turn.
#[derive(Clone, Debug, Serialize)]
pub struct Oversized {
    /// The part's name.
    pub name: String,
    /// What the part is.
    pub role: Role,
    /// Its footprint, the smallest square bed it fits and the largest scene scale that fits this bed.
    #[serde(flatten)]
    pub misfit: Misfit,
}

/// The layers of a depth ordering.
#[derive(Clone, Debug, Serialize)]
pub struct Layers {
    /// Layers on the bodies' front face.
    pub front: u32,
    /// Layers on the bodies' back face.
    pub back: u32,
    /// Most layers on a face (what the solver minimised).
    pub count: u32,
    /// Whether the solver proved that fewer layers are impossible.
    pub optimal: bool,
}

/// One printed part in the report.
#[derive(Clone, Debug, Serialize)]
pub struct PartReport {
    /// The part's name (also its file's stem).
    pub name: String,
    /// What the part is.
    pub role: Role,
    /// The face of the bodies it is on.
    pub face: Face,
    /// Its layer (1 next to the bodies), 0 for bodies and ground.
    pub layer: u32,
    /// Its STL file, relative to the output directory (`parts/NAME.stl`).
    pub file: String,
    /// Size laid flat for printing, mm.
    pub size_mm: [f64; 3],
    /// Its volume, mm³.
    pub volume_mm3: f64,
    /// Its estimated mass with the settings' density and fill fraction, grams.
    pub mass_g: f64,
    /// Triangles of its mesh.
    pub triangles: usize,
}

/// A counterbalance spring and where its hooks stand.
#[derive(Clone, Debug, Serialize)]
pub struct SpringReport {
    /// The face of the bodies it hangs beyond, outside every layer there.
    pub face: Face,
    /// Height of its axis above that face, mm.
    pub axis_height_mm: f64,
    /// The widest spring the room around it takes (a link's width), mm.
    pub max_outer_diameter_mm: f64,
    /// Its two hooks, the ground end first.
    pub hooks: Vec<HookReport>,
}

/// One hook of a spring.
#[derive(Clone, Debug, Serialize)]
pub struct HookReport {
    /// Where the spring is anchored, as asked for.
    #[serde(flatten)]
    pub anchor: Anchor,
    /// The printed part the hook stands on, in words.
    pub on: String,
}

/// One print bed's worth of parts.
#[derive(Clone, Debug, Serialize)]
pub struct PlateReport {
    /// Its 3MF file, relative to the output directory (`plate_N.3mf`).
    pub file: String,
    /// The names of the parts on it.
    pub parts: Vec<String>,
}

/// The whole linkage's parts, volume and mass.
#[derive(Clone, Debug, Serialize)]
pub struct Totals {
    /// Number of printed parts.
    pub parts: usize,
    /// Their total volume, mm³.
    pub volume_mm3: f64,
    /// Their total estimated mass, grams.
    pub mass_g: f64,
}

/// One recorded ordering constraint, in words.
#[derive(Clone, Debug, Serialize)]
pub struct ConstraintReport {
    /// Paper equation: 16, 17 or 18-19 (or "structure").
    pub equation: &'static str,
    /// What the constraint asks, with member and joint names.
    pub text: String,
    /// First crank angle where it was seen, degrees.
    pub at_deg: f64,
}

/// Mass in grams of `volume_mm3` with the settings' density and fill.
pub(crate) fn mass_g(fab: &Fabrication, volume_mm3: f64) -> f64 {
    volume_mm3 / 1000.0 * fab.settings.density * fab.settings.fill_fraction
}

/// The report of a fabrication, its plates (files named `plate_N.3mf`) and its checks.
pub(crate) fn report(fab: &Fabrication, plates: &Plates, checks: CheckReport) -> Report {
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
                Constraint::UnderHook { member, hook } => (
                    "structure",
                    format!(
                        "{} passes over the hook of spring {}: below what the hook stands on, or on the other face",
                        names(member),
                        fab.layout.hooks[hook].spring + 1
                    ),
                ),
                Constraint::SpringsApart { a, b } => {
                    ("structure", format!("springs {} and {} meet: opposite faces or different levels", a + 1, b + 1))
                }
                Constraint::SpringOverHook { spring, hook } => (
                    "structure",
                    format!(
                        "spring {} passes over a hook of spring {}: the other face or a higher level",
                        spring + 1,
                        fab.layout.hooks[hook].spring + 1
                    ),
                ),
            };
            ConstraintReport { equation, text, at_deg: at }
        })
        .collect();
    let volume: f64 = parts.iter().map(|p| p.volume_mm3).sum();
    Report {
        linkwright: FABRICATION_FORMAT,
        scene: fab.scene_name.clone(),
        mm_per_unit: s,
        scale: fab.scale.to_string(),
        model_mm: fab.model_mm,
        settings: fab.settings.clone(),
        layers: Layers {
            front: fab.ordering.layers_on(Face::Front),
            back: fab.ordering.layers_on(Face::Back),
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
        oversized: plates.oversized.iter().map(|&k| oversized(fab, k)).collect(),
        parts,
        springs: (0..fab.springs.len())
            .map(|n| SpringReport {
                face: fab.ordering.spring_face[n],
                axis_height_mm: fab.spring_axis(n) * s,
                max_outer_diameter_mm: 2.0 * fab.dims.spring_radius() * s,
                hooks: (0..2)
                    .map(|e| HookReport {
                        anchor: fab.springs[n][e].clone(),
                        on: super::sheet::hook_holder(fab, 2 * n + e),
                    })
                    .collect(),
            })
            .collect(),
        constraints,
        assembly: super::sheet::steps(fab),
        seconds: fab.timings,
        checks,
    }
}

/// What it would take to print part `k`, which fits the bed in no turn.
fn oversized(fab: &Fabrication, k: usize) -> Oversized {
    let p = &fab.parts[k];
    let (s, bed) = (fab.dims.mm_per_unit, &fab.settings.bed);
    let outline: Vec<Point> = p.print_mesh.vertices.iter().map(|v| Point::new(v[0] * s, v[1] * s)).collect();
    // A member's joints and post scale with the scene, its width does not.
    let member = p.member.and_then(|i| {
        let core: Vec<Point> = fab.layout.members[i].core.iter().map(|q| Point::new(q.x * s, q.y * s)).collect();
        misfit(&core, fab.dims.half_width * s, bed)
    });
    let found = member.or_else(|| misfit(&outline, 0.0, bed));
    let misfit = found.unwrap_or(Misfit { footprint_mm: [0.0; 2], square_bed_mm: 0.0, max_scale: 1.0 });
    Oversized { name: p.name.clone(), role: p.role, misfit }
}

impl Report {
    /// One sentence on the parts larger than the bed and what to change, `None` when every part fits.
    pub fn oversized_advice(&self) -> Option<String> {
        if self.oversized.is_empty() {
            return None;
        }
        let bed = &self.settings.bed;
        let names: Vec<String> = self
            .oversized
            .iter()
            .map(|o| format!("{} ({:.0} × {:.0} mm)", o.name, o.misfit.footprint_mm[0], o.misfit.footprint_mm[1]))
            .collect();
        let side = self.oversized.iter().map(|o| o.misfit.square_bed_mm).fold(0.0, f64::max);
        let scale = self.oversized.iter().map(|o| o.misfit.max_scale).fold(f64::INFINITY, f64::min);
        Some(format!(
            "{} larger than the {:.0} × {:.0} mm print area (the bed minus its margins) in every turn: print on a \
             bed of at least {side:.0} mm square (print settings \"bed\"), or print a model at most {scale:.2} times as large (the scene's \
             build)",
            names.join(", "),
            bed.width - 2.0 * bed.margin,
            bed.depth - 2.0 * bed.margin,
        ))
    }
}
