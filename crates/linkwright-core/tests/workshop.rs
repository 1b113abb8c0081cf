//! The full-size build's workshop outputs, against numbers found independently: joint distances of
//! known mechanisms, the closed-form statics of a parallelogram, the potential energy's derivative
//! with respect to a link's length (the kinematics solved again with that link lengthened), the
//! statics module's driving torque, the ISO 273 table, the strength rule's inequalities written out
//! here from its documentation, and the profiles read back as XML and as DXF group codes.

use linkwright_core::fab::PrintSettings;
use linkwright_core::geom::{Point, Vec2};
use linkwright_core::kinematics::{circle_circle, Branch, Plan, Trace};
use linkwright_core::statics::{driving_torque, Masses, GRAVITY};
use linkwright_core::testbed::{known_scene, Known, KnownScene};
use linkwright_core::workshop::{
    equilibrium, files, plan, BoltSize, LinkKind, LinkPlan, Workshop, WorkshopError, WorkshopSettings,
};
use linkwright_core::{Build, DesignFile, Material, Mechanism, MechanismType, Problem, Scene, Silent, Topology};
use std::sync::Arc;

/// A known four-bar a metre across (drawn in millimetres) whose body weighs `kg`.
fn known_four_bar(seed: u64, kg: f64) -> (KnownScene, Problem) {
    let mut known = known_scene(Known::chain(1), 3, seed, 1000.0).expect("a known scene");
    known.scene.moving_bodies[0].mass_kg = Some(kg);
    let problem = Problem::new(&known.scene).expect("a valid scene");
    (known, problem)
}

/// The known mechanism's motion at crank steps of `step_deg`.
fn sweep(known: &KnownScene, step_deg: f64) -> (Plan, Trace) {
    let plan = Plan::compile(&known.mechanism).unwrap();
    let mut trace = Trace::new(plan.joint_count());
    let (from, to) = (known.pose_crank[0], known.pose_crank[known.pose_crank.len() - 1]);
    trace.sweep(&plan, from, to, step_deg.to_radians()).unwrap();
    (plan, trace)
}

fn part_index(mechanism: &Mechanism, name: &str) -> usize {
    mechanism.topology.parts.iter().position(|p| p.name == name).unwrap()
}

fn joint(mechanism: &Mechanism, name: &str) -> usize {
    mechanism.topology.joint(name).unwrap()
}

/// Every link of the plan lists the distance between every pair of its joints as the design has
/// them, its holes are where its joints are, and every joint of the design has its bolt.
#[test]
fn pivot_to_pivot_lengths_are_the_joint_distances() {
    for seed in [3, 7, 11] {
        let (known, problem) = known_four_bar(seed, 20.0);
        let workshop = plan(&problem, &known.design(), Material::Steel, &WorkshopSettings::default()).unwrap();
        let m = &known.mechanism;
        let links: Vec<&LinkPlan> = workshop.links.iter().filter(|l| l.kind == LinkKind::Link).collect();
        assert_eq!(links.len(), 2, "crank and rocker");
        for part in m.topology.parts.iter().filter(|p| p.kind == linkwright_core::PartKind::Link) {
            let link = links.iter().find(|l| l.name == part.name).expect("every link is planned");
            assert_eq!(link.pivot_lengths.len(), part.joints.len() * (part.joints.len() - 1) / 2);
            for pl in &link.pivot_lengths {
                let expected = m.joint(&pl.joints[0]).unwrap().distance(m.joint(&pl.joints[1]).unwrap());
                assert!((pl.length_mm - expected).abs() < 1e-9, "{}: {pl:?} against {expected}", link.name);
            }
            // The outline's holes are the joints, as far apart as the joints.
            let holes: Vec<Point> = link
                .outline
                .holes
                .iter()
                .filter_map(|h| match h {
                    linkwright_core::workshop::Hole::Round { centre, purpose, .. } if purpose != "fixing" => {
                        Some(*centre)
                    }
                    _ => None,
                })
                .collect();
            assert_eq!(holes.len(), part.joints.len());
            let expected = m.joints[part.joints[0]].distance(m.joints[part.joints[1]]);
            assert!((holes[0].distance(holes[1]) - expected).abs() < 1e-9);
        }
        for j in &m.topology.joint_names {
            assert!(workshop.bolts.iter().any(|b| &b.at == j && b.count == 1), "joint {j} has a bolt");
        }
    }
}

/// The parallelogram: ground pivots 60 mm apart, crank and rocker of 30 mm turning together, a body
/// bar between their ends (its weight halfway along). Held at the crank at angle θ, the rocker is a
/// two-force member and the body's moments about the crank's end give the rocker's force:
/// `(W_body + W_rocker) / (2 sin θ)` in compression, the body bar `−cos θ` times that, the crank
/// `(W_body + W_crank)/2 · sin θ − (W_body + W_rocker)/2 · cos² θ / sin θ` along it, and the
/// holding torque `(W_body + (W_crank + W_rocker)/2) r cos θ`.
#[test]
fn a_parallelogram_has_the_closed_form_forces() {
    let r = 30.0;
    let at = |deg: f64| Point::new(r * deg.to_radians().cos(), r * deg.to_radians().sin());
    let (p, q) = (at(30.0), at(120.0));
    let scene = Scene::from_json(&format!(
        r#"{{"linkwright": "scene/1", "name": "parallelogram", "units": "mm",
            "fixed_bodies": [{{"name": "base", "polygon": [[-20, -90], [100, -90], [100, -70], [-20, -70]]}}],
            "moving_bodies": [{{"name": "plate", "polygon": [[0, -5], [60, -5], [60, 5], [0, 5]],
                                "poses": [[{}, {}, 0], [{}, {}, 0]]}}]}}"#,
        p.x, p.y, q.x, q.y
    ))
    .unwrap();
    let problem = Problem::new(&scene).unwrap();
    let topology = Arc::new(Topology::chain(1));
    let mut joints = vec![Point::ORIGIN; topology.joint_count()];
    for (name, at) in
        [("q0", Point::ORIGIN), ("r0", Point::new(60.0, 0.0)), ("p1", p), ("q1", p + Vec2::new(60.0, 0.0))]
    {
        joints[topology.joint(name).unwrap()] = at;
    }
    let mechanism = Mechanism { topology, joints, slider: None };
    let plan = Plan::compile(&mechanism).unwrap();
    let mut trace = Trace::new(plan.joint_count());
    trace.sweep(&plan, 30f64.to_radians(), 120f64.to_radians(), 1f64.to_radians()).unwrap();
    let (body, crank, rocker) = (7.0, 0.4, 0.25);
    let masses: Vec<f64> = mechanism
        .topology
        .parts
        .iter()
        .map(|part| match part.name.as_str() {
            "body1" => body,
            "crank" => crank,
            "rocker" => rocker,
            _ => 0.0,
        })
        .collect();
    let rows = equilibrium(&problem, &mechanism, &trace, &masses).unwrap();
    let (wb, wc, wr) = (body * GRAVITY, crank * GRAVITY, rocker * GRAVITY);
    let edge = |row: &linkwright_core::workshop::RowForces, part: &str| {
        let k = part_index(&mechanism, part);
        row.edges.iter().find(|e| e.part == k).unwrap().compression_n
    };
    for row in &rows {
        let theta = row.crank_deg.to_radians();
        let (s, c) = theta.sin_cos();
        let rocker_force = (wb + wr) / (2.0 * s);
        let tol = 1e-9 * (wb + wc + wr) / s;
        assert!((edge(row, "rocker") - rocker_force).abs() < tol, "{} at {:.1}°", edge(row, "rocker"), row.crank_deg);
        assert!((edge(row, "body1") + rocker_force * c).abs() < tol);
        let crank_force = (wb + wc) / 2.0 * s - (wb + wr) / 2.0 * c * c / s;
        assert!((edge(row, "crank") - crank_force).abs() < tol, "{} against {crank_force}", edge(row, "crank"));
        let torque = (wb + (wc + wr) / 2.0) * r / 1000.0 * c;
        assert!((row.torque_nm - torque).abs() < 1e-9, "{} against {torque}", row.torque_nm);
        // The bolt at the rocker's end carries the rocker's force.
        let q1 = joint(&mechanism, "q1");
        let rocker_on_q1 = row.pin_force(part_index(&mechanism, "rocker"), q1);
        assert!(
            (rocker_on_q1.norm() - ((rocker_force * c).powi(2) + (rocker_force * s - wr / 2.0).powi(2)).sqrt()).abs()
                < tol
        );
    }
}

/// The parts' potential energy with the joints at `row` of a four-bar (q0, r0, p1, q1), J: the body's
/// centre carried by p1 and q1, each bar's at its middle. Drawn in millimetres.
fn four_bar_energy(problem: &Problem, m: &Mechanism, masses: &[f64], row: &[Point]) -> f64 {
    let (p1, q1, q0, r0) = (joint(m, "p1"), joint(m, "q1"), joint(m, "q0"), joint(m, "r0"));
    let first = problem.bodies[0].poses[0].apply(problem.bodies[0].outline.centroid());
    let (a0, b0) = (m.joints[p1], m.joints[q1]);
    let turn = (row[q1] - row[p1]).angle() - (b0 - a0).angle();
    let local = first - a0;
    let com =
        row[p1] + Vec2::new(local.x * turn.cos() - local.y * turn.sin(), local.x * turn.sin() + local.y * turn.cos());
    let up = -problem.gravity;
    let height = |x: Point| (x - Point::ORIGIN).dot(up) / 1000.0;
    let mid = |a: Point, b: Point| a.lerp(b, 0.5);
    GRAVITY
        * (masses[part_index(m, "body1")] * height(com)
            + masses[part_index(m, "crank")] * height(mid(row[q0], row[p1]))
            + masses[part_index(m, "rocker")] * height(mid(row[r0], row[q1])))
}

/// The point of `circle_circle`'s two answers nearest `near`.
fn nearest_intersection(a: Point, ra: f64, b: Point, rb: f64, near: Point) -> Point {
    [Branch::Positive, Branch::Negative]
        .into_iter()
        .map(|branch| circle_circle(a, ra, b, rb, branch).unwrap())
        .min_by(|x, y| x.distance(near).total_cmp(&y.distance(near)))
        .unwrap()
}

/// Virtual work, evaluated the long way: lengthen one link by ±h with the crank's angle held, solve
/// the four-bar's kinematics again (its dyad at q1), and take the central difference of the parts'
/// potential energy. That derivative is the link's axial force (compression positive); the
/// equilibrium's must match it for the crank and the rocker. (The body's own pair of joints is not
/// compared: how a body would stretch is a choice, and its "force" is no part's load.)
#[test]
fn a_link_force_is_the_energy_derivative_with_respect_to_its_length() {
    for seed in [3, 5, 9] {
        let (known, problem) = known_four_bar(seed, 12.0);
        let m = &known.mechanism;
        let (_, trace) = sweep(&known, 5.0);
        let masses: Vec<f64> = m
            .topology
            .parts
            .iter()
            .map(|p| match p.name.as_str() {
                "body1" => 12.0,
                "crank" => 0.8,
                "rocker" => 0.5,
                _ => 0.0,
            })
            .collect();
        let rows = equilibrium(&problem, m, &trace, &masses).unwrap();
        let (q0, r0, p1, q1) = (joint(m, "q0"), joint(m, "r0"), joint(m, "p1"), joint(m, "q1"));
        let (crank, rocker) = (part_index(m, "crank"), part_index(m, "rocker"));
        let h = 1e-4;
        for (r, forces) in rows.iter().enumerate() {
            let row = trace.row(r);
            let energy = |pos: &[Point]| four_bar_energy(&problem, m, &masses, pos);
            let (lc, lb, lr) = (row[q0].distance(row[p1]), row[p1].distance(row[q1]), row[r0].distance(row[q1]));
            let along = (row[p1] - row[q0]).normalized();
            let moved = |dc: f64, db: f64, dr: f64| {
                let mut pos = row.to_vec();
                pos[p1] = row[q0] + along * (lc + dc);
                pos[q1] = nearest_intersection(pos[p1], lb + db, row[r0], lr + dr, row[q1]);
                energy(&pos)
            };
            // J per mm of length: ×1000 for newtons.
            let derivative = |f: &dyn Fn(f64) -> f64| (f(h) - f(-h)) / (2.0 * h) * 1000.0;
            let expected =
                [(crank, derivative(&|d| moved(d, 0.0, 0.0))), (rocker, derivative(&|d| moved(0.0, 0.0, d)))];
            for (part, value) in expected {
                let got = forces.edges.iter().find(|e| e.part == part).unwrap().compression_n;
                assert!(
                    (got - value).abs() < 1e-5 * (1.0 + value.abs()),
                    "seed {seed} at {:.1}°: part {part}: {got} against {value}",
                    forces.crank_deg
                );
            }
        }
    }
}

/// The holding torque is the statics module's driving torque (its own virtual work, by joint
/// velocities), up to the sense of the travel, and the forces balance at every bolt.
#[test]
fn the_holding_torque_is_the_statics_driving_torque() {
    for (kind, seed) in [
        (Known::chain(1), 3),
        (Known::chain(2), 5),
        (Known::one(MechanismType::SliderCrank), 2),
        (Known::one(MechanismType::WattTwo), 4),
    ] {
        let mut known = known_scene(kind, 3, seed, 1000.0).unwrap();
        for (k, b) in known.scene.moving_bodies.iter_mut().enumerate() {
            b.mass_kg = Some(10.0 + 5.0 * k as f64);
        }
        let problem = Problem::new(&known.scene).unwrap();
        let (plan, trace) = sweep(&known, 3.0);
        let m = &known.mechanism;
        let masses: Vec<f64> = m
            .topology
            .parts
            .iter()
            .map(|p| match p.kind {
                linkwright_core::PartKind::Body(b) => 10.0 + 5.0 * b as f64,
                _ => 0.0,
            })
            .collect();
        let rows = equilibrium(&problem, m, &trace, &masses).unwrap();
        // Weightless printed links, bodies at the scene's masses.
        let weightless =
            Masses::printed(&PrintSettings { density: 0.0, ..PrintSettings::default() }, &Default::default());
        let torque = driving_torque(&problem, m, &plan, &trace, &weightless).unwrap();
        let along = (trace.thetas[trace.len() - 1] - trace.thetas[0]).signum();
        for (row, &tau) in rows.iter().zip(&torque.torque_nm) {
            assert!(
                (row.torque_nm * along - tau).abs() < 1e-6 * (1.0 + tau.abs()),
                "{kind}: {} against {tau}",
                row.torque_nm
            );
            for j in 0..plan.joint_count() {
                let sum = row.pins.iter().filter(|p| p.joint == j).fold(Vec2::ZERO, |s, p| s + p.force_n);
                assert!(sum.norm() < 1e-6, "{kind}: the forces on joint {j} do not balance: {sum:?}");
            }
        }
    }
}

/// ISO 273, medium series.
const ISO_273_MEDIUM: [(BoltSize, f64); 8] = [
    (BoltSize::M5, 5.5),
    (BoltSize::M6, 6.6),
    (BoltSize::M8, 9.0),
    (BoltSize::M10, 11.0),
    (BoltSize::M12, 13.5),
    (BoltSize::M16, 17.5),
    (BoltSize::M20, 22.0),
    (BoltSize::M24, 26.0),
];

/// Every hole of every part, and every hole in the DXF, is the ISO 273 medium clearance hole of the
/// bolt asked for.
#[test]
fn holes_are_iso_273_medium_clearance_holes() {
    let (known, problem) = known_four_bar(7, 5.0);
    for (size, hole) in ISO_273_MEDIUM.into_iter().take(5) {
        let settings = WorkshopSettings { bolt: Some(size), ..WorkshopSettings::default() };
        let w = plan(&problem, &known.design(), Material::Aluminium, &settings).unwrap();
        assert_eq!((w.bolt.size, w.bolt.hole_mm), (size, hole));
        let iso = |b: BoltSize| ISO_273_MEDIUM.iter().find(|x| x.0 == b).unwrap().1;
        let mut diameters = Vec::new();
        for link in &w.links {
            assert_eq!(link.hole_mm, hole);
            for h in &link.outline.holes {
                match h {
                    linkwright_core::workshop::Hole::Round { diameter_mm, purpose, .. } if purpose == "fixing" => {
                        assert_eq!(*diameter_mm, iso(link.fixing_bolt.unwrap()));
                        diameters.push(*diameter_mm);
                    }
                    linkwright_core::workshop::Hole::Round { diameter_mm, .. } => {
                        assert_eq!(*diameter_mm, hole);
                        diameters.push(*diameter_mm);
                    }
                    linkwright_core::workshop::Hole::Slot { width_mm, .. } => assert_eq!(*width_mm, hole),
                }
            }
        }
        let mut circles = Vec::new();
        for (_, bytes) in files(&w).iter().filter(|(n, _)| n.ends_with(".dxf")) {
            circles.extend(
                dxf_entities(&String::from_utf8(bytes.clone()).unwrap(), "CIRCLE").into_iter().map(|c| 2.0 * c.radius),
            );
        }
        // The DXF's circles are the holes, diameter for diameter.
        let sorted = |mut v: Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v
        };
        let (circles, diameters) = (sorted(circles), sorted(diameters));
        assert_eq!(circles.len(), diameters.len());
        assert!(circles.iter().zip(&diameters).all(|(a, b)| (a - b).abs() < 1e-4), "{circles:?} against {diameters:?}");
    }
}

/// The documented design values (docs/fabrication.md, "Full size"), written out here: tension,
/// compression, modulus, bearing strength under a bolt of diameter d, edge distance from a hole's
/// centre, and the most width per thickness.
fn documented(material: Material, d: f64, d0: f64) -> (f64, f64, f64, f64, f64, f64) {
    match material {
        Material::Plywood => (30.0, 25.0, 7_000.0, 0.11 * (1.0 - 0.01 * d) * 630.0, 3.0 * d, 6.0),
        Material::Aluminium => (240.0, 240.0, 70_000.0, 1.5 * 240.0, 1.2 * d0, 12.0),
        Material::Steel => (235.0, 235.0, 210_000.0, 1.5 * 235.0, 1.2 * d0, 12.0),
    }
}

/// Whether a link `w` × `t` carries its loads by every inequality of the rule, written out afresh.
fn holds(link: &LinkPlan, w: &Workshop, width: f64, t: f64) -> Result<(), String> {
    let (d, d0, s) = (w.bolt.diameter_mm, w.bolt.hole_mm, w.settings.safety_factor);
    let (ft, fc, e, fb, edge, ratio) = documented(w.material, d, d0);
    let l = &link.loads;
    let length = link.pivot_lengths.iter().map(|p| p.length_mm).fold(0.0, f64::max);
    let shear_strength = 0.6 * 800.0 * link.fixing_bolt.unwrap_or(w.bolt.size).spec().stress_area_mm2;
    let two_bolts = link.kind != LinkKind::Link;
    // A bracket's fixing bolts: across it, each an edge distance from a side.
    let fixing_bolt = link.fixing_bolt.unwrap_or(w.bolt.size).spec();
    let (df, df0) = (fixing_bolt.diameter_mm, fixing_bolt.hole_mm);
    let (_, _, _, fbf, edge_f, _) = documented(w.material, df, df0);
    let least_spacing = match w.material {
        Material::Plywood => 4.0 * df,
        _ => 2.2 * df0,
    };
    let spacing = width - 2.0 * edge_f;
    let mut fails = Vec::new();
    let mut need = |ok: bool, what: &str| {
        if !ok {
            fails.push(what.to_string());
        }
    };
    // The shear on each fixing bolt at this width: half the resultant, and the moment over their spacing.
    let fixing = if two_bolts { l.axial_n / 2.0 + l.moment_nm * 1000.0 / spacing } else { 0.0 };
    need(s * l.hole_n <= fb * d * t * (1.0 + 1e-9), "bearing");
    need(s * fixing <= fbf * df * t * (1.0 + 1e-9), "fixing bolt bearing");
    need(width >= (2.0 * edge).max(2.5 * d) - 1e-9, "edge distance");
    need(!two_bolts || width >= (2.0 * edge_f).max(2.5 * df) - 1e-9, "edge distance of the fixing bolts");
    need(!two_bolts || spacing >= least_spacing - 1e-9, "room for two fixing bolts");
    need(width <= ratio * t + 1e-9, "width to thickness");
    need(s * l.tension_n <= ft * (width - d0) * t * (1.0 + 1e-9), "net tension");
    need(s * l.compression_n <= fc * (width - d0) * t * (1.0 + 1e-9), "compression");
    if link.kind == LinkKind::Link {
        let inertia = (width * t.powi(3)).min(t * width.powi(3)) / 12.0;
        let euler = std::f64::consts::PI.powi(2) * e * inertia / (length * length);
        need(s * l.compression_n <= euler * (1.0 + 1e-9), "buckling");
    }
    if l.moment_nm > 0.0 {
        let (area, inertia) = if two_bolts {
            (
                (width - 2.0 * d0) * t,
                t * width.powi(3) / 12.0 - 2.0 * (t * d0.powi(3) / 12.0 + t * d0 * (spacing / 2.0).powi(2)),
            )
        } else {
            ((width - d0) * t, t * (width.powi(3) - d0.powi(3)) / 12.0)
        };
        let stress = s * (l.axial_n / area + l.moment_nm * 1000.0 * (width / 2.0) / inertia);
        need(area > 0.0 && inertia > 0.0 && stress <= ft.min(fc) * (1.0 + 1e-9), "bending");
    }
    if two_bolts {
        need(s * fixing <= shear_strength * (1.0 + 1e-9), "fixing bolt shear");
    }
    if fails.is_empty() {
        Ok(())
    } else {
        Err(fails.join(", "))
    }
}

/// Each part's width and thickness satisfy every inequality of the strength rule (written out here
/// from its documentation, not taken from the plan's own checks), and the next thinner stock
/// would not do at any width up to its width-to-thickness limit. Loaded hard enough that the
/// thickness is not simply the thinnest stock.
#[test]
fn sections_hold_every_inequality_and_thinner_stock_would_not() {
    let mut thicker_than_thinnest = 0;
    for (material, kg) in [(Material::Plywood, 30.0), (Material::Aluminium, 150.0), (Material::Steel, 300.0)] {
        let (known, problem) = known_four_bar(3, kg);
        let w = plan(&problem, &known.design(), material, &WorkshopSettings::default()).unwrap();
        let stocks = &w.values.thicknesses_mm;
        for link in &w.links {
            holds(link, &w, link.width_mm, link.thickness_mm)
                .unwrap_or_else(|e| panic!("{material:?} {}: {e}", link.name));
            assert!(link.checks.iter().all(|c| c.ok), "{:?}", link.checks);
            // The width is whole millimetres, and one less fails.
            assert_eq!(link.width_mm, link.width_mm.round());
            assert!(holds(link, &w, link.width_mm - 1.0, link.thickness_mm).is_err(), "{material:?} {}", link.name);
            let k = stocks.iter().position(|&t| t == link.thickness_mm).unwrap();
            if k > 0 {
                thicker_than_thinnest += 1;
                let thinner = stocks[k - 1];
                let (_, _, _, _, _, ratio) = documented(material, w.bolt.diameter_mm, w.bolt.hole_mm);
                let mut width = 0.0;
                while width <= ratio * thinner {
                    assert!(
                        holds(link, &w, width, thinner).is_err(),
                        "{material:?} {}: {thinner} mm at {width} mm holds",
                        link.name
                    );
                    width += 0.5;
                }
                assert!(link.thinner_fails.is_some());
            }
        }
    }
    assert!(thicker_than_thinnest >= 3, "the loads should need more than the thinnest stock: {thicker_than_thinnest}");
}

/// A DXF entity read back from group codes: its type, layer, centre and radius.
#[derive(Debug)]
struct DxfEntity {
    layer: String,
    centre: Point,
    radius: f64,
}

/// The entities of one type in an ASCII DXF, read pair by pair (code line, value line).
fn dxf_entities(text: &str, kind: &str) -> Vec<DxfEntity> {
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines.len() % 2 == 0, "a DXF is pairs of lines");
    let pairs: Vec<(i32, &str)> = lines.chunks(2).map(|c| (c[0].trim().parse().expect("a group code"), c[1])).collect();
    assert_eq!(pairs.last(), Some(&(0, "EOF")));
    let mut out = Vec::new();
    let mut k = 0;
    while k < pairs.len() {
        if pairs[k] == (0, kind) {
            let mut e = DxfEntity { layer: String::new(), centre: Point::ORIGIN, radius: 0.0 };
            k += 1;
            while k < pairs.len() && pairs[k].0 != 0 {
                let (code, value) = pairs[k];
                match code {
                    8 => e.layer = value.to_string(),
                    10 => e.centre.x = value.parse().unwrap(),
                    20 => e.centre.y = value.parse().unwrap(),
                    40 => e.radius = value.parse().unwrap(),
                    _ => {}
                }
                k += 1;
            }
            out.push(e);
        } else {
            k += 1;
        }
    }
    out
}

/// The centres and radii of the arcs of an SVG path of `M x,y`, `L x,y`, `A r,r 0 large sweep x,y`
/// and `Z`, by SVG's own conversion from endpoints to centre (SVG 1.1, appendix F.6.5, without
/// rotation and with equal radii).
fn svg_arc_centres(d: &str) -> Vec<(Point, f64)> {
    let xy = |t: &str| {
        let (x, y) = t.split_once(',').unwrap();
        Point::new(x.parse().unwrap(), y.parse().unwrap())
    };
    let tokens: Vec<&str> = d.split_whitespace().collect();
    let (mut out, mut at, mut k) = (Vec::new(), Point::ORIGIN, 0);
    while k < tokens.len() {
        let t = tokens[k];
        match &t[..1] {
            "M" | "L" => {
                at = xy(&t[1..]);
                k += 1;
            }
            "A" => {
                let r: f64 = t[1..].split_once(',').unwrap().0.parse().unwrap();
                let (large, sweep) = (tokens[k + 2] == "1", tokens[k + 3] == "1");
                let end = xy(tokens[k + 4]);
                let half = (at - end) * 0.5;
                let sign = if large != sweep { 1.0 } else { -1.0 };
                let factor = sign * ((r * r - half.norm_sq()).max(0.0) / half.norm_sq()).sqrt();
                out.push((at.lerp(end, 0.5) + Vec2::new(half.y, -half.x) * factor, r));
                at = end;
                k += 5;
            }
            _ => k += 1,
        }
    }
    out
}

/// The profiles read back: the SVG as XML (a group per part, a circle per round hole, the rounded
/// ends of a link's outline concentric with its holes), the DXF as group codes (a `CIRCLE` per round
/// hole on the part's layer, outlines of lines and arcs whose circles sit as far apart as the part's
/// joints).
#[test]
fn profiles_read_back_with_every_hole() {
    let (known, problem) = known_four_bar(11, 40.0);
    let w = plan(&problem, &known.design(), Material::Plywood, &WorkshopSettings::default()).unwrap();
    let written = files(&w);
    for name in &w.files {
        assert!(written.iter().any(|(n, _)| n == name), "{name} is written");
    }
    let mut parts_seen = 0;
    for (name, bytes) in &written {
        let text = String::from_utf8(bytes.clone()).unwrap();
        let Some(thickness) = name.strip_prefix("profiles_").and_then(|r| r.split("mm.").next()) else { continue };
        let thickness: f64 = thickness.parse().unwrap();
        let parts: Vec<&LinkPlan> = w.links.iter().filter(|l| l.thickness_mm == thickness).collect();
        let holes: usize = parts.iter().map(|p| p.outline.round_holes()).sum();
        if name.ends_with(".svg") {
            let doc = roxmltree::Document::parse(&text).unwrap();
            let circles = doc.descendants().filter(|n| n.has_tag_name("circle")).count();
            assert_eq!(circles, holes, "{name}");
            let groups: Vec<&str> =
                doc.descendants().filter(|n| n.has_tag_name("g")).filter_map(|n| n.attribute("id")).collect();
            assert_eq!(groups.len(), parts.len());
            assert!(doc.root_element().attribute("width").unwrap().ends_with("mm"));
            for p in parts.iter().filter(|p| p.kind == LinkKind::Link) {
                let group = doc.descendants().find(|n| n.attribute("id") == Some(p.name.as_str())).unwrap();
                let holes: Vec<Point> = group
                    .descendants()
                    .filter(|n| n.has_tag_name("circle"))
                    .map(|c| {
                        Point::new(
                            c.attribute("cx").unwrap().parse().unwrap(),
                            c.attribute("cy").unwrap().parse().unwrap(),
                        )
                    })
                    .collect();
                let outline = group.descendants().find(|n| n.has_tag_name("path")).unwrap().attribute("d").unwrap();
                let arcs = svg_arc_centres(outline);
                // Each rounded end split in two half arcs.
                assert_eq!(arcs.len(), 2 * p.outline.centres.len(), "{}", p.name);
                for (centre, r) in arcs {
                    assert!((r - p.width_mm / 2.0).abs() < 1e-3);
                    assert!(
                        holes.iter().any(|h| h.distance(centre) < 1e-2),
                        "{}: an end arc about {centre:?}, holes {holes:?}",
                        p.name
                    );
                }
            }
            parts_seen += parts.len();
        } else {
            let circles = dxf_entities(&text, "CIRCLE");
            assert_eq!(circles.len(), holes, "{name}");
            let lines = dxf_entities(&text, "LINE").len();
            let arcs = dxf_entities(&text, "ARC").len();
            let hull: usize = parts.iter().map(|p| p.outline.centres.len()).sum();
            assert_eq!((lines, arcs), (hull, hull), "{name}: each side of a hull a line, each corner an arc");
            for p in parts.iter().filter(|p| p.kind == LinkKind::Link && p.joints.len() == 2) {
                let layer = linkwright_core::fab::sanitize(&p.name);
                let on: Vec<&DxfEntity> = circles.iter().filter(|c| c.layer == layer).collect();
                assert_eq!(on.len(), 2, "{}", p.name);
                let apart = on[0].centre.distance(on[1].centre);
                assert!((apart - p.pivot_lengths[0].length_mm).abs() < 1e-3, "{}: {apart}", p.name);
            }
        }
    }
    assert_eq!(parts_seen, w.links.len());
    let json: serde_json::Value =
        serde_json::from_slice(&written.iter().find(|(n, _)| n == "workshop.json").unwrap().1).unwrap();
    assert_eq!(json["linkwright"], "workshop/1");
    roxmltree::Document::parse(
        std::str::from_utf8(&written.iter().find(|(n, _)| n == "workshop_assembly.svg").unwrap().1).unwrap(),
    )
    .unwrap();
}

/// The bundled full-size wall bed (a 60 kg bed on a 2 m × 30 cm panel), designed with a short
/// search for a plywood build: every link of the design is listed with its pivot lengths, section and
/// holes, every joint has its bolt, and the bill of materials has the bolts, nuts and washers the
/// stacks use and every spring asked for.
#[test]
fn the_full_size_wall_bed_lists_every_link_bolt_and_the_bill_of_materials() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/k1_wall_bed_full_size.json");
    let mut scene = Scene::from_json(&std::fs::read_to_string(path).unwrap()).unwrap();
    scene.build = Build::Full(Material::Plywood);
    // A four-bar, the wall bed's usual linkage.
    scene.mechanism = linkwright_core::MechanismChoice::Only(linkwright_core::MechanismType::Chain);
    scene.settings.samples = 3000;
    scene.settings.iterations = 2;
    let problem = Problem::new(&scene).unwrap();
    let outcome = linkwright_core::synthesize(&problem, &Silent).unwrap();
    let design = DesignFile::from_outcome(&problem, &outcome);
    let mechanism = design.mechanism.as_ref().expect("a design").to_mechanism().unwrap();
    let settings =
        WorkshopSettings::from_json(r#"{"springs": [{"rate_n_per_mm": 1.8, "free_length_mm": 420, "count": 2}]}"#)
            .unwrap();
    let w = plan(&problem, &design, Material::Plywood, &settings).unwrap();
    assert_eq!(w.masses.iter().find(|m| m.part == "body1").map(|m| (m.kg, m.source)), Some((60.0, "scene")));
    for part in mechanism.topology.parts.iter().filter(|p| p.kind == linkwright_core::PartKind::Link) {
        let link = w.links.iter().find(|l| l.name == part.name).unwrap_or_else(|| panic!("{} is listed", part.name));
        assert!(link.width_mm > 0.0 && w.values.thicknesses_mm.contains(&link.thickness_mm));
        assert!(!link.pivot_lengths.is_empty() && link.outline.round_holes() >= part.joints.len());
        assert!(link.checks.iter().all(|c| c.ok), "{}: {:?}", link.name, link.checks);
        // A 60 kg bed on plywood links: more than the thinnest sheet.
        assert!(link.loads.hole_n > 100.0, "{}: {:?}", link.name, link.loads);
    }
    for name in &mechanism.topology.joint_names {
        let bolt = w.bolts.iter().find(|b| &b.at == name).unwrap_or_else(|| panic!("joint {name} has a bolt"));
        assert!(bolt.checks.iter().all(|c| c.ok) && bolt.length_mm >= bolt.needed_mm, "{bolt:?}");
    }
    let count = |what: &str| w.bill_of_materials.iter().filter(|b| b.item.contains(what)).map(|b| b.count).sum::<u32>();
    let bolts: u32 = w.bolts.iter().map(|b| b.count).sum();
    assert_eq!(count("hex bolt"), bolts);
    assert_eq!(count("nut"), bolts);
    let washers: u32 =
        w.bolts.iter().map(|b| b.count * b.stack.iter().filter(|s| s.item == "washer").count() as u32).sum();
    assert_eq!(count("washer"), washers);
    assert_eq!(count("extension spring"), 2);
    let cut: u32 = w.cut_list.iter().map(|c| c.count).sum();
    assert_eq!(cut as usize, w.links.len());
    assert!(w.peak_torque_nm > 10.0, "a 60 kg bed needs holding: {}", w.peak_torque_nm);
    assert_failures_are_noted(&w);
}

/// Every check that does not hold, of a part or of a bolt, is in the plan's notes (nothing fails
/// silently).
fn assert_failures_are_noted(w: &Workshop) {
    let failing = w
        .links
        .iter()
        .flat_map(|l| l.checks.iter().filter(|c| !c.ok).map(move |c| (l.name.as_str(), c.rule.as_str())))
        .chain(
            w.bolts
                .iter()
                .flat_map(|b| b.checks.iter().filter(|c| !c.ok).map(move |c| (b.at.as_str(), c.rule.as_str()))),
        );
    for (at, rule) in failing {
        assert!(
            w.notes.iter().any(|n| n.contains(at) && n.contains(rule)),
            "{at}: {rule} fails without a note: {:?}",
            w.notes
        );
    }
}

/// Every family of linkage plans: each of its links is cut, each of its joints has a bolt through
/// the parts on it (in the order of their layers), and the forces at every bolt balance.
#[test]
fn every_family_plans_with_a_bolt_at_every_joint() {
    for (kind, seed) in [
        (Known::chain(1), 1),
        (Known::chain(2), 5),
        (Known::one(MechanismType::SliderCrank), 2),
        (Known::one(MechanismType::WattTwo), 4),
        (Known::one(MechanismType::StephensonThree), 6),
    ] {
        let mut known = known_scene(kind, 3, seed, 1000.0).unwrap();
        for b in &mut known.scene.moving_bodies {
            b.mass_kg = Some(10.0);
        }
        let problem = Problem::new(&known.scene).unwrap();
        let w = plan(&problem, &known.design(), Material::Aluminium, &WorkshopSettings::default())
            .unwrap_or_else(|e| panic!("{kind}: {e}"));
        let m = &known.mechanism;
        for part in m.topology.parts.iter().filter(|p| p.kind == linkwright_core::PartKind::Link) {
            let link = w.links.iter().find(|l| l.name == part.name).unwrap_or_else(|| panic!("{kind}: {}", part.name));
            assert_eq!(link.pivot_lengths.len(), part.joints.len() * (part.joints.len() - 1) / 2);
        }
        for name in &m.topology.joint_names {
            let bolt = w.bolts.iter().find(|b| &b.at == name).unwrap_or_else(|| panic!("{kind}: joint {name}"));
            let parts: Vec<&str> =
                bolt.stack.iter().filter(|s| s.item == "part").filter_map(|s| s.name.as_deref()).collect();
            let layers: Vec<u32> = parts.iter().map(|p| w.links.iter().find(|l| l.name == *p).unwrap().layer).collect();
            assert!(layers.windows(2).all(|l| l[0] < l[1]), "{kind} {name}: {parts:?} on layers {layers:?}");
        }
        assert_failures_are_noted(&w);
    }
}

/// Settings that cannot work are refused naming the field; a bolt asked for that is too weak is
/// refused naming the joint and the size that would hold.
#[test]
fn bad_settings_and_weak_bolts_are_refused_with_what_to_change() {
    let (known, problem) = known_four_bar(3, 20.0);
    let bad = WorkshopSettings { safety_factor: 0.0, ..WorkshopSettings::default() };
    match plan(&problem, &known.design(), Material::Steel, &bad) {
        Err(WorkshopError::Settings(issues)) => assert_eq!(issues[0].field, "safety_factor"),
        other => panic!("{other:?}"),
    }
    let (known, problem) = known_four_bar(3, 3000.0);
    let weak = WorkshopSettings { bolt: Some(BoltSize::M5), ..WorkshopSettings::default() };
    match plan(&problem, &known.design(), Material::Steel, &weak) {
        Err(e @ WorkshopError::BoltTooWeak { needed: Some(needed), .. }) => {
            assert!(needed > BoltSize::M5);
            assert!(e.to_string().contains(needed.name()), "{e}");
        }
        other => panic!("{other:?}"),
    }
}
