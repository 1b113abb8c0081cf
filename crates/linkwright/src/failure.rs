//! How a command fails, and the exit code each failure gives.

use crate::terminal;
use std::process::ExitCode;

/// Exit codes: 0 done (a `no_solution` design included), 1 a check found violations, 2 bad input.
pub(crate) enum Failure {
    /// The person's input is unusable; the message says what to change.
    Input(String),
    /// `check` found violations (already printed).
    Violations,
}

impl Failure {
    /// Says what is wrong (violations were printed already) and gives the exit code.
    pub(crate) fn exit(self) -> ExitCode {
        match self {
            Failure::Violations => ExitCode::from(1),
            Failure::Input(message) => {
                terminal::warn(&message);
                ExitCode::from(2)
            }
        }
    }
}
