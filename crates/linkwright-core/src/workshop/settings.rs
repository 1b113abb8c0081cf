//! Workshop settings: what a person may choose about a full-size build, every field defaulted, read
//! from JSON with path-aware errors and validated field by field.

use super::standards::BoltSize;
use crate::balance::{Balance, Spring};
use crate::fab::SettingsIssue;
use serde::{Deserialize, Serialize};

/// A counterbalance spring to buy, as the spring search (or the person) chose it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpringOrder {
    /// Spring rate, N/mm.
    pub rate_n_per_mm: f64,
    /// Free length between the hooks, mm.
    pub free_length_mm: f64,
    /// How many of this spring.
    #[serde(default = "one")]
    pub count: u32,
}

fn one() -> u32 {
    1
}

impl SpringOrder {
    /// The extension springs of `balance` as a workshop orders them, one order per spring (torsion
    /// springs are bought by their own rate and fitted at a pivot, not listed here).
    pub fn from_balance(balance: &Balance) -> Vec<SpringOrder> {
        balance
            .springs
            .iter()
            .filter_map(|s| match s {
                Spring::Extension { rate_n_per_mm, free_length_mm, .. } => {
                    Some(SpringOrder { rate_n_per_mm: *rate_n_per_mm, free_length_mm: *free_length_mm, count: 1 })
                }
                Spring::Torsion { .. } => None,
            })
            .collect()
    }
}

/// What a person may choose about a full-size build. Every field may be left out (its default is
/// used); unknown fields are an error, so a misspelt setting is never silently ignored.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WorkshopSettings {
    /// The bolt size of every joint (`"M8"`). Default: none, the smallest size whose shear strength
    /// holds every joint and bracket.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bolt: Option<BoltSize>,
    /// The factor the peak loads are multiplied by before they are compared with the material's
    /// characteristic strengths. Default 3: the loads are quasi-static weights, and the factor
    /// covers the material's partial factor, a person pushing or letting the object drop onto its
    /// stops, and wear.
    pub safety_factor: f64,
    /// Thickness of a body the scene gives none for (and of the fixed bodies), mm: for its weight
    /// when the scene gives neither mass nor stock, and for the bolts through it. Default 18.
    pub body_thickness_mm: f64,
    /// Counterbalance springs to list in the bill of materials. Default none.
    pub springs: Vec<SpringOrder>,
}

impl Default for WorkshopSettings {
    fn default() -> Self {
        WorkshopSettings { bolt: None, safety_factor: 3.0, body_thickness_mm: 18.0, springs: Vec::new() }
    }
}

/// The largest safety factor taken: beyond it the sizes stop meaning anything.
const MAX_SAFETY_FACTOR: f64 = 20.0;
/// The thickest body taken, mm.
const MAX_BODY_THICKNESS_MM: f64 = 1000.0;
/// The thinnest body taken, mm: the thinnest sheet a workshop cuts a body from.
const MIN_BODY_THICKNESS_MM: f64 = 1.0;
/// The most spring lines taken.
const MAX_SPRINGS: usize = 16;

impl WorkshopSettings {
    /// Parses settings from JSON text (missing fields keep their defaults); the error names the field.
    pub fn from_json(text: &str) -> Result<WorkshopSettings, SettingsIssue> {
        let de = &mut serde_json::Deserializer::from_str(text);
        serde_path_to_error::deserialize(de)
            .map_err(|e| SettingsIssue { field: e.path().to_string(), message: e.into_inner().to_string() })
    }

    /// Every setting that cannot work, each naming its field (empty when all is well).
    pub fn validate(&self) -> Vec<SettingsIssue> {
        let mut out = Vec::new();
        let mut issue = |field: String, message: String| out.push(SettingsIssue { field, message });
        if !(self.safety_factor.is_finite() && (1.0..=MAX_SAFETY_FACTOR).contains(&self.safety_factor)) {
            issue(
                "safety_factor".into(),
                format!("must be between 1 and {MAX_SAFETY_FACTOR} (is {})", self.safety_factor),
            );
        }
        if !(self.body_thickness_mm.is_finite()
            && (MIN_BODY_THICKNESS_MM..=MAX_BODY_THICKNESS_MM).contains(&self.body_thickness_mm))
        {
            issue(
                "body_thickness_mm".into(),
                format!(
                    "is {} mm; use a number from {MIN_BODY_THICKNESS_MM} to {MAX_BODY_THICKNESS_MM} mm",
                    self.body_thickness_mm
                ),
            );
        }
        if self.springs.len() > MAX_SPRINGS {
            issue("springs".into(), format!("at most {MAX_SPRINGS} lines (has {})", self.springs.len()));
        }
        for (k, s) in self.springs.iter().enumerate().take(MAX_SPRINGS) {
            for (name, v) in [("rate_n_per_mm", s.rate_n_per_mm), ("free_length_mm", s.free_length_mm)] {
                if !(v.is_finite() && v > 0.0 && v < 1e6) {
                    issue(format!("springs[{k}].{name}"), format!("must be a positive number (is {v})"));
                }
            }
            if !(1..=100).contains(&s.count) {
                issue(format!("springs[{k}].count"), format!("must be between 1 and 100 (is {})", s.count));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_fill_in_and_bad_fields_are_named() {
        let s = WorkshopSettings::from_json("{}").unwrap();
        assert_eq!(s, WorkshopSettings::default());
        assert!(s.validate().is_empty());
        let s =
            WorkshopSettings::from_json(r#"{"bolt": "m10", "springs": [{"rate_n_per_mm": 2, "free_length_mm": 300}]}"#)
                .unwrap();
        assert_eq!((s.bolt, s.springs[0].count), (Some(BoltSize::M10), 1));
        let e = WorkshopSettings::from_json(r#"{"bolt": "M7"}"#).unwrap_err();
        assert_eq!(e.field, "bolt");
        let e = WorkshopSettings::from_json(r#"{"safety": 2}"#).unwrap_err();
        assert!(e.message.contains("safety"), "{e}");
        let bad = WorkshopSettings {
            safety_factor: 0.5,
            body_thickness_mm: f64::NAN,
            springs: vec![SpringOrder { rate_n_per_mm: -1.0, free_length_mm: 100.0, count: 0 }],
            ..WorkshopSettings::default()
        };
        let fields: Vec<String> = bad.validate().into_iter().map(|i| i.field).collect();
        assert_eq!(fields, ["safety_factor", "body_thickness_mm", "springs[0].rate_n_per_mm", "springs[0].count"]);
    }
}
