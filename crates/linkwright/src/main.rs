//! `linkwright`: the command-line shell around linkwright-core. It reads and writes files, shows
//! progress and maps outcomes to exit codes; every computation lives in the library.

// A binary exports nothing: its items say `pub(crate)` or less.
#![warn(unreachable_pub)]

mod bench;
mod commands;
mod fabricate;
mod failure;
mod files;
mod memory;
mod serve;
mod springs;
mod terminal;
mod workshop;

use clap::{Parser, Subcommand};
use failure::Failure;
use std::path::PathBuf;
use std::process::ExitCode;

/// Most worker threads a command takes: more than any machine this runs on has cores, while every
/// thread keeps its own scratch memory for the synthesis (a hundred thousand threads would exhaust it).
const MAX_THREADS: u64 = 256;

/// `--threads`: between 1 and [`MAX_THREADS`].
fn thread_count() -> clap::builder::RangedU64ValueParser<usize> {
    clap::builder::RangedU64ValueParser::new().range(1..=MAX_THREADS)
}

/// `--samples`: between 1 and the scene format's own bound.
fn sample_count() -> clap::builder::RangedU64ValueParser<usize> {
    clap::builder::RangedU64ValueParser::new().range(1..=linkwright_core::limits::MAX_SAMPLES as u64)
}

/// `--build`: model:auto, model:1:10, full:plywood, ... (the scene format's words).
fn build_choice() -> impl clap::builder::TypedValueParser<Value = linkwright_core::Build> {
    |text: &str| text.parse::<linkwright_core::Build>().map_err(|e| e.to_string())
}

/// Turn a sketch of an object and its key poses into a working linkage.
#[derive(Parser, Debug)]
#[command(name = "linkwright", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Find the best linkage for a scene and write design.json, design.svg and animation.svg.
    Design(commands::DesignArgs),
    /// Re-simulate a design against its scene and report every violated constraint (exit 1 if any).
    Check {
        /// The scene file (scene/1).
        scene: PathBuf,
        /// The design file (design/1).
        design: PathBuf,
        /// Print the violations as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Time the synthesis on the paper's Table-1 objects (or given scenes), side by side with the paper.
    Bench(bench::BenchArgs),
    /// Start the local web app: sketch an object, design its linkage, watch it move.
    Serve(serve::ServeArgs),
    /// Printable parts for a design: STL per part, assembly and plates as 3MF, SVG/DXF profiles, the
    /// assembly sheet and fabrication.json.
    Fabricate(fabricate::FabricateArgs),
    /// The torque the crank needs to hold a design against gravity along its motion (masses of the
    /// printed parts, or the scene's mass_kg per body), and the counterbalance spring(s) that lower
    /// its peak
    Analyze {
        scene: PathBuf,
        design: PathBuf,
        /// Print the result as JSON
        #[arg(long)]
        json: bool,
        /// Print settings (JSON) a printed model's masses come from: density, fill, body and link sizes
        #[arg(long)]
        print_settings: Option<PathBuf>,
        /// How the object is built (overrides the scene's `build`): a printed model (model:auto,
        /// model:1:10) is weighed as printed at its scale, a full-size build (full:plywood, ...) with
        /// the scene's real masses (mass_kg, or material and thickness)
        #[arg(long, value_name = "BUILD", value_parser = build_choice())]
        build: Option<linkwright_core::Build>,
    },
    /// Print the joint positions along a design's motion as CSV.
    Simulate {
        scene: PathBuf,
        design: PathBuf,
        /// Number of crank steps from the first to the last pose.
        #[arg(long, default_value_t = 100)]
        steps: usize,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Design(args) => commands::design(args),
        Command::Check { scene, design, json } => commands::check(&scene, &design, json),
        Command::Fabricate(args) => fabricate::fabricate(args),
        Command::Simulate { scene, design, steps } => commands::simulate(&scene, &design, steps),
        Command::Analyze { scene, design, json, print_settings, build } => {
            commands::analyze(&scene, &design, json, print_settings.as_deref(), build)
        }
        Command::Serve(args) => serve::serve(args),
        Command::Bench(args) => bench::bench(args),
    };
    result.map_or_else(Failure::exit, |()| ExitCode::SUCCESS)
}
