//! Print settings: every physical size of the printed parts, in millimetres, with defaults that work on
//! a common desktop FDM printer (0.4 mm nozzle, PLA), and the same sizes converted to scene units.

use serde::{Deserialize, Serialize};

/// How the links may be spread over the two faces of the bodies.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Faces {
    /// One face when an ordering exists there, otherwise both faces (default).
    #[default]
    Auto,
    /// Only the front face: no ordering on one face is an error.
    One,
    /// Both faces allowed from the start (the solver still minimises the layers).
    Both,
}

/// The snap cap at the end of every pin and post: a cone whose base is wider than the hole, so the
/// pin clicks through the last part and holds the stack together.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SnapCap {
    /// Height of the cap, mm (JD of paper eq. 20). Default 1.6.
    pub height: f64,
    /// How much wider than the hole the cap's base is (radius), mm: the snap interference. Default 0.2.
    pub lip: f64,
    /// How much narrower than the pin the cap's tip is (radius), mm: the lead-in. Default 0.5.
    pub tip_inset: f64,
}

impl Default for SnapCap {
    fn default() -> Self {
        SnapCap { height: 1.6, lip: 0.2, tip_inset: 0.5 }
    }
}

/// The print bed and how parts are spread on it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Bed {
    /// Usable width (x), mm. Default 220.
    pub width: f64,
    /// Usable depth (y), mm. Default 220.
    pub depth: f64,
    /// Free border along the bed's edges, mm. Default 5.
    pub margin: f64,
    /// Free space between two parts, mm. Default 4.
    pub spacing: f64,
}

impl Default for Bed {
    fn default() -> Self {
        Bed { width: 220.0, depth: 220.0, margin: 5.0, spacing: 4.0 }
    }
}

/// Every physical size of the fabricated parts, millimetres. Read from `--settings PRINT.json`; any
/// field left out keeps its default; unknown fields are an error (a misspelt setting would otherwise
/// be silently ignored).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PrintSettings {
    /// Width of links and connectors (the diameter of their rounded ends), mm. Default 10.
    pub link_width: f64,
    /// Thickness of links and connectors (LD of paper eq. 20), mm. Default 3.
    pub link_thickness: f64,
    /// Axial play between two stacked parts and between a part and a snap cap (GP of eq. 20), mm.
    /// Default 0.3.
    pub axial_gap: f64,
    /// Radial play between a pin and its hole (and a post and its socket), mm. Default 0.25.
    pub radial_clearance: f64,
    /// Radius of every pin, mm. Default 2 (a 4 mm pin in a 4.5 mm hole).
    pub pin_radius: f64,
    /// The snap cap of pins and posts.
    pub snap_cap: SnapCap,
    /// Thickness of the extruded bodies, mm. Default 6.
    pub body_thickness: f64,
    /// Side of the square post that holds a connector on its body, mm. Default 4.
    pub connector_post: f64,
    /// Least material around any hole, post or pin base, mm. Default 1.2 (three perimeters).
    pub wall: f64,
    /// Segments of a full circle in meshes and outlines. Default 48.
    pub circle_segments: usize,
    /// Which faces of the bodies may carry links. Default auto.
    pub faces: Faces,
    /// The printer's bed.
    pub bed: Bed,
    /// Material density, g/cm³. Default 1.24 (PLA).
    pub density: f64,
    /// Fraction of a part's volume the slicer fills (walls and infill); 1 is solid. Default 0.5.
    pub fill_fraction: f64,
}

impl Default for PrintSettings {
    fn default() -> Self {
        PrintSettings {
            link_width: 10.0,
            link_thickness: 3.0,
            axial_gap: 0.3,
            radial_clearance: 0.25,
            pin_radius: 2.0,
            snap_cap: SnapCap::default(),
            body_thickness: 6.0,
            connector_post: 4.0,
            wall: 1.2,
            circle_segments: 48,
            faces: Faces::Auto,
            bed: Bed::default(),
            density: 1.24,
            fill_fraction: 0.5,
        }
    }
}

/// Which settings a check is for.
#[derive(Clone, Copy)]
enum Scope {
    /// A person's print settings: every value within what a printer makes.
    Printer,
    /// Settings a full-size build derives from its validated stock and bolts.
    AnyBuild,
}

/// The values a setting may take, inclusive, and its unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Range {
    /// The least value.
    pub lo: f64,
    /// The greatest value.
    pub hi: f64,
    /// The unit, as messages write it after a number (empty for a plain number).
    pub unit: &'static str,
}

impl Range {
    /// The range of the print setting `field` (a path such as `bed.width`), the one place the bounds
    /// live. They are what a desktop or large-format FDM printer makes, far beyond every default:
    /// - a part's own sizes (link width and thickness, pin, post, cap, wall) from 0.1 mm, the finest
    ///   layer and line a printer lays, to 100 mm, a plank rather than a link;
    /// - the body slab from 0.1 mm to 100 mm (thicker bodies are cut, not printed);
    /// - plays (gaps, clearance, the snap lip) from 0.01 mm, below any printer's resolution, to 5 mm,
    ///   beyond which nothing fits or snaps;
    /// - the bed from 10 mm to 2,000 mm a side (the largest printers are about a metre), its margin
    ///   and spacing up to 100 mm;
    /// - density from 0.05 g/cm³ (foamed filaments weigh 0.3) to 25 g/cm³ (osmium, the densest
    ///   element, is 22.6), and a fill from 1% (walls alone weigh more) to solid;
    /// - 8 to 512 segments per circle.
    ///
    /// Together they keep every volume, mass, torque and spring rate derived from them finite and
    /// every mesh non-degenerate: without them, `body_thickness: 1e308` gives NaN grams and infinite
    /// vertices.
    pub(crate) fn of(field: &str) -> Range {
        let mm = |lo, hi| Range { lo, hi, unit: "mm" };
        match field {
            "axial_gap" | "radial_clearance" | "snap_cap.lip" => mm(0.01, 5.0),
            "snap_cap.tip_inset" => mm(0.0, 100.0),
            "bed.width" | "bed.depth" => mm(10.0, 2000.0),
            "bed.margin" => mm(0.0, 100.0),
            "bed.spacing" => mm(0.1, 100.0),
            "density" => Range { lo: 0.05, hi: 25.0, unit: "g/cm³" },
            "fill_fraction" => Range { lo: 0.01, hi: 1.0, unit: "" },
            "circle_segments" => Range { lo: 8.0, hi: 512.0, unit: "" },
            _ => mm(0.1, 100.0),
        }
    }

    /// The range of a length setting derived for a full-size build: its bodies are up to a metre
    /// thick and it has no bed (a million millimetres stands for none); a thousandth of a millimetre
    /// and a kilometre still keep every product finite. Other settings keep their range.
    pub(crate) fn any_build(self) -> Range {
        match self.unit {
            "mm" => Range { lo: self.lo.min(1e-3), hi: 1e6, unit: self.unit },
            _ => self,
        }
    }

    /// What to say of a value `v` outside the range.
    fn words(&self, v: f64) -> String {
        let (lo, hi, unit) = (self.lo, self.hi, self.unit);
        let unit = if unit.is_empty() { String::new() } else { format!(" {unit}") };
        format!("is {}{unit}; use a number from {lo} to {hi}{unit}", number(v))
    }
}

/// `v` as a person reads it: in scientific notation when far from the settings' scale, so `1e308` is
/// not written out in 309 digits.
fn number(v: f64) -> String {
    if v != 0.0 && !(1e-3..1e6).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// A setting that cannot work, naming the field.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{field}: {message}")]
pub struct SettingsIssue {
    /// The setting, as a path (`bed.width`, `snap_cap.lip`).
    pub field: String,
    /// What is wrong with it and what to change.
    pub message: String,
}

impl PrintSettings {
    /// Parses settings from JSON text (missing fields keep their defaults).
    pub fn from_json(text: &str) -> Result<PrintSettings, SettingsIssue> {
        let de = &mut serde_json::Deserializer::from_str(text);
        serde_path_to_error::deserialize(de)
            .map_err(|e| SettingsIssue { field: e.path().to_string(), message: e.into_inner().to_string() })
    }

    /// Every setting that cannot work, each naming its field (empty when all is well): each within
    /// the range a printer makes, then the sizes that must fit one another.
    pub fn validate(&self) -> Vec<SettingsIssue> {
        self.check(Scope::Printer)
    }

    /// [`PrintSettings::validate`] for settings a full-size build derives from its own validated
    /// stock and bolts (bodies up to a metre thick, a bed without bounds): each within
    /// [`Range::any_build`], which keeps every volume, mass and coordinate finite.
    pub(crate) fn validate_any_build(&self) -> Vec<SettingsIssue> {
        self.check(Scope::AnyBuild)
    }

    /// Every value with its field, in the order of the format.
    fn values(&self) -> [(&'static str, f64); 18] {
        [
            ("link_width", self.link_width),
            ("link_thickness", self.link_thickness),
            ("axial_gap", self.axial_gap),
            ("radial_clearance", self.radial_clearance),
            ("pin_radius", self.pin_radius),
            ("snap_cap.height", self.snap_cap.height),
            ("snap_cap.lip", self.snap_cap.lip),
            ("snap_cap.tip_inset", self.snap_cap.tip_inset),
            ("body_thickness", self.body_thickness),
            ("connector_post", self.connector_post),
            ("wall", self.wall),
            ("bed.width", self.bed.width),
            ("bed.depth", self.bed.depth),
            ("bed.margin", self.bed.margin),
            ("bed.spacing", self.bed.spacing),
            ("density", self.density),
            ("fill_fraction", self.fill_fraction),
            ("circle_segments", self.circle_segments as f64),
        ]
    }

    fn check(&self, scope: Scope) -> Vec<SettingsIssue> {
        let mut out: Vec<SettingsIssue> = Vec::new();
        fn push(out: &mut Vec<SettingsIssue>, field: &str, message: String) {
            out.push(SettingsIssue { field: field.into(), message });
        }
        macro_rules! issue {
            ($f:expr, $m:expr $(,)?) => {
                push(&mut out, $f, $m)
            };
        }
        for (field, v) in self.values() {
            let range = Range::of(field);
            let range = match scope {
                Scope::Printer => range,
                Scope::AnyBuild => range.any_build(),
            };
            if !(v.is_finite() && range.lo <= v && v <= range.hi) {
                issue!(field, range.words(v));
            }
        }
        if !out.is_empty() {
            return out;
        }
        if self.snap_cap.tip_inset >= self.pin_radius {
            issue!("snap_cap.tip_inset", "must be smaller than pin_radius".into());
        }
        let d = Dims::new(self, 1.0);
        if 0.5 * self.link_width - self.wall < d.hole_radius + self.wall - 1e-12 {
            issue!(
                "link_width",
                format!(
                    "{} mm leaves no wall around a {} mm hole: it must be at least {:.2} mm",
                    self.link_width,
                    2.0 * d.hole_radius,
                    2.0 * (d.hole_radius + 2.0 * self.wall)
                ),
            );
        }
        if d.post_hole_circumradius + self.wall > d.half_width {
            issue!(
                "connector_post",
                format!("a {} mm post does not fit in a {} mm wide connector", self.connector_post, self.link_width),
            );
        }
        let usable = (self.bed.width - 2.0 * self.bed.margin).min(self.bed.depth - 2.0 * self.bed.margin);
        if usable < 4.0 * self.link_width {
            issue!("bed", "the bed minus its margins is too small for any part".into());
        }
        out
    }
}

/// The settings as the lengths geometry is built from, in scene units (every field derived from
/// [`PrintSettings`]; nothing here is chosen independently).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dims {
    /// Millimetres per scene unit.
    pub mm_per_unit: f64,
    /// Half the link width: the radius of every rounded end.
    pub half_width: f64,
    /// Link thickness LD.
    pub thickness: f64,
    /// Axial gap GP.
    pub gap: f64,
    /// Cap height JD.
    pub cap_height: f64,
    /// Layer pitch `LD + JD + 2 GP` (eq. 20 with Δz = 1 plus LD).
    pub pitch: f64,
    /// Radius of every pin.
    pub pin_radius: f64,
    /// Pin radius plus the radial clearance.
    pub hole_radius: f64,
    /// Radius of the bosses and collars that space stacked parts on a pin (the pin column).
    pub boss_radius: f64,
    /// Radius of the cap's base (wider than the hole by the lip).
    pub cap_base_radius: f64,
    /// Radius of the cap's tip.
    pub cap_tip_radius: f64,
    /// Half side of the square connector post.
    pub post_half: f64,
    /// Circumradius of the square socket of a connector (post plus clearance).
    pub post_hole_circumradius: f64,
    /// Radius of the round collar under a connector, around its post (the post column).
    pub post_collar_radius: f64,
    /// Half side of the post's cap base.
    pub post_cap_half: f64,
    /// Thickness of the extruded bodies.
    pub body_thickness: f64,
    /// Least material around any hole, post or pin base.
    pub wall: f64,
    /// Radial play between a pin and its hole, and a post and its socket.
    pub clearance: f64,
    /// Segments of a full circle in meshes and outlines.
    pub segments: usize,
}

impl Dims {
    /// The settings in a scene whose unit is `mm_per_unit` millimetres.
    pub fn new(s: &PrintSettings, mm_per_unit: f64) -> Dims {
        let u = 1.0 / mm_per_unit;
        let half_width = 0.5 * s.link_width;
        let hole_radius = s.pin_radius + s.radial_clearance;
        let boss_radius = (half_width - s.wall).max(hole_radius + s.wall);
        let post_half = 0.5 * s.connector_post;
        let post_hole_circumradius = (post_half + s.radial_clearance) * std::f64::consts::SQRT_2;
        Dims {
            mm_per_unit,
            half_width: half_width * u,
            thickness: s.link_thickness * u,
            gap: s.axial_gap * u,
            cap_height: s.snap_cap.height * u,
            pitch: (s.link_thickness + s.snap_cap.height + 2.0 * s.axial_gap) * u,
            pin_radius: s.pin_radius * u,
            hole_radius: hole_radius * u,
            boss_radius: boss_radius * u,
            cap_base_radius: (hole_radius + s.snap_cap.lip) * u,
            cap_tip_radius: (s.pin_radius - s.snap_cap.tip_inset) * u,
            post_half: post_half * u,
            post_hole_circumradius: post_hole_circumradius * u,
            post_collar_radius: (post_hole_circumradius + s.wall) * u,
            post_cap_half: (post_half + s.radial_clearance + s.snap_cap.lip) * u,
            body_thickness: s.body_thickness * u,
            wall: s.wall * u,
            clearance: s.radial_clearance * u,
            segments: s.circle_segments,
        }
    }

    /// The least distance between two joints of one link: two bosses side by side with a wall between.
    pub fn min_joint_spacing(&self) -> f64 {
        2.0 * self.boss_radius + self.wall
    }

    /// Bottom of a part on layer `k ≥ 1`, measured from the face of the bodies (paper eq. 20: two
    /// parts `Δz` layers apart are `Δz·(LD + JD + 2 GP) − LD` apart).
    pub fn layer_bottom(&self, k: u32) -> f64 {
        self.gap + f64::from(k.saturating_sub(1)) * self.pitch
    }
    /// Top of a part on layer `k`.
    pub fn layer_top(&self, k: u32) -> f64 {
        self.layer_bottom(k) + self.thickness
    }
    /// The room a counterbalance spring has around its axis: a spring is taken to be no wider than a
    /// link, so it has a link's half width.
    pub fn spring_radius(&self) -> f64 {
        self.half_width
    }
    /// Height of the axis of a spring at `level` (0 nearest) above a face with `layers` layers: beyond
    /// the snap caps of the outermost layer by the clearance and a spring's radius, and each level
    /// beyond the hook caps of the level below likewise.
    pub fn spring_axis(&self, layers: u32, level: u32) -> f64 {
        let top = if layers == 0 { 0.0 } else { self.layer_top(layers) };
        let first = top + self.gap + self.cap_height + self.gap + self.spring_radius();
        first + f64::from(level) * (self.thickness + self.cap_height + self.gap + 2.0 * self.spring_radius())
    }
    /// Height of the snap cap on the hooks of a spring at `level`: a part's thickness above the
    /// spring's axis, room for the spring's loop.
    pub fn hook_cap_base(&self, layers: u32, level: u32) -> f64 {
        self.spring_axis(layers, level) + self.thickness
    }
    /// Least distance from a joint of a link to a spring's hook on it (not on the joint): the joint's
    /// boss and the hook's cap side by side, with the radial clearance.
    pub fn hook_clear_of_joints(&self) -> f64 {
        self.boss_radius + self.cap_base_radius + self.clearance
    }
    /// Least depth inside a body for a pin fused to it (its collar and a wall).
    pub fn pin_depth(&self) -> f64 {
        self.boss_radius + self.wall
    }
    /// Least depth inside a body for a connector post (its collar and a wall).
    pub fn post_depth(&self) -> f64 {
        self.post_collar_radius + self.wall
    }
    /// Least depth inside a body too thin for [`Dims::post_depth`]: the collar within the radial
    /// clearance of the body's edge (a solid column fused on a solid slab needs no wall around it).
    pub fn post_flush_depth(&self) -> f64 {
        self.post_collar_radius + self.clearance
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_pins_have_the_set_clearance() {
        let s = PrintSettings::default();
        assert!(s.validate().is_empty(), "{:?}", s.validate());
        let d = Dims::new(&s, 1.0);
        assert!((d.hole_radius - d.pin_radius - 0.25).abs() < 1e-12);
        assert!((d.layer_bottom(2) - d.layer_top(1) - (1.6 + 0.6)).abs() < 1e-12);
    }

    #[test]
    fn unknown_and_bad_fields_are_named() {
        let e = PrintSettings::from_json(r#"{"pin_radus": 2}"#).unwrap_err();
        assert!(e.message.contains("pin_radus"), "{e}");
        let s = PrintSettings::from_json(r#"{"link_width": 3, "bed": {"width": 100}}"#).unwrap();
        assert_eq!(s.bed.depth, 220.0);
        assert!(s.validate().iter().any(|i| i.field == "link_width"));
    }

    /// The issues of the default settings with `json` merged in.
    fn issues_with(json: &str) -> Vec<SettingsIssue> {
        PrintSettings::from_json(json).unwrap().validate()
    }

    #[test]
    fn every_setting_is_bounded_and_its_refusal_names_it_with_its_unit_and_range() {
        let fields: Vec<&str> = PrintSettings::default().values().iter().map(|v| v.0).collect();
        for field in fields {
            let json = |v: &str| match field.split_once('.') {
                Some((outer, inner)) => format!(r#"{{"{outer}": {{"{inner}": {v}}}}}"#),
                None => format!(r#"{{"{field}": {v}}}"#),
            };
            let range = Range::of(field);
            for v in ["1e308", "-1", "5e-324"] {
                if field == "circle_segments" && v != "1e308" {
                    continue; // a count: negative and fractional numbers are refused as it is read
                }
                if v == "5e-324" && range.lo == 0.0 {
                    continue;
                }
                let Ok(s) = PrintSettings::from_json(&json(v)) else {
                    assert_eq!(field, "circle_segments", "{v}");
                    continue;
                };
                let issues = s.validate();
                let issue =
                    issues.iter().find(|i| i.field == field).unwrap_or_else(|| panic!("{field} {v}: {issues:?}"));
                let words = format!("use a number from {} to {}", range.lo, range.hi);
                assert!(issue.message.contains(&words) && issue.message.contains(range.unit), "{issue}");
            }
        }
    }

    #[test]
    fn huge_and_vanishing_sizes_are_refused_with_the_setting_named() {
        let issues = issues_with(r#"{"body_thickness": 1e308}"#);
        assert_eq!(issues.len(), 1, "{issues:?}");
        assert_eq!(issues[0].to_string(), "body_thickness: is 1e308 mm; use a number from 0.1 to 100 mm");
        let issues = issues_with(r#"{"body_thickness": 5e-324}"#);
        assert_eq!(issues[0].to_string(), "body_thickness: is 5e-324 mm; use a number from 0.1 to 100 mm");
        // Density is in grams per cubic centimetre, not millimetres.
        let issues = issues_with(r#"{"density": 1e308}"#);
        assert_eq!(issues[0].to_string(), "density: is 1e308 g/cm³; use a number from 0.05 to 25 g/cm³");
        assert!(issues_with(r#"{"density": 22.6, "body_thickness": 100, "fill_fraction": 1}"#).is_empty());
    }

    #[test]
    fn settings_a_full_size_build_derives_need_only_be_finite_sizes() {
        let mut s = PrintSettings { body_thickness: 400.0, ..PrintSettings::default() };
        s.bed = Bed { width: 1e6, depth: 1e6, margin: 0.0, spacing: 10.0 };
        assert_eq!(s.validate().len(), 3, "{:?}", s.validate());
        assert!(s.validate_any_build().is_empty(), "{:?}", s.validate_any_build());
        s.body_thickness = 1e308;
        assert_eq!(s.validate_any_build()[0].field, "body_thickness");
    }

    #[test]
    fn units_scale_the_parts() {
        let s = PrintSettings::default();
        let cm = Dims::new(&s, "cm".parse::<crate::Units>().unwrap().millimetres());
        assert!((cm.half_width - 0.5).abs() < 1e-12);
    }
}
