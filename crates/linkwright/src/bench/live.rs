//! `linkwright bench --live SCENES...`: a live redesign as the app runs it while a person drags a
//! pose. Each scene is designed (default settings, an auto printed model), then its first body's
//! middle pose is moved by a tenth of the body's size d in ten steps, each redesigned from the design
//! before it as the app's live mode asks for it. Reported per scene: whether the family changed, the
//! largest move of a joint in one step (fraction of d) and the seconds per step (median, p90).

use crate::failure::Failure;
use crate::files::read_problem;
use linkwright_core::{Problem, Start, Status};
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;

/// Steps of the drag, and how far it goes in all (fraction of d).
const STEPS: usize = 10;
const DRAG_OF_D: f64 = 0.1;

/// One scene's drag.
#[derive(Serialize, Debug)]
struct Row {
    scene: String,
    /// Steps that gave a design.
    designed: usize,
    /// Steps whose design is of another family than the step before.
    family_changes: usize,
    /// The largest distance a joint moved in one step, fraction of d.
    worst_joint_move_rel_d: f64,
    /// The median of the steps' largest joint moves, fraction of d.
    median_joint_move_rel_d: f64,
    /// Seconds per step.
    seconds_median: f64,
    seconds_p90: f64,
}

pub(super) fn bench_live(scenes: &[PathBuf], pool: &rayon::ThreadPool, json: bool) -> Result<(), Failure> {
    if scenes.is_empty() {
        return Err(Failure::Input("error: --live: name the scene files to drag a pose of (examples/*.json)".into()));
    }
    let mut rows = Vec::new();
    for path in scenes {
        let (scene, problem) = read_problem(path)?;
        let label = super::scene_label(path);
        let design = |problem: &Problem, start: Start| super::design_printed(problem, start, pool);
        let mut shown = design(&problem, Start::Cold);
        if shown.status != Status::Ok {
            eprintln!("{label}: no design to start from");
            continue;
        }
        let d = problem.bodies[0].size;
        let pose = scene.moving_bodies[0].poses.len() / 2;
        let mut dragged = scene.clone();
        let (mut seconds, mut moves, mut family_changes, mut designed) = (Vec::new(), Vec::new(), 0, 0);
        for _ in 0..STEPS {
            let step = DRAG_OF_D * d / STEPS as f64 / std::f64::consts::SQRT_2;
            let [x, y, _] = &mut dragged.moving_bodies[0].poses[pose];
            (*x, *y) = (*x + step, *y + step);
            let Ok(problem) = Problem::new(&dragged) else { break };
            let previous = shown.usable_mechanisms();
            let t = Instant::now();
            let next = design(&problem, Start::Follow(&previous));
            seconds.push(t.elapsed().as_secs_f64());
            let (Some(before), Some(after)) = (&shown.mechanism, &next.mechanism) else { continue };
            designed += 1;
            if before.mechanism_type != after.mechanism_type {
                family_changes += 1;
            } else {
                let moved = after
                    .joints
                    .iter()
                    .filter_map(|(name, p)| before.joints.get(name).map(|q| p.distance(*q)))
                    .fold(0.0, f64::max);
                moves.push(moved / d);
            }
            shown = next;
        }
        let row = Row {
            scene: label,
            designed,
            family_changes,
            worst_joint_move_rel_d: moves.iter().copied().fold(0.0, f64::max),
            median_joint_move_rel_d: super::quantile(&mut moves, 0.5),
            seconds_median: super::quantile(&mut seconds, 0.5),
            seconds_p90: super::quantile(&mut seconds, 0.9),
        };
        // Progress while the next scene runs; the table comes at the end (labels are escaped).
        eprintln!("{}: {} steps designed, median {:.2} s", row.scene, row.designed, row.seconds_median);
        rows.push(row);
    }
    if json {
        println!("{}", serde_json::to_string_pretty(&rows).expect("rows serialize"));
        return Ok(());
    }
    println!(
        "{:<28} {:>8} {:>8} {:>12} {:>12} {:>9} {:>9}",
        "scene", "designed", "families", "worst (d)", "median (d)", "med (s)", "p90 (s)"
    );
    for r in &rows {
        println!(
            "{:<28} {:>8} {:>8} {:>12.4} {:>12.4} {:>9.3} {:>9.3}",
            r.scene,
            format!("{}/{STEPS}", r.designed),
            r.family_changes,
            r.worst_joint_move_rel_d,
            r.median_joint_move_rel_d,
            r.seconds_median,
            r.seconds_p90
        );
    }
    Ok(())
}
