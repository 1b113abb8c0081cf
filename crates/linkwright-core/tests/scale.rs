//! The drawing's units do not matter: a scene scaled by any factor gives the same design, scaled
//! (every threshold and every soft cost is relative to the body size d).

use linkwright_core::testbed::scaled_scene as scaled;
use linkwright_core::{synthesize, DesignFile, Problem, Scene, Silent, Status};
use rand::{RngExt, SeedableRng};

fn example(name: &str) -> Scene {
    let path = format!("{}/../../examples/{name}.json", env!("CARGO_MANIFEST_DIR"));
    Scene::from_json(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn design(scene: &Scene) -> (Problem, DesignFile) {
    let problem = Problem::new(scene).unwrap();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    let outcome = pool.install(|| synthesize(&problem, &Silent)).unwrap();
    let file = DesignFile::from_outcome(&problem, &outcome);
    (problem, file)
}

/// The mean link length of a design's best mechanism, and its metrics' pose errors relative to d.
fn relative_metrics(file: &DesignFile) -> (f64, f64, f64) {
    let m = file.metrics.as_ref().unwrap();
    let worst = m.worst_pose_error.unwrap();
    (m.size, worst.position_rel_d, worst.angle_deg)
}

/// Random factors from 10⁻³ to 10³: the same seed gives the same design scaled, by its cost (which is
/// scale-free), its pose errors relative to d, its angle errors, and its link lengths over the factor.
/// Rounding differs at each scale, so a sample on the edge of a check may go either way and the
/// refinement stops a rounding away; the designs must still agree to a part in a thousand.
#[test]
fn the_same_scene_at_any_scale_gives_the_same_design_scaled() {
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(11);
    for name in ["k1_garbage_truck", "k2_wall_chair", "k1_sofa_bed"] {
        let mut scene = example(name);
        scene.settings.samples = 6000;
        scene.settings.particles = 40;
        scene.settings.iterations = 8;
        let (_, reference) = design(&scene);
        assert_eq!(reference.status, Status::Ok, "{name}: {:?}", reference.reason);
        let (size, rel, angle) = relative_metrics(&reference);
        let cost = reference.metrics.as_ref().unwrap().cost;
        for _ in 0..2 {
            let factor = 10f64.powf(rng.random_range(-3.0..3.0));
            let (_, file) = design(&scaled(&scene, factor));
            assert_eq!(file.status, Status::Ok, "{name} ×{factor}: {:?}", file.reason);
            let (s_size, s_rel, s_angle) = relative_metrics(&file);
            let s_cost = file.metrics.as_ref().unwrap().cost;
            let close = |a: f64, b: f64, what: &str| {
                assert!((a - b).abs() <= 1e-3 * a.abs().max(b.abs()) + 1e-9, "{name} ×{factor}: {what} {a} against {b}")
            };
            close(s_cost, cost, "cost");
            close(s_size / factor, size, "mean link length / factor");
            // Pose errors near zero are where the refinement stopped: equal to a thousandth of d.
            assert!((s_rel - rel).abs() <= 1e-3, "{name} ×{factor}: worst pose error / d {s_rel} against {rel}");
            assert!((s_angle - angle).abs() <= 0.05, "{name} ×{factor}: angle error {s_angle}° against {angle}°");
        }
    }
}
