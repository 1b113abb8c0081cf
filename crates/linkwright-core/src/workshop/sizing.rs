//! The strength rule: a flat part's stock thickness and width from its peak loads. Every inequality
//! compares the peak load times the safety factor S with what the section holds at the material's
//! characteristic strength ([`super::MaterialValues`]); d is the bolt's diameter, d₀ its clearance hole,
//! w the part's width and t its thickness:
//!
//! - bearing of the bolt on the part: `S F ≤ f_b d t` for the largest force at any of its holes;
//! - tension across the hole (net section): `S T ≤ f_t (w − d₀) t`;
//! - compression across the hole: `S C ≤ f_c (w − d₀) t`, and Euler buckling between the pivots
//!   (pinned at both ends, about the weaker axis): `S C ≤ π² E min(w t³, t w³) / (12 L²)`;
//! - edge distance: `w ≥ max(2 e, 2.5 d)`, e the material's least distance from a hole's centre to an
//!   edge (the ends are rounded to w/2 around the holes, so the end distance is the same);
//! - bending where a moment is carried (the crank held at its pivot, a bracket at its fixing bolts):
//!   `S (N / A_net + M / Z_net) ≤ min(f_t, f_c)` on the section through the hole(s);
//! - a bracket's two fixing bolts, across it at its post, each an edge distance from a side, so
//!   `s = w − 2 e` apart (at least the material's bolt spacing): each takes at most
//!   `V = R/2 + M/s` (R the resultant, M the moment about the post), with `S V` under the bolt's
//!   shear strength (`0.6 f_ub A_s`, class 8.8) and under its bearing on the bracket.
//!
//! The thickness is the thinnest stock for which bearing holds and the width the other inequalities
//! need (rounded up to a whole millimetre) is at most the material's width-to-thickness limit.

use super::standards::{BoltSpec, MaterialValues};
use serde::Serialize;
use std::f64::consts::PI;

/// One inequality of the strength rule, with both of its sides.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Check {
    /// What is checked: `bearing`, `net tension p1–q1`, `buckling p1–q1`, `edge distance`, ...
    pub rule: String,
    /// The load side (the safety factor applied), in `unit`.
    pub demand: f64,
    /// What the part holds, in `unit`.
    pub capacity: f64,
    /// `N`, `MPa` or `mm`.
    pub unit: &'static str,
    /// Whether `demand ≤ capacity`.
    pub ok: bool,
}

impl Check {
    pub(crate) fn new(rule: impl Into<String>, demand: f64, capacity: f64, unit: &'static str) -> Check {
        // A hair of slack for the rounding of values written back and forth.
        Check { rule: rule.into(), demand, capacity, unit, ok: demand <= capacity * (1.0 + 1e-9) + 1e-9 }
    }
}

/// The peak axial loads between two holes of a part.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct EdgeLoad {
    /// The two joints' names, `a–b`.
    pub label: String,
    /// Pivot-to-pivot length, mm.
    pub length_mm: f64,
    /// The largest tension, N (0 when never pulled).
    pub tension_n: f64,
    /// The largest compression, N (0 when never pushed).
    pub compression_n: f64,
}

/// A moment carried across the section through one or two holes.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Bending {
    /// The largest moment, N·m.
    pub moment_nm: f64,
    /// The largest force along (or on) the part at that section, N.
    pub axial_n: f64,
    /// Whether the section holds two fixing bolts across it, each an edge distance from a side (a
    /// bracket at its post); otherwise one hole on the centre line (the crank at its pivot).
    pub fixing: bool,
}

/// Everything one part must carry: peaks over the motion.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Demand {
    /// Axial loads between its holes.
    pub edges: Vec<EdgeLoad>,
    /// The largest force at any of its joint holes, N.
    pub hole_n: f64,
    /// A moment it carries, if any.
    pub bending: Option<Bending>,
}

impl Demand {
    /// The larger of the two, load by load (the sizing keeps every load it has seen).
    pub(crate) fn max(&self, other: &Demand) -> Demand {
        let edges = self
            .edges
            .iter()
            .map(|e| match other.edges.iter().find(|o| o.label == e.label) {
                Some(o) => EdgeLoad {
                    tension_n: e.tension_n.max(o.tension_n),
                    compression_n: e.compression_n.max(o.compression_n),
                    ..e.clone()
                },
                None => e.clone(),
            })
            .collect();
        let bending = match (&self.bending, &other.bending) {
            (Some(a), Some(b)) => Some(Bending {
                moment_nm: a.moment_nm.max(b.moment_nm),
                axial_n: a.axial_n.max(b.axial_n),
                fixing: a.fixing,
            }),
            (a, b) => a.clone().or_else(|| b.clone()),
        };
        Demand { edges, hole_n: self.hole_n.max(other.hole_n), bending }
    }
}

/// A chosen section and every inequality it was checked against.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Section {
    /// Width, mm.
    pub width_mm: f64,
    /// Stock thickness, mm.
    pub thickness_mm: f64,
    /// Every inequality at this width and thickness.
    pub checks: Vec<Check>,
    /// Why the next thinner stock would not do (none for the thinnest).
    pub thinner_fails: Option<String>,
}

/// What width a thickness needs.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Need {
    /// The bolt's bearing fails at this thickness, whatever the width.
    Bearing,
    /// This width (unrounded), mm; infinite when no width will do.
    Width(f64),
}

/// The material, bolts and factor a part is sized with.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Rule<'a> {
    pub values: &'a MaterialValues,
    /// The bolt of the joints (the part's joint holes).
    pub bolt: &'a BoltSpec,
    /// The bolt fixing a bracket to its body (the joints' for every other part).
    pub fixing: &'a BoltSpec,
    pub factor: f64,
}

impl Rule<'_> {
    /// The least width any part around a hole has (and a bracket's fixing bolts need), mm.
    fn min_width(&self, demand: &Demand) -> f64 {
        let around_hole = self.values.min_width_mm(self.bolt);
        match &demand.bending {
            Some(b) if b.fixing => {
                around_hole.max(self.values.spacing_mm(self.bolt) + 2.0 * self.values.edge_mm(self.bolt))
            }
            _ => around_hole,
        }
    }

    /// The distance between a bracket's two fixing bolts in a bracket `w` wide: each an edge
    /// distance from its side, as far apart as the width allows (the farther, the less the moment
    /// loads them).
    pub(crate) fn fixing_spacing(&self, w: f64) -> f64 {
        w - 2.0 * self.values.edge_mm(self.fixing)
    }

    /// The shear on each of a bracket's two fixing bolts in a bracket `w` wide, N (no safety factor):
    /// half the force, and the moment over their spacing.
    pub(crate) fn fixing_shear(&self, b: &Bending, w: f64) -> f64 {
        0.5 * b.axial_n + b.moment_nm * 1000.0 / self.fixing_spacing(w).max(1e-9)
    }

    /// The combined stress of a bending section `w` wide, `t` thick, MPa (the safety factor applied).
    fn bending_stress(&self, b: &Bending, w: f64, t: f64) -> f64 {
        let (area, inertia) = if b.fixing {
            let d0 = self.fixing.hole_mm;
            let s = self.fixing_spacing(w);
            ((w - 2.0 * d0) * t, t * w.powi(3) / 12.0 - 2.0 * (t * d0.powi(3) / 12.0 + t * d0 * (0.5 * s).powi(2)))
        } else {
            let d0 = self.bolt.hole_mm;
            ((w - d0) * t, t * (w.powi(3) - d0.powi(3)) / 12.0)
        };
        if area <= 0.0 || inertia <= 0.0 {
            return f64::INFINITY;
        }
        self.factor * (b.axial_n / area + b.moment_nm * 1000.0 / (inertia / (0.5 * w)))
    }

    /// The bearing `bolt` has in `t` of the material, N.
    fn bearing_of(&self, bolt: &BoltSpec, t: f64) -> f64 {
        self.values.bearing_mpa(bolt) * bolt.diameter_mm * t
    }

    /// The bearing a joint's bolt has in `t` of the material, N.
    fn bearing(&self, t: f64) -> f64 {
        self.bearing_of(self.bolt, t)
    }

    /// Whether the inequalities that depend on the width in other ways than a bound (bending, a
    /// bracket's fixing bolts) hold at width `w` and thickness `t`.
    fn wide_enough(&self, demand: &Demand, w: f64, t: f64) -> bool {
        let Some(b) = &demand.bending else { return true };
        let s = self.factor;
        let bending = self.bending_stress(b, w, t) <= self.values.tension_mpa.min(self.values.compression_mpa);
        if !b.fixing {
            return bending;
        }
        let shear = s * self.fixing_shear(b, w);
        bending && shear <= self.fixing.shear_strength_n() && shear <= self.bearing_of(self.fixing, t)
    }

    /// The width `demand` needs at thickness `t`.
    fn width_needed(&self, demand: &Demand, t: f64) -> Need {
        let (v, bolt, s) = (self.values, self.bolt, self.factor);
        if s * demand.hole_n > self.bearing(t) {
            return Need::Bearing;
        }
        let d0 = bolt.hole_mm;
        let mut w = self.min_width(demand);
        for e in &demand.edges {
            w = w.max(d0 + s * e.tension_n / (v.tension_mpa * t));
            w = w.max(d0 + s * e.compression_n / (v.compression_mpa * t));
            // min(w t³, t w³) ≥ X: both terms grow with w.
            let x = 12.0 * s * e.compression_n * e.length_mm.powi(2) / (PI * PI * v.modulus_mpa);
            w = w.max(x / t.powi(3)).max((x / t).cbrt());
        }
        if self.wide_enough(demand, w, t) {
            return Need::Width(w);
        }
        // Widening helps (bending falls as w², a bracket's bolts spread apart); how far is found by
        // doubling, then bisection.
        let mut hi = 2.0 * w;
        while !self.wide_enough(demand, hi, t) {
            hi *= 2.0;
            if hi > 1e6 {
                return Need::Width(f64::INFINITY);
            }
        }
        let mut lo = w;
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if self.wide_enough(demand, mid, t) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        Need::Width(hi)
    }

    /// Every inequality at width `w` and thickness `t`.
    pub(crate) fn checks(&self, demand: &Demand, w: f64, t: f64) -> Vec<Check> {
        let (v, bolt, s) = (self.values, self.bolt, self.factor);
        let d0 = bolt.hole_mm;
        let mut out = vec![
            Check::new("bearing", s * demand.hole_n, self.bearing(t), "N"),
            Check::new("edge distance", self.min_width(demand), w, "mm"),
        ];
        for e in &demand.edges {
            out.push(Check::new(
                format!("net tension {}", e.label),
                s * e.tension_n,
                v.tension_mpa * (w - d0) * t,
                "N",
            ));
            out.push(Check::new(
                format!("compression {}", e.label),
                s * e.compression_n,
                v.compression_mpa * (w - d0) * t,
                "N",
            ));
            let inertia = (w * t.powi(3)).min(t * w.powi(3)) / 12.0;
            out.push(Check::new(
                format!("buckling {}", e.label),
                s * e.compression_n,
                PI * PI * v.modulus_mpa * inertia / e.length_mm.powi(2),
                "N",
            ));
        }
        if let Some(b) = &demand.bending {
            out.push(Check::new("bending", self.bending_stress(b, w, t), v.tension_mpa.min(v.compression_mpa), "MPa"));
            if b.fixing {
                let shear = s * self.fixing_shear(b, w);
                out.push(Check::new("fixing bolt shear", shear, self.fixing.shear_strength_n(), "N"));
                out.push(Check::new("fixing bolt bearing", shear, self.bearing_of(self.fixing, t), "N"));
            }
        }
        out.push(Check::new("width to thickness", w, v.max_width_per_thickness * t, "mm"));
        out
    }

    /// The thinnest stock (and the width it needs) on which every inequality holds; when none does,
    /// the thickest stock at the width it needs, or at its width-to-thickness limit when no width
    /// will do (its failing checks say what is short).
    pub(crate) fn size(&self, demand: &Demand) -> Section {
        let v = self.values;
        let stocks = v.thicknesses_mm;
        let mut why_not: Option<String> = None;
        for &t in stocks {
            let cap = v.max_width_per_thickness * t;
            match self.width_needed(demand, t) {
                Need::Width(w) if w.ceil() <= cap => {
                    let width = w.ceil();
                    return Section {
                        width_mm: width,
                        thickness_mm: t,
                        checks: self.checks(demand, width, t),
                        thinner_fails: why_not,
                    };
                }
                Need::Width(w) if w.is_finite() => {
                    why_not = Some(format!(
                        "{t} mm would need a width of {:.0} mm, more than {} times its thickness",
                        w.ceil(),
                        v.max_width_per_thickness
                    ))
                }
                Need::Width(_) => {
                    why_not = Some(format!("{t} mm: no width carries the bracket's fixing bolts' shear"));
                }
                Need::Bearing => {
                    why_not = Some(format!(
                        "{t} mm is too thin for the bolt's bearing ({:.0} N with the safety factor, {:.0} N held)",
                        self.factor * demand.hole_n,
                        self.bearing(t)
                    ))
                }
            }
        }
        let t = stocks[stocks.len() - 1];
        let cap = v.max_width_per_thickness * t;
        let width = match self.width_needed(demand, t) {
            Need::Width(w) if w.is_finite() => w.ceil(),
            _ => cap.max(self.min_width(demand)).ceil(),
        };
        let thinner = stocks.len().checked_sub(2).map(|k| format!("{} mm is thinner still", stocks[k]));
        Section { width_mm: width, thickness_mm: t, checks: self.checks(demand, width, t), thinner_fails: thinner }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Material;
    use crate::workshop::standards::BoltSize;

    fn rule<'a>(values: &'a MaterialValues, bolt: &'a BoltSpec) -> Rule<'a> {
        Rule { values, bolt, fixing: bolt, factor: 3.0 }
    }

    /// Every chosen section passes its checks and sits exactly at the thinnest stock that does.
    #[test]
    fn sections_pass_and_thinner_stock_fails() {
        let bolt = BoltSize::M8.spec();
        for material in Material::ALL {
            let values = MaterialValues::of(material);
            let r = rule(&values, &bolt);
            for load in [0.0, 500.0, 2_000.0, 8_000.0] {
                for length in [100.0, 600.0, 1500.0] {
                    let demand = Demand {
                        edges: vec![EdgeLoad {
                            label: "a–b".into(),
                            length_mm: length,
                            tension_n: load,
                            compression_n: load,
                        }],
                        hole_n: load,
                        bending: None,
                    };
                    let section = r.size(&demand);
                    let k = values.thicknesses_mm.iter().position(|&t| t == section.thickness_mm).unwrap();
                    if section.checks.iter().all(|c| c.ok) {
                        if k > 0 {
                            let thinner = values.thicknesses_mm[k - 1];
                            match r.width_needed(&demand, thinner) {
                                Need::Bearing => {}
                                Need::Width(w) => assert!(
                                    w.ceil() > values.max_width_per_thickness * thinner,
                                    "{material:?} {load} {length}"
                                ),
                            }
                            assert!(section.thinner_fails.is_some());
                        }
                        // One millimetre narrower fails something, unless the width is the edge minimum.
                        let narrower = r.checks(&demand, section.width_mm - 1.0, section.thickness_mm);
                        assert!(narrower.iter().any(|c| !c.ok), "{material:?} {load} {length}: {section:?}");
                    } else {
                        assert_eq!(k, values.thicknesses_mm.len() - 1);
                    }
                }
            }
        }
    }

    #[test]
    fn bending_needs_width_and_brackets_need_room_for_two_bolts() {
        let bolt = BoltSize::M10.spec();
        let values = MaterialValues::of(Material::Steel);
        let r = rule(&values, &bolt);
        let bending = Bending { moment_nm: 200.0, axial_n: 1000.0, fixing: true };
        let demand = Demand { edges: Vec::new(), hole_n: 1000.0, bending: Some(bending.clone()) };
        let section = r.size(&demand);
        assert!(section.checks.iter().all(|c| c.ok), "{section:?}");
        let spacing = r.fixing_spacing(section.width_mm);
        assert!(spacing >= values.spacing_mm(&bolt));
        let stress = r.bending_stress(&bending, section.width_mm, section.thickness_mm);
        assert!(stress <= values.tension_mpa);
        // A millimetre narrower, the fixing bolts or the bending fail.
        assert!(r.checks(&demand, section.width_mm - 1.0, section.thickness_mm).iter().any(|c| !c.ok));
    }
}
