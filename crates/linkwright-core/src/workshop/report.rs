//! The plan of a full-size build as data ([`Workshop`], written as `workshop.json`) and the files it
//! becomes ([`super::files`]).

use super::outline::Outline;
use super::settings::WorkshopSettings;
use super::sizing::Check;
use super::standards::{BoltSpec, MaterialValues};
use crate::fab::Face;
use crate::scene::Material;
use serde::Serialize;
use std::fmt::Write as _;

/// The version string of `workshop.json`.
pub const WORKSHOP_FORMAT: &str = "workshop/1";

/// What a cut part is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LinkKind {
    /// A binary bar or a ternary plate of the linkage.
    Link,
    /// A plate fixed to a body (or the fixed bodies) by two bolts, carrying a joint that lies outside it.
    Bracket,
    /// The slider's guide: a slotted plate fixed to the fixed bodies by two bolts.
    Guide,
    /// A scene without a fixed body: the plate that carries the ground joints.
    Frame,
}

/// The distance between two joints of a part, centre to centre of their holes.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PivotLength {
    /// The two joints' names.
    pub joints: [String; 2],
    /// Centre to centre, mm.
    pub length_mm: f64,
}

/// The peak loads a part was sized for (over the motion, and over the sizing's rounds as the links'
/// own weight settled), before the safety factor.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct LinkLoads {
    /// The largest tension between two of its holes, N.
    pub tension_n: f64,
    /// The largest compression between two of its holes, N.
    pub compression_n: f64,
    /// The largest force on any of its joint holes, N.
    pub hole_n: f64,
    /// The largest moment it carries (the crank held at its pivot, a bracket at its fixing), N·m.
    pub moment_nm: f64,
    /// The largest force along the section that carries the moment (the crank's axial force, the
    /// resultant of a bracket's loads), N.
    pub axial_n: f64,
    /// The largest shear on one of its two fixing bolts, N (brackets, guide, frame).
    pub fixing_shear_n: f64,
}

/// One cut part: its size, holes, place in the stack and why it is that strong.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LinkPlan {
    /// The part's name (a link's name in the design, `connector_JOINT` for a bracket).
    pub name: String,
    /// What it is.
    pub kind: LinkKind,
    /// What it is fixed to (a bracket, the guide, the frame): the design's part, `ground` for the
    /// fixed bodies.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub on: Option<String>,
    /// The joints it carries.
    pub joints: Vec<String>,
    /// Every pair of its joints, centre to centre.
    pub pivot_lengths: Vec<PivotLength>,
    /// Width, mm (the diameter of its rounded ends).
    pub width_mm: f64,
    /// Stock thickness, mm.
    pub thickness_mm: f64,
    /// The joint holes' diameter, mm.
    pub hole_mm: f64,
    /// The bolts fixing it to its body (a bracket, the guide, the frame), when they differ from the
    /// joints' or there are any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fixing_bolt: Option<super::standards::BoltSize>,
    /// The face of the bodies it lies on.
    pub face: Face,
    /// Its layer on that face (1 next to the bodies).
    pub layer: u32,
    /// Its mass, kg.
    pub mass_kg: f64,
    /// The outline's length and width, mm.
    pub size_mm: [f64; 2],
    /// The loads it was sized for.
    pub loads: LinkLoads,
    /// Every inequality of the strength rule at its width and thickness.
    pub checks: Vec<Check>,
    /// Why the next thinner stock would not do.
    pub thinner_fails: Option<String>,
    /// Its outline and holes, in its own frame.
    pub outline: Outline,
    /// The profile file it is cut from.
    pub profile_file: String,
}

/// One item on a bolt, from under its head to its nut.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StackItem {
    /// `washer`, `spacer`, `part` (a link, bracket, ...), `body` (a body or the fixed bodies) or `nut`.
    pub item: &'static str,
    /// The part's or body's name.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Its thickness along the bolt, mm.
    pub thickness_mm: f64,
}

/// A bolt: at a joint (through every part that turns on it) or fixing a bracket to its body.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct JointPlan {
    /// The joint's name, or `NAME fixing` for a bracket's two fixing bolts.
    pub at: String,
    /// How many such bolts (2 for a bracket's fixing).
    pub count: u32,
    /// Their size.
    pub bolt: super::standards::BoltSize,
    /// The face of the bodies its parts lie on.
    pub face: Face,
    /// What it passes through and what sits on it, from under the head to the nut.
    pub stack: Vec<StackItem>,
    /// The grip, the nut and two threads beyond it, mm.
    pub needed_mm: f64,
    /// The standard length to buy, mm.
    pub length_mm: f64,
    /// The largest shear across the bolt between two of the parts it holds, N.
    pub shear_n: f64,
    /// The largest bending moment in the bolt, N·m.
    pub moment_nm: f64,
    /// Its checks: shear of one shear plane and bending of the thread core (class 8.8).
    pub checks: Vec<Check>,
}

/// One layer of parts on one face.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LayerPlan {
    /// The face.
    pub face: Face,
    /// The layer (1 next to the bodies).
    pub layer: u32,
    /// Its distance from the bodies' face, mm.
    pub from_face_mm: f64,
    /// Its thickness (its thickest part), mm.
    pub thickness_mm: f64,
    /// Its parts.
    pub parts: Vec<String>,
}

/// One line of the cut list: identical parts together.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CutItem {
    /// The parts.
    pub parts: Vec<String>,
    /// What they are.
    pub kind: LinkKind,
    /// The material.
    pub material: Material,
    /// Stock thickness, mm.
    pub thickness_mm: f64,
    /// Outline length, mm.
    pub length_mm: f64,
    /// Outline width, mm.
    pub width_mm: f64,
    /// Holes per part.
    pub holes: usize,
    /// Their diameter, mm.
    pub hole_mm: f64,
    /// How many.
    pub count: u32,
    /// The profile file.
    pub file: String,
}

/// One line of the bill of materials.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BomItem {
    /// What it is.
    pub item: String,
    /// The standard it is bought by, when there is one.
    pub standard: String,
    /// Its size.
    pub size: String,
    /// How many.
    pub count: u32,
}

/// The mass of one moving part and where it comes from.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PartMass {
    /// The design's part.
    pub part: String,
    /// Its mass, kg.
    pub kg: f64,
    /// `scene` (the scene's mass), `stock` (its material and thickness in the scene), `default` (its
    /// outline × the settings' body thickness × the build's material) or `sized` (a link, as cut).
    pub source: &'static str,
}

/// Everything a workshop needs to build a design at full size.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Workshop {
    /// [`WORKSHOP_FORMAT`].
    pub linkwright: &'static str,
    /// The scene's name.
    pub scene: String,
    /// The material the parts are cut from.
    pub material: Material,
    /// Its design values and their sources.
    pub values: MaterialValues,
    /// The settings used.
    pub settings: WorkshopSettings,
    /// The bolt of every joint (brackets' fixing bolts may be larger: see each bolt's size).
    pub bolt: BoltSpec,
    /// The moving parts' masses.
    pub masses: Vec<PartMass>,
    /// The largest torque that holds the crank, N·m.
    pub peak_torque_nm: f64,
    /// Where along the travel, degrees of crank.
    pub peak_torque_crank_deg: f64,
    /// Every part to cut.
    pub links: Vec<LinkPlan>,
    /// Every bolt, at the joints and fixing the brackets.
    pub bolts: Vec<JointPlan>,
    /// The layers, face by face from the bodies outwards.
    pub layers: Vec<LayerPlan>,
    /// The cut list.
    pub cut_list: Vec<CutItem>,
    /// The bill of materials.
    pub bill_of_materials: Vec<BomItem>,
    /// The assembly steps, in order.
    pub steps: Vec<String>,
    /// What the builder should know: checks that do not hold, loads not designed for.
    pub notes: Vec<String>,
    /// The files [`super::files`] writes.
    pub files: Vec<String>,
}

/// The profile file of parts `thickness_mm` thick.
pub(crate) fn profile_file(thickness_mm: f64, extension: &str) -> String {
    format!("profiles_{}mm.{extension}", number(thickness_mm))
}

/// A thickness as written in file names and text: whole millimetres without decimals.
pub(crate) fn number(x: f64) -> String {
    if (x - x.round()).abs() < 1e-9 {
        format!("{}", x.round() as i64)
    } else {
        format!("{x:.1}")
    }
}

/// The distinct stock thicknesses of `workshop`'s parts, thinnest first.
pub(crate) fn thicknesses(links: &[LinkPlan]) -> Vec<f64> {
    let mut out: Vec<f64> = links.iter().map(|l| l.thickness_mm).collect();
    out.sort_by(f64::total_cmp);
    out.dedup();
    out
}

/// The names of the files [`super::files`] writes for these parts.
pub(crate) fn file_names(links: &[LinkPlan]) -> Vec<String> {
    let mut out = vec!["workshop.json".to_string(), "workshop_assembly.svg".into()];
    for t in thicknesses(links) {
        out.push(profile_file(t, "dxf"));
        out.push(profile_file(t, "svg"));
    }
    out.push("cut_list.csv".into());
    out.push("bill_of_materials.csv".into());
    out
}

/// A CSV field, quoted when it holds a comma, a quote or a line break.
fn field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

pub(crate) fn cut_list_csv(items: &[CutItem]) -> String {
    let mut s = String::from("parts,kind,material,thickness_mm,length_mm,width_mm,holes,hole_mm,count,file\n");
    for c in items {
        let kind = serde_json::to_value(c.kind).ok().and_then(|v| v.as_str().map(str::to_string)).unwrap_or_default();
        let _ = writeln!(
            s,
            "{},{kind},{},{},{:.1},{:.1},{},{},{},{}",
            field(&c.parts.join(" ")),
            c.material.id(),
            number(c.thickness_mm),
            c.length_mm,
            c.width_mm,
            c.holes,
            c.hole_mm,
            c.count,
            field(&c.file)
        );
    }
    s
}

pub(crate) fn bom_csv(items: &[BomItem]) -> String {
    let mut s = String::from("item,standard,size,count\n");
    for b in items {
        let _ = writeln!(s, "{},{},{},{}", field(&b.item), field(&b.standard), field(&b.size), b.count);
    }
    s
}
