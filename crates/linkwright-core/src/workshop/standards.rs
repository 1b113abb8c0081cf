//! Standard parts and design values the workshop sizing reads, each with its source: metric bolts of
//! property class 8.8 and what goes with them, and per material its strengths, stiffness, the hole
//! distances it needs and the stock thicknesses it is sold in.

use crate::scene::Material;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// Ultimate tensile strength of a property class 8.8 bolt, MPa (ISO 898-1).
pub const BOLT_GRADE_ULTIMATE_MPA: f64 = 800.0;

/// Yield strength of a property class 8.8 bolt, MPa (ISO 898-1: 0.8 × 800), for its bending.
pub const BOLT_GRADE_YIELD_MPA: f64 = 640.0;

/// Shear strength of a bolt per shear plane as a fraction of its ultimate strength, on the tensile
/// stress area: α_v = 0.6 for class 8.8 with the thread in the shear plane (EN 1993-1-8 Table 3.4).
/// Taking the thread's area holds wherever the thread ends.
pub const BOLT_SHEAR_FRACTION: f64 = 0.6;

/// Bolt lengths stocked as standard (ISO 4014 / ISO 4017 preferred lengths), mm.
pub const BOLT_LENGTHS_MM: [f64; 29] = [
    16.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0, 55.0, 60.0, 65.0, 70.0, 75.0, 80.0, 90.0, 100.0, 110.0, 120.0,
    130.0, 140.0, 150.0, 160.0, 180.0, 200.0, 220.0, 240.0, 260.0, 280.0, 300.0,
];

/// A metric bolt size of the coarse-thread series.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum BoltSize {
    /// M5.
    M5,
    /// M6.
    M6,
    /// M8.
    M8,
    /// M10.
    M10,
    /// M12.
    M12,
    /// M16.
    M16,
    /// M20.
    M20,
    /// M24.
    M24,
}

/// One bolt size's standard dimensions, millimetres, and what comes with it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BoltSpec {
    /// The size (`M8`).
    pub size: BoltSize,
    /// Nominal diameter d.
    pub diameter_mm: f64,
    /// Thread pitch (coarse).
    pub pitch_mm: f64,
    /// Clearance hole d₀, ISO 273 medium series.
    pub hole_mm: f64,
    /// Tensile stress area A_s, mm² (ISO 898-1).
    pub stress_area_mm2: f64,
    /// Height of the hexagon head, ISO 4014.
    pub head_mm: f64,
    /// Plain washer ISO 7089: inner diameter.
    pub washer_inner_mm: f64,
    /// Plain washer ISO 7089: outer diameter.
    pub washer_outer_mm: f64,
    /// Plain washer ISO 7089: thickness (also the gap between two layers of links).
    pub washer_mm: f64,
    /// Height of the prevailing-torque (nylon insert) nut, ISO 10511.
    pub nut_mm: f64,
}

impl BoltSize {
    /// Every size, smallest first.
    pub const ALL: [BoltSize; 8] = [
        BoltSize::M5,
        BoltSize::M6,
        BoltSize::M8,
        BoltSize::M10,
        BoltSize::M12,
        BoltSize::M16,
        BoltSize::M20,
        BoltSize::M24,
    ];

    /// Its name (`M8`).
    pub fn name(self) -> &'static str {
        match self {
            BoltSize::M5 => "M5",
            BoltSize::M6 => "M6",
            BoltSize::M8 => "M8",
            BoltSize::M10 => "M10",
            BoltSize::M12 => "M12",
            BoltSize::M16 => "M16",
            BoltSize::M20 => "M20",
            BoltSize::M24 => "M24",
        }
    }

    /// The size called `name` (`M8` or `m8`), `None` for one not in [`BoltSize::ALL`].
    pub fn from_name(name: &str) -> Option<BoltSize> {
        BoltSize::ALL.into_iter().find(|s| s.name().eq_ignore_ascii_case(name.trim()))
    }

    /// Its standard dimensions.
    pub fn spec(self) -> BoltSpec {
        // d, pitch, ISO 273 medium hole, A_s, ISO 4014 head k, ISO 7089 d1 d2 h, ISO 10511 nut m.
        let (d, p, hole, area, head, [w1, w2, wh], nut) = match self {
            BoltSize::M5 => (5.0, 0.8, 5.5, 14.2, 3.5, [5.3, 10.0, 1.0], 5.0),
            BoltSize::M6 => (6.0, 1.0, 6.6, 20.1, 4.0, [6.4, 12.0, 1.6], 6.0),
            BoltSize::M8 => (8.0, 1.25, 9.0, 36.6, 5.3, [8.4, 16.0, 1.6], 8.0),
            BoltSize::M10 => (10.0, 1.5, 11.0, 58.0, 6.4, [10.5, 20.0, 2.0], 10.0),
            BoltSize::M12 => (12.0, 1.75, 13.5, 84.3, 7.5, [13.0, 24.0, 2.5], 12.0),
            BoltSize::M16 => (16.0, 2.0, 17.5, 157.0, 10.0, [17.0, 30.0, 3.0], 16.0),
            BoltSize::M20 => (20.0, 2.5, 22.0, 245.0, 12.5, [21.0, 37.0, 3.0], 20.0),
            BoltSize::M24 => (24.0, 3.0, 26.0, 353.0, 15.0, [25.0, 44.0, 4.0], 24.0),
        };
        BoltSpec {
            size: self,
            diameter_mm: d,
            pitch_mm: p,
            hole_mm: hole,
            stress_area_mm2: area,
            head_mm: head,
            washer_inner_mm: w1,
            washer_outer_mm: w2,
            washer_mm: wh,
            nut_mm: nut,
        }
    }
}

impl BoltSpec {
    /// The shear force one shear plane of the bolt carries at failure, N: `0.6 · f_ub · A_s`.
    pub fn shear_strength_n(&self) -> f64 {
        BOLT_SHEAR_FRACTION * BOLT_GRADE_ULTIMATE_MPA * self.stress_area_mm2
    }

    /// The tension the bolt holds at failure, N: `0.9 · f_ub · A_s` (EN 1993-1-8 Table 3.4, k₂ = 0.9).
    pub fn tension_strength_n(&self) -> f64 {
        0.9 * BOLT_GRADE_ULTIMATE_MPA * self.stress_area_mm2
    }

    /// The bending moment at which the bolt's thread core yields, N·m: `f_yb · π d_s³ / 32`, d_s the
    /// diameter of the tensile stress area (the elastic modulus only, without the 1.5 shape factor
    /// EN 1993-1-8 Table 3.10 allows a pin).
    pub fn bending_strength_nm(&self) -> f64 {
        let core = (4.0 * self.stress_area_mm2 / std::f64::consts::PI).sqrt();
        BOLT_GRADE_YIELD_MPA * std::f64::consts::PI * core.powi(3) / 32.0 / 1000.0
    }

    /// The shortest standard length at least `needed_mm` long; beyond the longest standard bolt,
    /// `needed_mm` rounded up to 10 mm (threaded rod cut to length).
    pub fn standard_length(needed_mm: f64) -> f64 {
        BOLT_LENGTHS_MM.into_iter().find(|&l| l >= needed_mm - 1e-9).unwrap_or((needed_mm / 10.0).ceil() * 10.0)
    }
}

impl std::fmt::Display for BoltSize {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl Serialize for BoltSize {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for BoltSize {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<BoltSize, D::Error> {
        let text = String::deserialize(d)?;
        BoltSize::from_name(&text).ok_or_else(|| {
            let names: Vec<&str> = BoltSize::ALL.iter().map(|s| s.name()).collect();
            serde::de::Error::custom(format!("unknown bolt size \"{text}\"; use one of {}", names.join(", ")))
        })
    }
}

/// A workshop material's design values: characteristic strengths (5th percentile or guaranteed
/// minimum) and a mean stiffness, the distances holes need, and the stock thicknesses. The safety
/// factor of [`crate::workshop::WorkshopSettings`] is applied to the loads, never folded in here.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MaterialValues {
    /// The material.
    pub material: Material,
    /// Tension strength, MPa (net section at a hole).
    pub tension_mpa: f64,
    /// Compression strength, MPa.
    pub compression_mpa: f64,
    /// Modulus of elasticity, MPa (Euler buckling).
    pub modulus_mpa: f64,
    /// Density, kg/m³ (the links' weight).
    pub density_kg_m3: f64,
    /// Where each value comes from.
    pub sources: &'static str,
    /// Least distance from a hole's centre to any edge of the part, in bolt diameters d
    /// (`edge_per_d`) plus clearance-hole diameters d₀ (`edge_per_hole`).
    pub edge_per_d: f64,
    /// See `edge_per_d`.
    pub edge_per_hole: f64,
    /// Least distance between the centres of two fixing bolts, in d (`spacing_per_d`) plus d₀
    /// (`spacing_per_hole`).
    pub spacing_per_d: f64,
    /// See `spacing_per_d`.
    pub spacing_per_hole: f64,
    /// A link is at most this many times as wide as thick: wider, it is a panel rather than a bar,
    /// so the next stock thickness is taken instead.
    pub max_width_per_thickness: f64,
    /// The stock thicknesses, mm, thinnest first.
    pub thicknesses_mm: &'static [f64],
}

/// Characteristic density of birch plywood, kg/m³, for its embedment strength (EN 1995-1-1 eq. 8.20).
const PLYWOOD_CHARACTERISTIC_DENSITY: f64 = 630.0;

impl MaterialValues {
    /// The values for `material`.
    pub fn of(material: Material) -> MaterialValues {
        const SHEET_METAL: &[f64] = &[2.0, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0, 15.0, 20.0, 25.0];
        match material {
            // Both directions of the face grain: a link may be cut either way on the sheet.
            Material::Plywood => MaterialValues {
                material,
                tension_mpa: 30.0,
                compression_mpa: 25.0,
                modulus_mpa: 7_000.0,
                density_kg_m3: material.density_kg_m3(),
                sources: "birch plywood, characteristic values in the weaker of the two grain directions, rounded \
                          down from the Handbook of Finnish Plywood (tension 30, compression 25, E 7000 MPa); \
                          embedment of a bolt EN 1995-1-1 eq. 8.20 with a characteristic density of 630 kg/m³; \
                          edge and end distance 3 d and bolt spacing 4 d after EN 1995-1-1 Table 8.4 (bolts)",
                edge_per_d: 3.0,
                edge_per_hole: 0.0,
                spacing_per_d: 4.0,
                spacing_per_hole: 0.0,
                max_width_per_thickness: 6.0,
                thicknesses_mm: &[6.0, 9.0, 12.0, 15.0, 18.0, 21.0, 24.0, 27.0, 30.0],
            },
            Material::Aluminium => MaterialValues {
                material,
                tension_mpa: 240.0,
                compression_mpa: 240.0,
                modulus_mpa: 70_000.0,
                density_kg_m3: material.density_kg_m3(),
                sources: "6061-T6 plate: 0.2% proof strength 240 MPa (EN 485-2 minimum), E 70000 MPa (EN 1999-1-1 \
                          3.2.5); bearing of a pin 1.5 f_y (EN 1993-1-8 Table 3.10, pins); edge distance 1.2 d0 and \
                          bolt spacing 2.2 d0 (EN 1993-1-8 Table 3.3)",
                edge_per_d: 0.0,
                edge_per_hole: 1.2,
                spacing_per_d: 0.0,
                spacing_per_hole: 2.2,
                max_width_per_thickness: 12.0,
                thicknesses_mm: SHEET_METAL,
            },
            Material::Steel => MaterialValues {
                material,
                tension_mpa: 235.0,
                compression_mpa: 235.0,
                modulus_mpa: 210_000.0,
                density_kg_m3: material.density_kg_m3(),
                sources: "S235 plate: yield strength 235 MPa (EN 10025-2), E 210000 MPa (EN 1993-1-1 3.2.6); \
                          bearing of a pin 1.5 f_y (EN 1993-1-8 Table 3.10, pins); edge distance 1.2 d0 and bolt \
                          spacing 2.2 d0 (EN 1993-1-8 Table 3.3)",
                edge_per_d: 0.0,
                edge_per_hole: 1.2,
                spacing_per_d: 0.0,
                spacing_per_hole: 2.2,
                max_width_per_thickness: 12.0,
                thicknesses_mm: SHEET_METAL,
            },
        }
    }

    /// The bearing strength of the material under a bolt, MPa: the embedment strength
    /// `0.11 (1 − 0.01 d) ρ_k` for plywood (EN 1995-1-1 eq. 8.20), `1.5 f_y` for the metals (a pin
    /// in a plate, EN 1993-1-8 Table 3.10).
    pub fn bearing_mpa(&self, bolt: &BoltSpec) -> f64 {
        match self.material {
            Material::Plywood => 0.11 * (1.0 - 0.01 * bolt.diameter_mm) * PLYWOOD_CHARACTERISTIC_DENSITY,
            Material::Aluminium | Material::Steel => 1.5 * self.tension_mpa,
        }
    }

    /// Least distance from a hole's centre to an edge, mm.
    pub fn edge_mm(&self, bolt: &BoltSpec) -> f64 {
        self.edge_per_d * bolt.diameter_mm + self.edge_per_hole * bolt.hole_mm
    }

    /// Least distance between two fixing bolts' centres, mm.
    pub fn spacing_mm(&self, bolt: &BoltSpec) -> f64 {
        self.spacing_per_d * bolt.diameter_mm + self.spacing_per_hole * bolt.hole_mm
    }

    /// The narrowest link around a hole: its centre an edge distance from both sides, and never
    /// under 2.5 d.
    pub fn min_width_mm(&self, bolt: &BoltSpec) -> f64 {
        (2.0 * self.edge_mm(bolt)).max(2.5 * bolt.diameter_mm)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_back_and_grow() {
        for pair in BoltSize::ALL.windows(2) {
            let (a, b) = (pair[0].spec(), pair[1].spec());
            assert!(a.diameter_mm < b.diameter_mm && a.hole_mm < b.hole_mm && a.stress_area_mm2 < b.stress_area_mm2);
            // Every clearance hole passes the bolt, and every washer's hole passes the bolt.
            assert!(a.hole_mm > a.diameter_mm && a.washer_inner_mm > a.diameter_mm && a.washer_outer_mm > a.hole_mm);
        }
        for size in BoltSize::ALL {
            assert_eq!(BoltSize::from_name(&size.name().to_lowercase()), Some(size));
            let json = serde_json::to_string(&size).unwrap();
            assert_eq!(serde_json::from_str::<BoltSize>(&json).unwrap(), size);
        }
        assert!(serde_json::from_str::<BoltSize>("\"M7\"").unwrap_err().to_string().contains("M8"));
        assert_eq!(BoltSpec::standard_length(61.0), 65.0);
        assert_eq!(BoltSpec::standard_length(65.0), 65.0);
        assert_eq!(BoltSpec::standard_length(301.0), 310.0);
    }

    #[test]
    fn plywood_embedment_is_eurocode_5() {
        let ply = MaterialValues::of(Material::Plywood);
        let m8 = BoltSize::M8.spec();
        assert!((ply.bearing_mpa(&m8) - 0.11 * 0.92 * 630.0).abs() < 1e-12);
        assert_eq!(ply.min_width_mm(&m8), 48.0);
        let steel = MaterialValues::of(Material::Steel);
        assert!((steel.min_width_mm(&m8) - 21.6).abs() < 1e-12);
        assert!((BoltSize::M8.spec().shear_strength_n() - 0.6 * 800.0 * 36.6).abs() < 1e-9);
    }
}
