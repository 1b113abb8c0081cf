//! Builds: the scene is the real object, and a printed model (at a fixed or an `auto` scale) or a
//! full-size build is a separate choice. Each build designs what it should, an `auto` scale is the
//! one of the series nearest 1:1 within the documented bounds, a drawing too small or too large for
//! its scale is told so in numbers, and no design is lost to the print check alone.

use linkwright_core::fab::{self, BuildPlan, PrintSettings, SizeNote, PIN_SPACINGS_PER_REGION};
use linkwright_core::testbed::scaled_scene;
use linkwright_core::{
    synthesize_with, Build, DesignFile, Material, ModelScale, Options, PartKindJson, Problem, Ratio, Scene, Silent,
    Status,
};

fn example(name: &str) -> Scene {
    let path = format!("{}/../../examples/{name}.json", env!("CARGO_MANIFEST_DIR"));
    Scene::from_json(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// `scene` with `build`, searched with `samples` samples: its problem, build plan and design file.
fn design(scene: &Scene, build: Build, samples: usize) -> (Problem, BuildPlan, DesignFile, bool) {
    let mut scene = scene.clone();
    scene.build = build;
    scene.settings.samples = samples;
    let problem = Problem::new(&scene).unwrap();
    let plan = BuildPlan::new(&problem, &PrintSettings::default());
    let settings = PrintSettings::default();
    let (plan, outcome) = plan.synthesize(&problem, &settings, &Options::default(), &Silent).unwrap();
    let file = plan.design_file(&problem, &outcome);
    (problem, plan, file, outcome.unbuildable)
}

fn model(model: u32, object: u32) -> Build {
    Build::Model(ModelScale::Fixed(Ratio { model, object }))
}

/// The scale an `auto` model gets by the documented rule, found by trying every scale of the series:
/// of those at which the region's diagonal plus a link's width fits along the print area's diagonal
/// and the region is [`PIN_SPACINGS_PER_REGION`] pin spacings across, 1:1 if it is one, else the
/// largest.
fn expected_auto(scene: &Scene) -> Ratio {
    let s = PrintSettings::default();
    let usable = (s.bed.width - 2.0 * s.bed.margin).hypot(s.bed.depth - 2.0 * s.bed.margin);
    let spacing = 2.0 * (0.5 * s.link_width - s.wall).max(s.pin_radius + s.radial_clearance + s.wall) + s.wall;
    let region = Problem::new(scene).unwrap().region.aabb().diagonal();
    let fitting: Vec<Ratio> = Ratio::series()
        .into_iter()
        .filter(|r| {
            let across = region * r.factor();
            across + s.link_width <= usable && across >= PIN_SPACINGS_PER_REGION * spacing
        })
        .collect();
    if fitting.contains(&Ratio::ONE) {
        return Ratio::ONE;
    }
    *fitting.iter().max_by(|a, b| a.factor().total_cmp(&b.factor())).unwrap()
}

#[test]
fn an_auto_model_is_at_the_scale_nearest_full_size_that_fits() {
    let wall_bed = example("k1_wall_bed_full_size");
    let table = example("k1_table");
    let cases = [
        // The 2 m wall bed's region is 630 mm square, 891 mm across: 1:5 puts it at 178 mm, 1:2 at 446 mm,
        // more than the 297 mm diagonal of the print area.
        (wall_bed.clone(), Ratio { model: 1, object: 5 }),
        (table.clone(), Ratio::ONE),
        // The table's region is 93 mm across. Drawn a hundredth as large (0.93 mm), its model is as
        // large as the bed takes: 186 mm at 200:1 (465 mm at 500:1 is too long), twice its own size.
        (scaled_scene(&table, 0.01), Ratio { model: 200, object: 1 }),
        (scaled_scene(&table, 100.0), Ratio { model: 1, object: 50 }),
        // The wall bed drawn a thousandth as large: 0.89 mm across, 178 mm at 200:1.
        (scaled_scene(&wall_bed, 0.001), Ratio { model: 200, object: 1 }),
    ];
    for (scene, scale) in cases {
        assert_eq!(expected_auto(&scene), scale, "{}", scene.name);
        let problem = Problem::new(&scene).unwrap();
        let plan = BuildPlan::new(&problem, &PrintSettings::default());
        assert_eq!(plan.model_scale(), Some(scale), "{}", scene.name);
        assert!(plan.notes.is_empty(), "{:?}", plan.notes);
    }
}

#[test]
fn a_model_at_a_fixed_scale_is_designed_and_printed_at_that_scale() {
    let scene = example("k1_wall_bed_full_size");
    let (problem, plan, file, unbuildable) = design(&scene, model(1, 10), 40_000);
    assert_eq!(file.status, Status::Ok, "{:?}", file.reason);
    assert!(!unbuildable);
    let record = file.build.as_ref().unwrap();
    assert_eq!((record.asked, record.checked, record.buildable), (model(1, 10), model(1, 10), true));
    // Everything drawn (2.55 × 2.4 m with the floor) at a tenth.
    let [w, h] = record.model_mm.unwrap();
    assert!((w - 255.0).abs() < 1e-9 && (h - 240.0).abs() < 1e-9, "{w} × {h}");
    // Two joints of a link are at least the spacing two pins need apart, in the model's millimetres.
    let need = fab::Dims::new(&PrintSettings::default(), 1.0).min_joint_spacing();
    let mechanism = file.mechanism.as_ref().unwrap();
    for part in mechanism.parts.iter().filter(|p| p.kind == PartKindJson::Link) {
        let at = |name: &str| mechanism.joints[name];
        let apart = at(&part.joints[0]).distance(at(&part.joints[1])) * plan.model_mm_per_unit().unwrap();
        assert!(apart >= need, "{}: {apart} mm in the model", part.name);
    }
    let fabrication = fab::fabricate_design(&problem, &file, &PrintSettings::default()).unwrap();
    assert_eq!(fabrication.scale, Ratio { model: 1, object: 10 });
    assert!(fabrication.off_bed().is_empty());
    assert!(fab::check(&fabrication).ok());
}

#[test]
fn the_full_size_wall_bed_prints_as_an_auto_model_on_a_few_plates() {
    let scene = example("k1_wall_bed_full_size");
    let (problem, _, file, _) = design(&scene, Build::default(), 100_000);
    let record = file.build.as_ref().unwrap();
    assert_eq!((record.checked, record.buildable), (model(1, 5), true), "{:?}", record.reason);
    let fabrication = fab::fabricate_design(&problem, &file, &PrintSettings::default()).unwrap();
    assert!(fab::check(&fabrication).ok());
    let files = fab::bundle(&fabrication).unwrap();
    assert!(files.report.oversized.is_empty(), "{:?}", files.report.oversized);
    let placed: usize = files.report.plates.iter().map(|p| p.parts.len()).sum();
    assert_eq!(placed, files.report.parts.len(), "every part lies on a plate");
    assert!(files.report.plates.len() <= 10, "{} plates", files.report.plates.len());
    assert_eq!(files.report.scale, "1:5");
}

#[test]
fn a_full_size_build_designs_without_the_print_check() {
    let scene = example("k1_wall_bed_full_size");
    let (problem, plan, file, _) = design(&scene, Build::Full(Material::Plywood), 20_000);
    assert!(plan.acceptance().is_none() && plan.model_scale().is_none());
    let record = file.build.as_ref().unwrap();
    assert_eq!((record.checked, record.buildable, record.model_mm), (Build::Full(Material::Plywood), true, None));
    // The same design as the paper's synthesis alone.
    let plain = synthesize_with(&problem, &Options::default(), &Silent).unwrap();
    assert_eq!(file.mechanism, DesignFile::from_outcome(&problem, &plain).mechanism);
}

#[test]
fn valid_linkages_the_print_check_refuses_still_give_the_best_of_them() {
    // The table drawn 100 times as large (12 m) and printed at 1:1: every valid linkage is too long
    // for the bed.
    let scene = scaled_scene(&example("k1_table"), 100.0);
    let (problem, plan, file, unbuildable) = design(&scene, model(1, 1), 20_000);
    assert_eq!(file.status, Status::Ok, "{:?}", file.reason);
    assert!(unbuildable);
    assert_eq!(file.violations(&problem), vec![], "the design is valid");
    let record = file.build.as_ref().unwrap();
    assert!(!record.buildable);
    let reason = record.reason.as_deref().unwrap();
    assert!(reason.contains("print at 1:") && reason.contains("full size"), "{reason}");
    assert!(file.alternatives.is_empty());
    // The size was told before the search too.
    assert!(matches!(plan.notes[..], [SizeNote::TooLarge { fits: Some(_), .. }]), "{:?}", plan.notes);
}

#[test]
fn a_drawing_too_small_for_its_scale_is_told_so_in_numbers() {
    // The table drawn 1/100 as large (1.3 mm): at 1:1 no link can hold two pins.
    let scene = scaled_scene(&example("k1_table"), 0.01);
    let (_, plan, file, _) = design(&scene, model(1, 1), 20_000);
    assert_eq!(file.status, Status::NoSolution);
    let reason = file.reason.as_deref().unwrap();
    assert!(reason.starts_with("The drawing's size does not suit the build model:1:1"), "{reason}");
    assert!(reason.contains("print at 50:1 or larger") && !reason.contains("poses"), "{reason}");
    assert!(matches!(plan.notes[..], [SizeNote::TooSmall { .. }]), "{:?}", plan.notes);
    // At the auto scale it designs.
    let (_, _, file, _) = design(&scene, Build::default(), 20_000);
    assert_eq!(file.status, Status::Ok, "{:?}", file.reason);
    assert_eq!(file.build.unwrap().checked, model(200, 1));
}

#[test]
fn an_auto_model_that_prints_nothing_is_tried_at_larger_scales() {
    // The paper's folding roof (three bodies), drawn without a linkage region: everything drawn is
    // longer along its diagonal than the bed, so the drawing decides 1:2, where its pins leave no
    // linkage; at 1:1 its links fit and it prints. Drawn a hundredth as large, the same at 100:1.
    let path = format!("{}/tests/fixtures/reference-scenes/k3_new_folding_roof4.json", env!("CARGO_MANIFEST_DIR"));
    let roof = Scene::from_json(&std::fs::read_to_string(path).unwrap()).unwrap();
    for (scene, decided, printed) in
        [(roof.clone(), model(1, 2), model(1, 1)), (scaled_scene(&roof, 0.01), model(50, 1), model(100, 1))]
    {
        let plan = BuildPlan::new(&Problem::new(&scene).unwrap(), &PrintSettings::default());
        assert_eq!(plan.checked, decided);
        let (_, _, file, unbuildable) = design(&scene, Build::default(), 20_000);
        assert_eq!(file.status, Status::Ok, "{:?}", file.reason);
        assert!(!unbuildable);
        let record = file.build.unwrap();
        assert_eq!((record.asked, record.checked), (Build::default(), printed));
    }
}
