//! The length unit a scene is drawn in: read once from the scene's `units` field, so every later
//! stage has a length with a known size in millimetres.

use super::build::Ratio;
use std::fmt;
use std::str::FromStr;

/// A unit a scene may be drawn in, as [`Units::known`] lists it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KnownUnit {
    /// The symbol messages use (`"in"`).
    pub symbol: &'static str,
    /// Every word read as this unit, the symbol among them, in lower case: a scene's word is read as
    /// the unit when, with the spaces around it trimmed and its ASCII letters lowered, it is one of
    /// these (`" Inches"` is `"inches"`). The empty word is millimetres.
    pub words: &'static [&'static str],
    /// Millimetres in one unit (25.4).
    pub millimetres: f64,
}

/// Every unit a scene may be drawn in, the default (millimetres) first.
const KNOWN: [KnownUnit; 6] = [
    KnownUnit {
        symbol: "mm",
        words: &["", "mm", "millimeter", "millimeters", "millimetre", "millimetres"],
        millimetres: 1.0,
    },
    KnownUnit {
        symbol: "cm",
        words: &["cm", "centimeter", "centimeters", "centimetre", "centimetres"],
        millimetres: 10.0,
    },
    KnownUnit { symbol: "m", words: &["m", "meter", "meters", "metre", "metres"], millimetres: 1000.0 },
    KnownUnit { symbol: "in", words: &["in", "inch", "inches"], millimetres: 25.4 },
    KnownUnit { symbol: "ft", words: &["ft", "foot", "feet"], millimetres: 304.8 },
    KnownUnit { symbol: "µm", words: &["um", "µm", "micrometer", "micrometers"], millimetres: 0.001 },
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
    /// Every unit this version reads, the default (millimetres) first: the table a scene's word is
    /// read with, for code that must read the word as the engine does.
    ///
    /// ```
    /// use linkwright_core::Units;
    ///
    /// let inch = Units::known().iter().find(|u| u.symbol == "in").expect("inches are known");
    /// assert_eq!((inch.words, inch.millimetres), (&["in", "inch", "inches"][..], 25.4));
    /// // Each word, in capitals and with spaces around it, reads as its unit.
    /// for unit in Units::known() {
    ///     for word in unit.words {
    ///         let units: Units = format!(" {} ", word.to_ascii_uppercase()).parse()?;
    ///         assert_eq!(units.millimetres(), unit.millimetres, "{word:?}");
    ///     }
    /// }
    /// # Ok::<(), linkwright_core::UnitsParseError>(())
    /// ```
    pub fn known() -> &'static [KnownUnit] {
        &KNOWN
    }

    /// Millimetres in one unit (25.4 for inches).
    pub fn millimetres(&self) -> f64 {
        self.millimetres
    }

    /// Millimetres of a model at `scale` for one unit of the drawing (2.54 for inches at 1:10): what
    /// printing, fabricating and weighing a model measure the drawing in.
    pub fn model_millimetres(&self, scale: Ratio) -> f64 {
        self.millimetres * scale.factor()
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
    let symbols: Vec<&str> = KNOWN.iter().map(|unit| unit.symbol).collect();
    let (last, rest) = symbols.split_last().expect("some unit is known");
    format!("{} or {last}", rest.join(", "))
}

impl FromStr for Units {
    type Err = UnitsParseError;

    fn from_str(word: &str) -> Result<Units, UnitsParseError> {
        let read = word.trim().to_ascii_lowercase();
        KNOWN
            .iter()
            .find(|unit| unit.words.contains(&read.as_str()))
            .map(|unit| Units { word: word.to_string(), millimetres: unit.millimetres })
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

    /// The table is read by others too (the web app): a word is in the form a scene's word is read
    /// to, names one unit only, and each unit's symbol is one of its words.
    #[test]
    fn the_known_words_are_read_forms_of_one_unit_each() {
        let mut seen = std::collections::HashSet::new();
        for unit in Units::known() {
            assert!(unit.words.contains(&unit.symbol), "{unit:?}");
            for word in unit.words {
                assert_eq!(word.trim().to_ascii_lowercase(), *word, "{unit:?}");
                assert!(seen.insert(*word), "{word:?} is read for two units");
            }
        }
        assert_eq!(Units::known()[0].millimetres, Units::default().millimetres());
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
