//! The `design/1` format: what the engine answers, and the reader that turns a design file's parts
//! back into a [`Mechanism`](crate::Mechanism) (so any design can be re-simulated from the file alone).

mod file;
mod validate;

pub use file::{
    Alternative, BuildRecord, DesignError, DesignFile, DesignParseError, DriverJson, EditError, MechanismJson, Metrics,
    Motion, PartJson, PartKindJson, Seconds, SliderJson, Stats, Status, DESIGN_FORMAT,
};
pub use validate::DesignIssue;
pub(crate) use validate::MAX_TRAVEL_DEG;
