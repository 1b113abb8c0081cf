//! How the drawn object is to be built: the scene is the real object, and the build is a separate
//! choice, a printed model at some scale or the object at full size in a workshop material. Written
//! the same way in scene files, design files, the command line and the HTTP API:
//! `model:auto`, `model:1:10`, `model:2:1`, `full:plywood`.

use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// The largest number on either side of a model scale (`1:10000`, `10000:1`).
pub const MAX_RATIO_TERM: u32 = 10_000;

/// A model's scale: `model` units of the model for `object` units of the real object (1:10 is one
/// tenth of the object's size, 2:1 twice it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Ratio {
    /// The model's side of the ratio.
    pub model: u32,
    /// The object's side of the ratio.
    pub object: u32,
}

impl Ratio {
    /// Full scale, 1:1.
    pub const ONE: Ratio = Ratio { model: 1, object: 1 };

    /// The model's length per length of the object (0.1 for 1:10).
    pub fn factor(self) -> f64 {
        f64::from(self.model) / f64::from(self.object)
    }

    /// The 1-2-5 series from 10000:1 down to 1:10000, largest first: the scales a model is chosen
    /// from when its scale is `auto`. The series is closed under a factor of 10 within its range, so
    /// a drawing ten times as large gets a scale exactly ten times as small and the same model.
    pub fn series() -> Vec<Ratio> {
        // 1, 2, 5, 10, 20, ... up to the largest term.
        let terms: Vec<u32> = (0..)
            .map(|k| 10u32.pow(k))
            .take_while(|&decade| decade <= MAX_RATIO_TERM)
            .flat_map(|decade| [decade, 2 * decade, 5 * decade])
            .filter(|&t| t <= MAX_RATIO_TERM)
            .collect();
        let up = terms.iter().rev().filter(|&&t| t > 1).map(|&model| Ratio { model, object: 1 });
        let down = terms.iter().map(|&object| Ratio { model: 1, object });
        up.chain(down).collect()
    }
}

impl fmt::Display for Ratio {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.model, self.object)
    }
}

/// The scale of a printed model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum ModelScale {
    /// 1:1 when the links fit the print bed and the pins fit the links, else the largest scale of
    /// [`Ratio::series`] at which they do, chosen from the drawing before the search (fabrication
    /// decides it).
    #[default]
    Auto,
    /// A scale the person chose.
    Fixed(Ratio),
}

/// A workshop material for a full-size build.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Material {
    /// Birch plywood (links cut by laser or CNC router).
    Plywood,
    /// Aluminium plate (6061-T6).
    Aluminium,
    /// Mild steel plate (S235).
    Steel,
}

impl Material {
    /// Every material, in the order the app lists them.
    pub const ALL: [Material; 3] = [Material::Plywood, Material::Aluminium, Material::Steel];

    /// The word files use for it.
    pub fn id(self) -> &'static str {
        match self {
            Material::Plywood => "plywood",
            Material::Aluminium => "aluminium",
            Material::Steel => "steel",
        }
    }

    /// The material for a word (`aluminum` too), `None` for one this version does not know.
    pub fn from_id(word: &str) -> Option<Material> {
        match word {
            "plywood" => Some(Material::Plywood),
            "aluminium" | "aluminum" => Some(Material::Aluminium),
            "steel" => Some(Material::Steel),
            _ => None,
        }
    }

    /// Density, kg/m³ (birch plywood about 680, 6061 aluminium 2,700, mild steel 7,850).
    pub fn density_kg_m3(self) -> f64 {
        match self {
            Material::Plywood => 680.0,
            Material::Aluminium => 2_700.0,
            Material::Steel => 7_850.0,
        }
    }
}

/// How the drawn object is to be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Build {
    /// A 3D-printed model at a scale (the default: `model:auto`); the synthesis only offers linkages
    /// the model can be printed with.
    Model(ModelScale),
    /// The object at its real size in a workshop material: no print check, and fabrication writes
    /// what a workshop needs.
    Full(Material),
}

impl Default for Build {
    fn default() -> Self {
        Build::Model(ModelScale::Auto)
    }
}

/// Why a build's text cannot be read.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("\"{text}\" is not a build: {why}; write model:auto, model:1:10 (any scale a:b), or full:plywood, full:aluminium or full:steel")]
pub struct BuildParseError {
    /// The text given.
    pub text: String,
    /// What is wrong with it.
    pub why: String,
}

impl std::str::FromStr for Build {
    type Err = BuildParseError;

    fn from_str(text: &str) -> Result<Build, BuildParseError> {
        let fail = |why: &str| BuildParseError { text: text.chars().take(64).collect(), why: why.into() };
        let lower = text.trim().to_ascii_lowercase();
        let (kind, rest) = lower.split_once(':').unwrap_or((lower.as_str(), ""));
        match kind {
            "model" => match rest {
                "" | "auto" => Ok(Build::Model(ModelScale::Auto)),
                ratio => {
                    let (a, b) = ratio.split_once(':').ok_or_else(|| fail("a model's scale is a:b, such as 1:10"))?;
                    let term = |s: &str| s.trim().parse::<u32>().ok().filter(|&n| (1..=MAX_RATIO_TERM).contains(&n));
                    match (term(a), term(b)) {
                        (Some(model), Some(object)) => Ok(Build::Model(ModelScale::Fixed(Ratio { model, object }))),
                        _ => Err(fail(&format!("both sides of a scale are whole numbers from 1 to {MAX_RATIO_TERM}"))),
                    }
                }
            },
            "full" => match rest {
                "" => Ok(Build::Full(Material::Plywood)),
                word => Material::from_id(word).map(Build::Full).ok_or_else(|| fail("unknown material")),
            },
            _ => Err(fail("it starts with neither model nor full")),
        }
    }
}

impl fmt::Display for Build {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Build::Model(ModelScale::Auto) => write!(f, "model:auto"),
            Build::Model(ModelScale::Fixed(r)) => write!(f, "model:{r}"),
            Build::Full(m) => write!(f, "full:{}", m.id()),
        }
    }
}

impl Serialize for Material {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.id())
    }
}

impl<'de> Deserialize<'de> for Material {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Material, D::Error> {
        let text = String::deserialize(d)?;
        Material::from_id(&text.to_ascii_lowercase()).ok_or_else(|| {
            serde::de::Error::custom(format!("unknown material \"{text}\"; use plywood, aluminium or steel"))
        })
    }
}

impl Serialize for Build {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl<'de> Deserialize<'de> for Build {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Build, D::Error> {
        let text = String::deserialize(d)?;
        text.parse().map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builds_read_and_write_as_the_format_says() {
        for text in ["model:auto", "model:1:10", "model:2:1", "full:plywood", "full:aluminium", "full:steel"] {
            let build: Build = text.parse().unwrap();
            assert_eq!(build.to_string(), text);
            assert_eq!(serde_json::to_value(build).unwrap(), serde_json::Value::String(text.into()));
        }
        assert_eq!("model".parse::<Build>().unwrap(), Build::default());
        assert_eq!("Full:Aluminum".parse::<Build>().unwrap(), Build::Full(Material::Aluminium));
        for bad in ["", "print", "model:1", "model:0:1", "model:1:100000", "full:wood", "model:a:b"] {
            let e = bad.parse::<Build>().unwrap_err();
            assert!(e.to_string().contains("model:auto"), "{e}");
        }
    }

    #[test]
    fn the_series_is_one_two_five_and_closed_under_ten() {
        let s = Ratio::series();
        assert_eq!(s.first(), Some(&Ratio { model: 10_000, object: 1 }));
        assert_eq!(s.len(), 2 * 12 + 1, "1, 2 and 5 a decade up to 10000 each way, and 1:1 once");
        assert_eq!(s.last(), Some(&Ratio { model: 1, object: 10_000 }));
        assert!(s.windows(2).all(|w| w[0].factor() > w[1].factor()));
        assert!(s.contains(&Ratio::ONE) && s.contains(&Ratio { model: 1, object: 5 }));
        // Every scale ten times smaller than one in the series is in it, within its range.
        for r in &s {
            let smaller = r.factor() / 10.0;
            if smaller >= 1.0 / f64::from(MAX_RATIO_TERM) {
                assert!(s.iter().any(|q| (q.factor() / smaller - 1.0).abs() < 1e-12), "{r}");
            }
        }
    }
}
