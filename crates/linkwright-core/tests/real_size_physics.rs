//! Physics at the object's real size: parts weighed for the build (a printed model at its scale, or
//! the object at full size in its material), checked against closed forms, and the counterbalance
//! springs of the full-size wall bed (60 kg) checked to be stock springs whose reported torque is the
//! one those very springs leave.
//!
//! The linkage is a four-bar made by hand for the bundled full-size wall bed: two points of the bed,
//! each with its ground pivot at the centre of the circle through its three places (Burmester's
//! three-position synthesis), so the four-bar carries the bed through its three poses exactly.

use linkwright_core::balance::{
    Balance, Balancing, Series, Spring, SpringNeed, SpringSearch, FREE_LENGTHS, NO_SPRING_NEEDED_NM, STRETCH_RATIO,
};
use linkwright_core::fab::PrintSettings;
use linkwright_core::geom::{Point, Rigid, Vec2};
use linkwright_core::kinematics::{BodyFrames, Plan, Trace};
use linkwright_core::statics::{driving_torque, FullSize, Masses, MassesError, Torque};
use linkwright_core::{
    Build, Material, Mechanism, ModelScale, PartKind, Problem, Ratio, Scene, Silent, Topology, Units,
};
use std::sync::Arc;

/// ISO 3's R10 and R20 steps of a decade, written out here rather than read from the library.
const R10: [f64; 10] = [1.0, 1.25, 1.6, 2.0, 2.5, 3.15, 4.0, 5.0, 6.3, 8.0];
const R20: [f64; 20] =
    [1.0, 1.12, 1.25, 1.4, 1.6, 1.8, 2.0, 2.24, 2.5, 2.8, 3.15, 3.55, 4.0, 4.5, 5.0, 5.6, 6.3, 7.1, 8.0, 9.0];

/// Whether `x` is a step of `steps` times a power of ten.
fn in_series(x: f64, steps: &[f64]) -> bool {
    let decade = 10f64.powi(x.log10().floor() as i32);
    steps.iter().chain(&[10.0]).any(|s| (x / decade - s).abs() <= 1e-9 * s)
}

fn assert_close(a: f64, b: f64, tol: f64, what: &str) {
    assert!((a - b).abs() <= tol, "{what}: {a} against {b} (tolerance {tol})");
}

/// The full-size wall bed, drawn in millimetres, its bed 2000 × 300 and 60 kg.
fn wall_bed_scene() -> Scene {
    let path = format!("{}/../../examples/k1_wall_bed_full_size.json", env!("CARGO_MANIFEST_DIR"));
    Scene::from_json(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The centre of the circle through three points.
fn circumcentre(a: Point, b: Point, c: Point) -> Point {
    let (ab, ac) = (b - a, c - a);
    let d = 2.0 * ab.cross(ac);
    let (nb, nc) = (ab.dot(ab), ac.dot(ac));
    a + Vec2::new(ac.y * nb - ab.y * nc, ab.x * nc - ac.x * nb) / d
}

/// The angle `a` brought into (−π, π].
fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(std::f64::consts::TAU);
    if w > std::f64::consts::PI {
        w - std::f64::consts::TAU
    } else {
        w
    }
}

/// A four-bar and its travel, from the first pose to the last in steps of at most 1°.
struct FourBar {
    problem: Problem,
    mechanism: Mechanism,
    plan: Plan,
    trace: Trace,
    frames: BodyFrames,
}

/// `scene` (drawn in mm) drawn in centimetres: every length, the bed's thickness included, a tenth.
fn in_centimetres(scene: &Scene) -> Scene {
    let cm = |p: &Point| Point::new(p.x / 10.0, p.y / 10.0);
    let mut out = scene.clone();
    out.units = "cm".into();
    for f in &mut out.fixed_bodies {
        f.polygon = f.polygon.iter().map(cm).collect();
    }
    for b in &mut out.moving_bodies {
        b.polygon = b.polygon.iter().map(cm).collect();
        b.poses.iter_mut().for_each(|pose| [pose[0], pose[1]] = [pose[0] / 10.0, pose[1] / 10.0]);
        b.thickness = b.thickness.map(|t| t / 10.0);
    }
    out.linkage_region = out.linkage_region.as_ref().map(|r| r.iter().map(cm).collect());
    out
}

/// The four-bar that carries `scene`'s bed (the wall bed's poses) through its poses: its crank on the
/// bed at (450, 250) mm, its rocker at (200, 0) mm (bed coordinates), each ground pivot the centre of
/// its point's three places. Asserts that it reaches every pose.
fn four_bar(scene: &Scene) -> FourBar {
    let problem = Problem::new(scene).unwrap();
    let bed = &problem.bodies[0];
    let unit = problem.units.millimetres();
    let places = |x: f64, y: f64| -> Vec<Point> {
        bed.poses.iter().map(|pose| pose.apply(Point::new(x / unit, y / unit))).collect()
    };
    let (crank_tip, rocker_tip) = (places(450.0, 250.0), places(200.0, 0.0));
    let (q0, r0) = (
        circumcentre(crank_tip[0], crank_tip[1], crank_tip[2]),
        circumcentre(rocker_tip[0], rocker_tip[1], rocker_tip[2]),
    );
    let topology = Arc::new(Topology::chain(1));
    let mut joints = vec![Point::ORIGIN; topology.joint_count()];
    for (name, p) in [("q0", q0), ("p1", crank_tip[0]), ("r0", r0), ("q1", rocker_tip[0])] {
        joints[topology.joint(name).unwrap()] = p;
    }
    let mechanism = Mechanism { topology, joints, slider: None };
    let plan = Plan::compile(&mechanism).unwrap();
    // The crank's angle at each pose, each from the last without a jump.
    let raw: Vec<f64> = crank_tip.iter().map(|&p| (p - q0).y.atan2((p - q0).x)).collect();
    let mut thetas = vec![raw[0]];
    for &a in &raw[1..] {
        let last = thetas[thetas.len() - 1];
        thetas.push(last + wrap(a - last));
    }
    let mut trace = Trace::new(plan.joint_count());
    trace.sweep(&plan, thetas[0], thetas[2], 1f64.to_radians()).unwrap();
    let first_poses: Vec<Rigid> = problem.bodies.iter().map(|b| b.poses[0]).collect();
    let frames = BodyFrames::new(&mechanism, &first_poses);
    let mut row = vec![Point::ORIGIN; plan.joint_count()];
    for (i, &theta) in thetas.iter().enumerate() {
        plan.solve(theta, &mut row).unwrap();
        let miss = problem.bodies[0].miss(i, &frames.pose(0, &row));
        assert!(miss.position < 1e-6 * problem.scale && miss.angle_deg < 1e-6, "pose {i}: {miss:?}");
    }
    FourBar { problem, mechanism, plan, trace, frames }
}

impl FourBar {
    fn torque(&self, masses: &Masses) -> Torque {
        driving_torque(&self.problem, &self.mechanism, &self.plan, &self.trace, masses).unwrap()
    }

    fn balance(&self, masses: &Masses, torque: &Torque) -> Balance {
        let (problem, mechanism, plan, trace) = (&self.problem, &self.mechanism, &self.plan, &self.trace);
        Balancing { problem, mechanism, plan, trace, masses, torque }.best(SpringSearch::ANALYSIS, &Silent).unwrap()
    }

    fn mass(torque: &Torque, name: &str) -> f64 {
        torque.parts.iter().find(|p| p.name == name).unwrap().mass_kg
    }

    /// The length of link `name` at the first pose, scene units.
    fn link_length(&self, name: &str) -> f64 {
        let part = self.mechanism.topology.parts.iter().find(|p| p.name == name).unwrap();
        self.mechanism.joints[part.joints[0]].distance(self.mechanism.joints[part.joints[1]])
    }

    /// The two joints whose frame carries part `p`'s points (none for the ground).
    fn carriers(&self, p: usize) -> Option<(usize, usize)> {
        let part = &self.mechanism.topology.parts[p];
        match part.kind {
            PartKind::Fixed => None,
            PartKind::Body(b) => Some((self.frames.frame(b).0, self.frames.frame(b).1)),
            PartKind::Link => Some((part.joints[0], part.joints[1])),
        }
    }
}

/// The bed (2000 × 300 mm) of the given stock weighs its volume times its density; one with
/// `mass_kg` weighs that whatever its stock; one with neither weighs the build's material at the
/// stock's body thickness; every link is a bar of the stock's section and material.
#[test]
fn a_full_size_body_weighs_its_stock_and_links_their_bars() {
    let area_m2 = 2.0 * 0.3;
    let mut scene = wall_bed_scene();
    scene.moving_bodies[0].mass_kg = None;
    scene.moving_bodies[0].material = Some(Material::Plywood);
    scene.moving_bodies[0].thickness = Some(18.0);
    let steel = FullSize::new(Material::Steel);
    // The same object drawn in centimetres weighs the same.
    for scene in [scene.clone(), in_centimetres(&scene)] {
        let bed = four_bar(&scene);
        let torque = bed.torque(&Masses::full(&steel, &bed.problem.units).unwrap());
        // Its own plywood, though the links are steel.
        assert_close(FourBar::mass(&torque, "body1"), area_m2 * 0.018 * 680.0, 1e-12, "plywood bed");
        for link in ["crank", "rocker"] {
            // Steel flat bar, 30 × 5 mm.
            let metres = bed.link_length(link) * bed.problem.units.millimetres() / 1000.0;
            assert_close(FourBar::mass(&torque, link), metres * 0.030 * 0.005 * 7850.0, 1e-12, link);
        }
    }
    let mm = Units::default();
    let steel = Masses::full(&steel, &mm).unwrap();

    // Given its mass, the bed weighs it, its stock notwithstanding.
    scene.moving_bodies[0].mass_kg = Some(60.0);
    let torque = four_bar(&scene).torque(&steel);
    assert_eq!(FourBar::mass(&torque, "body1"), 60.0);

    // Neither: the build's material at the stock's thickness, 6 mm aluminium by default, then 10 mm;
    // links of a 50 × 8 mm aluminium bar.
    scene.moving_bodies[0].mass_kg = None;
    scene.moving_bodies[0].material = None;
    scene.moving_bodies[0].thickness = None;
    let bed = four_bar(&scene);
    let aluminium = FullSize::new(Material::Aluminium);
    let torque = bed.torque(&Masses::full(&aluminium, &bed.problem.units).unwrap());
    assert_close(FourBar::mass(&torque, "body1"), area_m2 * 0.006 * 2700.0, 1e-12, "aluminium bed");
    let thicker = aluminium.with_body_thickness_mm(10.0).with_link_section_mm([50.0, 8.0]);
    let torque = bed.torque(&Masses::full(&thicker, &bed.problem.units).unwrap());
    assert_close(FourBar::mass(&torque, "body1"), area_m2 * 0.010 * 2700.0, 1e-12, "10 mm bed");
    let expected = bed.link_length("crank") / 1000.0 * 0.050 * 0.008 * 2700.0;
    assert_close(FourBar::mass(&torque, "crank"), expected, 1e-12, "50 × 8 crank");

    // What cannot be weighed says why.
    let settings = PrintSettings::default();
    assert_eq!(Masses::for_build(Build::Model(ModelScale::Auto), &settings, &mm), Err(MassesError::UndecidedScale));
    assert!(matches!(
        Masses::full(&aluminium.with_link_section_mm([0.0, 6.0]), &mm),
        Err(MassesError::Stock { field: "link_section_mm", .. })
    ));
    assert_eq!(
        Masses::for_build(Build::Full(Material::Steel), &settings, &mm),
        Masses::full(&FullSize::new(Material::Steel), &mm)
    );
}

/// A model at scale f has every length of the drawing times f. Printed with the same settings
/// (whose thicknesses and link width are the model's own millimetres), a body's volume is its outline
/// (f²) times the body thickness, a bar's its length (f) times the section; the centres of mass move
/// f times as far, so a body's share of the torque is f³ times the 1:1 model's and a bar's f². With
/// the settings' lengths scaled by f as well, every volume is f³ and every share of the torque
/// f³ · f = f⁴. The real bed's 60 kg play no part in the model.
#[test]
fn a_model_weighs_its_print_at_its_size_and_its_torque_scales_with_it() {
    let scene = wall_bed_scene();
    let bed = four_bar(&scene);
    let settings = PrintSettings::default();
    let full_scale = Masses::model(&settings, &bed.problem.units, Ratio::ONE).unwrap();
    let one = bed.torque(&full_scale);
    // Printed: 600,000 mm² × 6 mm at 1.24 g/cm³, half filled; the scene's 60 kg are the real bed's.
    let printed_bed = 600_000.0 * 6.0 * 1.24e-6 * 0.5;
    assert_close(FourBar::mass(&one, "body1"), printed_bed, 1e-12, "printed bed");
    // The weighing of the front ends that do not choose a build keeps the scene's mass.
    let legacy = bed.torque(&Masses::printed(&settings, &bed.problem.units));
    assert_eq!(FourBar::mass(&legacy, "body1"), 60.0);

    let f = 0.1;
    let tenth = Ratio { model: 1, object: 10 };
    let same_settings = bed.torque(&Masses::model(&settings, &bed.problem.units, tenth).unwrap());
    let scaled_settings = PrintSettings {
        body_thickness: settings.body_thickness * f,
        link_width: settings.link_width * f,
        link_thickness: settings.link_thickness * f,
        ..settings.clone()
    };
    let all_scaled = bed.torque(&Masses::model(&scaled_settings, &bed.problem.units, tenth).unwrap());
    for (k, part) in one.parts.iter().enumerate() {
        let body = part.name == "body1";
        let (mass, share) = if body { (f * f, f * f * f) } else { (f, f * f) };
        let peak = part.torque_nm.iter().fold(0.0f64, |m, t| m.max(t.abs()));
        assert_close(same_settings.parts[k].mass_kg, mass * part.mass_kg, 1e-12 * part.mass_kg, &part.name);
        assert_close(all_scaled.parts[k].mass_kg, f * f * f * part.mass_kg, 1e-12 * part.mass_kg, &part.name);
        for (r, &tau) in part.torque_nm.iter().enumerate() {
            assert_close(same_settings.parts[k].torque_nm[r], share * tau, 1e-12 * peak, &part.name);
            assert_close(all_scaled.parts[k].torque_nm[r], f.powi(4) * tau, 1e-12 * peak, &part.name);
        }
    }
    assert_close(all_scaled.peak_nm, 1e-4 * one.peak_nm, 1e-12 * one.peak_nm, "peak");
}

/// A spring's stored energy, J, with the linkage's joints at `row`.
type Energy<'a> = Box<dyn Fn(&[Point]) -> f64 + 'a>;
/// Where a point carried by a part is, with the linkage's joints at `row`.
type Carried<'a> = Box<dyn Fn(&[Point]) -> Point + 'a>;

/// The full-size wall bed with its 60 kg, links of plywood, gets stock springs: free lengths on R20
/// and rates on R10 (checked against the numbers written here), each extension spring between its
/// free length and STRETCH_RATIO times it at every row of the travel, and the torque reported with
/// them the one they leave: the unbalanced torque plus the derivative along the crank of their
/// energies, ½k(L − L₀)² or ½κ(φ − φ₀)², re-evaluated here from their reported anchors, rates and
/// free lengths alone.
#[test]
fn the_full_size_wall_bed_gets_stock_springs_whose_torque_is_their_own() {
    let mut scene = wall_bed_scene();
    scene.build = Build::Full(Material::Plywood);
    let bed = four_bar(&scene);
    let masses = Masses::for_build(bed.problem.build, &PrintSettings::default(), &bed.problem.units).unwrap();
    let torque = bed.torque(&masses);
    assert!(torque.peak_nm > 100.0, "a 60 kg bed asks hundreds of N·m: {}", torque.peak_nm);
    let balance = bed.balance(&masses, &torque);
    assert_eq!(balance.need, SpringNeed::Springs);
    assert!((1..=2).contains(&balance.springs.len()), "{:?}", balance.springs);
    assert!(
        balance.peak_with_springs_nm < 0.5 * torque.peak_nm,
        "{} of {}",
        balance.peak_with_springs_nm,
        torque.peak_nm
    );
    let peak = balance.torque_with_springs_nm.iter().fold(0.0f64, |m, t| m.max(t.abs()));
    assert_eq!(balance.peak_with_springs_nm, peak);

    let trace = &bed.trace;
    let metres = masses.millimetres_per_unit / 1000.0;
    let parts = &bed.mechanism.topology.parts;
    let part_of = |name: &str| parts.iter().position(|p| p.name == name).unwrap();
    let mut energies: Vec<Energy> = Vec::new();
    for spring in &balance.springs {
        match spring {
            Spring::Extension {
                anchors,
                stiffness_n_per_m,
                free_length,
                free_length_mm,
                length_range,
                length_range_mm,
                rate_n_per_mm,
                ends,
                ..
            } => {
                assert!(in_series(*free_length_mm, &R20) && FREE_LENGTHS.contains(*free_length_mm), "{spring:?}");
                assert!(in_series(*rate_n_per_mm, &R10), "{spring:?}");
                assert_close(*stiffness_n_per_m, rate_n_per_mm * 1000.0, 1e-9 * stiffness_n_per_m, "rate");
                assert_close(free_length * metres * 1000.0, *free_length_mm, 1e-9 * free_length_mm, "free length");
                // Within the stretch limit at every row, and the reported range is the rows' range.
                assert_eq!(ends.len(), trace.len());
                let lengths: Vec<f64> = ends.iter().map(|[a, b]| a.distance(*b)).collect();
                for (r, &length) in lengths.iter().enumerate() {
                    assert!(length >= free_length * (1.0 - 1e-12), "row {r}: {length} shorter than {free_length}");
                    assert!(length <= STRETCH_RATIO * free_length * (1.0 + 1e-12), "row {r}: {length} overstretched");
                }
                let (lo, hi) = lengths.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &l| (lo.min(l), hi.max(l)));
                assert_close(length_range[0], lo, 1e-9, "shortest");
                assert_close(length_range[1], hi, 1e-9, "longest");
                assert_close(length_range_mm[1], hi * metres * 1000.0, 1e-9, "longest, mm");
                // Each end carried by its part from where it is at the first row.
                let row0 = trace.row(0);
                let place = |p: usize, at: Point| -> Carried {
                    match bed.carriers(p) {
                        None => Box::new(move |_: &[Point]| at),
                        Some((a, c)) => {
                            let local = Rigid::from_frame(row0[a], row0[c] - row0[a]).inverse().apply(at);
                            Box::new(move |row: &[Point]| Rigid::from_frame(row[a], row[c] - row[a]).apply(local))
                        }
                    }
                };
                let (a, b) = (
                    place(part_of(&anchors[0].part), anchors[0].point),
                    place(part_of(&anchors[1].part), anchors[1].point),
                );
                let (k, free) = (rate_n_per_mm * 1000.0, *free_length);
                energies.push(Box::new(move |row: &[Point]| {
                    let stretch = (a(row).distance(b(row)) - free) * metres;
                    0.5 * k * stretch * stretch
                }));
            }
            Spring::Torsion { part, stiffness_nm_per_rad, rate_n_mm_per_deg, free_angle_deg, .. } => {
                assert!(in_series(*rate_n_mm_per_deg, &R10), "{spring:?}");
                let per_rate = 180.0 / std::f64::consts::PI / 1000.0;
                assert_close(*stiffness_nm_per_rad, rate_n_mm_per_deg * per_rate, 1e-9 * stiffness_nm_per_rad, "rate");
                let fixed = bed.mechanism.topology.fixed_joints();
                let joints = &parts[part_of(part)].joints;
                let pivot = *joints.iter().find(|j| fixed.contains(j)).unwrap();
                let tip = *joints.iter().find(|j| !fixed.contains(j)).unwrap();
                let (k, free) = (rate_n_mm_per_deg * per_rate, free_angle_deg.to_radians());
                // The crank turns more than half a turn: the angle from the first row is unwrapped
                // about the middle of the travel, which each evaluation is near.
                let mid = trace.row(trace.len() / 2)[tip] - trace.row(trace.len() / 2)[pivot];
                let mid_angle = {
                    let mut angle = 0.0;
                    for r in 1..=trace.len() / 2 {
                        let (u, v) =
                            (trace.row(r - 1)[tip] - trace.row(r - 1)[pivot], trace.row(r)[tip] - trace.row(r)[pivot]);
                        angle += u.cross(v).atan2(u.dot(v));
                    }
                    angle
                };
                energies.push(Box::new(move |row: &[Point]| {
                    let arm = row[tip] - row[pivot];
                    let twist = mid_angle + mid.cross(arm).atan2(mid.dot(arm)) - free;
                    0.5 * k * twist * twist
                }));
            }
        }
    }
    let along = (trace.thetas[trace.len() - 1] - trace.thetas[0]).signum();
    let h = 1e-6;
    let mut row = vec![Point::ORIGIN; bed.plan.joint_count()];
    let mut energy = |theta: f64| {
        bed.plan.solve(theta, &mut row).unwrap();
        energies.iter().map(|e| e(&row)).sum::<f64>()
    };
    for (r, &theta) in trace.thetas.iter().enumerate() {
        let springs = along * (energy(theta + h) - energy(theta - h)) / (2.0 * h);
        let expected = torque.torque_nm[r] + springs;
        assert_close(balance.torque_with_springs_nm[r], expected, 1e-6 * torque.peak_nm, &format!("row {r}"));
    }
}

/// A load whose peak is below NO_SPRING_NEEDED_NM gets no spring, and says so: the wall bed as a
/// 1:100 model (its bed 20 × 3 mm, a quarter of a gram). The same linkage at 1:1 is a load that needs
/// springs.
#[test]
fn a_tiny_load_needs_no_spring() {
    let scene = wall_bed_scene();
    let bed = four_bar(&scene);
    let settings = PrintSettings::default();
    let tiny = Masses::model(&settings, &bed.problem.units, Ratio { model: 1, object: 100 }).unwrap();
    let torque = bed.torque(&tiny);
    assert!(torque.peak_nm > 0.0 && torque.peak_nm < NO_SPRING_NEEDED_NM, "{}", torque.peak_nm);
    let balance = bed.balance(&tiny, &torque);
    assert_eq!(balance.need, SpringNeed::NotNeeded);
    assert!(balance.springs.is_empty());
    assert_eq!(balance.torque_with_springs_nm, torque.torque_nm);
    assert_eq!(balance.no_spring_below_nm, NO_SPRING_NEEDED_NM);
    let json = serde_json::to_value(&balance).unwrap();
    assert_eq!(json["need"], "not_needed");

    let one = bed.torque(&Masses::model(&settings, &bed.problem.units, Ratio::ONE).unwrap());
    assert!(one.peak_nm > NO_SPRING_NEEDED_NM);
    assert_eq!(Balance::none(&one).need, SpringNeed::NoneHelps);
    // The series the test reads its members from are the library's too.
    assert_eq!(Series::R10.within(1.0, 9.0), R10);
}
