//! The length unit a scene is drawn in: read once from the scene's `units` field, so every later
//! stage has a length with a known size in millimetres.

use std::fmt;
use std::str::FromStr;

/// Each unit a scene may be drawn in: the symbol messages use, every other word read for it (in any
/// case, with spaces around it ignored), and the millimetres in one unit.
const KNOWN: [(&str, &[&str], f64); 6] = [
    ("mm", &["", "mm", "millimeter", "millimeters", "millimetre", "millimetres"], 1.0),
    ("cm", &["cm", "centimeter", "centimeters", "centimetre", "centimetres"], 10.0),
    ("m", &["m", "meter", "meters", "metre", "metres"], 1000.0),
    ("in", &["in", "inch", "inches"], 25.4),
    ("ft", &["ft", "foot", "feet"], 304.8),
    ("µm", &["um", "µm", "micrometer", "micrometers"], 0.001),
];

/// The length unit of a scene's coordinates: the word the scene writes and the millimetres in one
/// unit. Only a unit this version knows can be read, so a [`crate::Problem`] always has a size in
/// millimetres. The word is kept as written (`"Millimetres"`, or `""`, which means millimetres): a
/// scene is written back as it was read, and labels say what the person wrote.
///
/// ```
/// use linkwright_core::Units;
///
/// let inches: Units = "Inches".parse()?;
/// assert_eq!((inches.to_string(), inches.millimetres()), ("Inches".to_string(), 25.4));
/// let error = "furlong".parse::<Units>().unwrap_err().to_string();
/// assert!(error.contains("use mm, cm, m, in, ft or µm"), "{error}");
/// # Ok::<(), linkwright_core::UnitsParseError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Units {
    word: String,
    millimetres: f64,
}

impl Units {
    /// Millimetres in one unit (25.4 for inches).
    pub fn millimetres(&self) -> f64 {
        self.millimetres
    }

    /// The word as the scene writes it.
    pub fn as_str(&self) -> &str {
        &self.word
    }
}

/// Millimetres, written `mm`: what a scene without `units` is drawn in.
impl Default for Units {
    fn default() -> Units {
        Units { word: "mm".to_string(), millimetres: 1.0 }
    }
}

impl fmt::Display for Units {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.word)
    }
}

/// Why a scene's `units` cannot be read: the word is not a unit this version knows.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "is {word:?}, not a unit of length this version knows; use {} (or a unit's name, such as millimetres or inches)",
    symbols()
)]
pub struct UnitsParseError {
    /// The word given (its first 64 characters).
    pub word: String,
}

/// The known units' symbols, as a list a person reads: `mm, cm, ... or µm`.
fn symbols() -> String {
    let symbols: Vec<&str> = KNOWN.iter().map(|(symbol, _, _)| *symbol).collect();
    let (last, rest) = symbols.split_last().expect("some unit is known");
    format!("{} or {last}", rest.join(", "))
}

impl FromStr for Units {
    type Err = UnitsParseError;

    fn from_str(word: &str) -> Result<Units, UnitsParseError> {
        let read = word.trim().to_ascii_lowercase();
        KNOWN
            .iter()
            .find(|(_, words, _)| words.contains(&read.as_str()))
            .map(|&(_, _, millimetres)| Units { word: word.to_string(), millimetres })
            .ok_or_else(|| UnitsParseError { word: word.chars().take(64).collect() })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_known_word_reads_as_its_length() {
        let known = [
            (1.0, &["", "  ", "mm", "MM", " millimeter", "millimeters", "Millimetre", "millimetres "][..]),
            (10.0, &["cm", "centimeter", "centimeters", "centimetre", "Centimetres"][..]),
            (1000.0, &["m", "M", "meter", "meters", "metre", "metres"][..]),
            (25.4, &["in", "inch", "Inches"][..]),
            (304.8, &["ft", "foot", "FEET"][..]),
            (0.001, &["um", "µm", "µM", "micrometer", "micrometers"][..]),
        ];
        for (millimetres, words) in known {
            for word in words {
                let units: Units = word.parse().unwrap_or_else(|e| panic!("{word:?}: {e}"));
                assert_eq!(units.millimetres(), millimetres, "{word:?}");
                // Kept as written, so a scene is written back as it was read.
                assert_eq!((units.as_str(), units.to_string().as_str()), (*word, *word));
            }
        }
        assert_eq!(Units::default(), "mm".parse().unwrap());
    }

    #[test]
    fn an_unknown_word_is_refused_with_the_units_known() {
        for word in ["furlong", "px", "micrometre", "mm2", "inchs"] {
            let error = word.parse::<Units>().unwrap_err();
            assert_eq!(
                error.to_string(),
                format!(
                    "is {word:?}, not a unit of length this version knows; use mm, cm, m, in, ft or µm (or a unit's \
                     name, such as millimetres or inches)"
                )
            );
        }
        // A long word is cut short, and a control character shown escaped.
        let error = format!("{}\u{1b}", "x".repeat(100)).parse::<Units>().unwrap_err();
        assert_eq!(error.word.chars().count(), 64);
        assert!("mm\u{1b}[2J".parse::<Units>().unwrap_err().to_string().starts_with("is \"mm\\u{1b}[2J\""));
    }
}
