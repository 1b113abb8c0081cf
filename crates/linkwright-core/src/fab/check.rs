//! The checks every fabrication must pass, computed from the parts themselves (not from the ordering's
//! reasoning): every mesh is a closed, consistently oriented 2-manifold with a positive volume; every
//! pin, post and boss stands on its part's slab; no two parts overlap (and no part, pad, pin or post
//! enters a body) at any row of the motion, decided exactly on the parts' prisms with a polygon
//! library's overlap predicate (only the bodies as drawn may touch each other: that is the synthesis's
//! concern); every pin is coaxial with its holes at every row, with the set radial clearance and its
//! holes within its shaft; every recorded constraint holds; every spring has its hooks at its axis and
//! meets no part between them (its coil taken as wide as a link) at any row.

use super::depth::{violations, Constraint};
use super::fabrication::Fabrication;
use super::parts::{Prism, Role};
use crate::geom::{point_segment_distance, Aabb, Point, Rigid};
use i_overlay::float::relate::FloatRelate;
use serde::Serialize;

/// What the checks found (every list empty when all holds).
#[derive(Clone, Debug, Default, Serialize)]
pub struct CheckReport {
    /// Parts whose mesh is not closed or has no positive volume.
    pub meshes: Vec<String>,
    /// Pins, posts and bosses that do not stand wholly on their part's slab.
    pub supports: Vec<String>,
    /// Pairs of parts that overlap, with where.
    pub intersections: Vec<String>,
    /// Pins not seated in their holes.
    pub seats: Vec<String>,
    /// Recorded constraints the layers break.
    pub ordering: Vec<String>,
    /// Springs without a hook at an end, or meeting a part along the motion.
    pub springs: Vec<String>,
    /// Rows of the motion checked.
    pub rows: usize,
    /// Pairs of prisms whose overlap was decided by the polygon predicate.
    pub exact_tests: usize,
}

impl CheckReport {
    /// Whether every check holds (no finding in any list).
    pub fn ok(&self) -> bool {
        self.meshes.is_empty()
            && self.supports.is_empty()
            && self.intersections.is_empty()
            && self.seats.is_empty()
            && self.ordering.is_empty()
            && self.springs.is_empty()
    }
}

/// Runs every check over the fabrication's whole motion.
pub fn check(fab: &Fabrication) -> CheckReport {
    let mut report = CheckReport { rows: fab.trace.len(), ..CheckReport::default() };
    for p in &fab.parts {
        if let Err(e) = p.mesh.check_closed() {
            report.meshes.push(format!("{}: {e}", p.name));
        } else if p.mesh.volume() <= 0.0 {
            report.meshes.push(format!("{}: volume {} is not positive", p.name, p.mesh.volume()));
        }
        if let Err(e) = p.print_mesh.check_closed() {
            report.meshes.push(format!("{} (print orientation): {e}", p.name));
        }
    }
    let c: Vec<Constraint> = violations(&fab.layout, &fab.recorded, &fab.ordering);
    report.ordering = c.iter().map(|c| format!("{c:?}")).collect();
    supports(fab, &mut report);
    intersections(fab, &mut report);
    seats(fab, &mut report);
    springs(fab, &mut report);
    report
}

/// Each spring, a cylinder as wide as a link around its axis between its hooks: at its first pose each
/// end is on a hook (a prism spanning the axis's height and holding the end), and at no row does any
/// other prism reaching its height come within its radius.
fn springs(fab: &Fabrication, report: &mut CheckReport) {
    let d = &fab.dims;
    let radius = d.spring_radius();
    let mut poses: Vec<Rigid> = Vec::new();
    for n in 0..fab.springs.len() {
        let axis = fab.spring_axis_z(n);
        let coil = (axis - radius, axis + radius);
        let mut hooked = [false; 2];
        'rows: for r in 0..fab.trace.len() {
            let row = fab.trace.row(r);
            fab.layout.carrier_poses(row, &mut poses);
            let ends = [fab.layout.hook_at(2 * n, row, &poses), fab.layout.hook_at(2 * n + 1, row, &poses)];
            for p in &fab.parts {
                for pr in p.prisms.iter().filter(|pr| pr.z.0 < coil.1 && pr.z.1 > coil.0) {
                    let outline: Vec<Point> = pr.outline.iter().map(|&q| poses[p.carrier].apply(q)).collect();
                    let polygon = crate::geom::Polygon::new(outline);
                    let holds: Vec<bool> = ends.iter().map(|&e| polygon.contains(e)).collect();
                    if holds.contains(&true) {
                        // One of the spring's own hooks.
                        if r == 0 && pr.z.0 <= axis && pr.z.1 >= axis {
                            hooked[0] |= holds[0];
                            hooked[1] |= holds[1];
                        }
                        continue;
                    }
                    let near = polygon.edges().any(|(a, b)| super::shapes::core_distance(&ends, &[a, b]) < radius);
                    if near {
                        report.springs.push(format!(
                            "spring {} meets {} at crank {:.2}°",
                            n + 1,
                            p.name,
                            fab.trace.thetas[r].to_degrees()
                        ));
                        break 'rows;
                    }
                }
            }
        }
        for (e, end) in ["ground", "moving"].iter().enumerate() {
            if !hooked[e] {
                report.springs.push(format!("spring {}: no hook at its {end} end", n + 1));
            }
        }
    }
}

/// A prism in the world: contours, box, heights.
type Placed = (Vec<Vec<[f64; 2]>>, Aabb, (f64, f64));

fn is_body(r: Role) -> bool {
    matches!(r, Role::Body | Role::Ground)
}

fn intersections(fab: &Fabrication, report: &mut CheckReport) {
    let parts = &fab.parts;
    let scale = fab.dims.half_width;
    let ztol = 1e-9 * scale.max(1.0);
    let mut poses: Vec<Rigid> = Vec::new();
    let mut found: std::collections::BTreeSet<(usize, usize)> = Default::default();
    for r in 0..fab.trace.len() {
        fab.layout.carrier_poses(fab.trace.row(r), &mut poses);
        let world: Vec<Vec<Placed>> =
            parts.iter().map(|p| p.prisms.iter().map(|pr| place(pr, &poses[p.carrier])).collect()).collect();
        for a in 0..parts.len() {
            for b in a + 1..parts.len() {
                let (pa, pb) = (&parts[a], &parts[b]);
                if found.contains(&(a, b)) {
                    continue;
                }
                if r > 0 && pa.carrier == pb.carrier {
                    continue;
                }
                // Two bodies as drawn may touch (the synthesis's concern); what fabrication adds to them
                // (pads, pins, posts) may not enter anything.
                let both_bodies = is_body(pa.role) && is_body(pb.role);
                let pads_a: Vec<_> = pa.pads.iter().map(|pr| place(pr, &poses[pa.carrier])).collect();
                let pads_b: Vec<_> = pb.pads.iter().map(|pr| place(pr, &poses[pb.carrier])).collect();
                let (all_a, all_b) = (tagged(&world[a], &pads_a), tagged(&world[b], &pads_b));
                let pairs: Vec<(&Placed, &Placed)> = all_a
                    .iter()
                    .flat_map(|&(da, x)| all_b.iter().map(move |&(db, y)| (da && db, x, y)))
                    .filter(|&(drawn, _, _)| !(both_bodies && drawn))
                    .map(|(_, x, y)| (x, y))
                    .collect();
                'pairs: for ((sa, ba, za), (sb, bb, zb)) in pairs {
                    {
                        if za.1.min(zb.1) - za.0.max(zb.0) <= ztol || !ba.overlaps(bb, 0.0) {
                            continue;
                        }
                        report.exact_tests += 1;
                        if sa.interiors_intersect(sb) {
                            found.insert((a, b));
                            report.intersections.push(format!(
                                "{} and {} overlap at crank {:.2}° (heights {:.3}..{:.3} and {:.3}..{:.3})",
                                pa.name,
                                pb.name,
                                fab.trace.thetas[r].to_degrees(),
                                za.0,
                                za.1,
                                zb.0,
                                zb.1
                            ));
                            break 'pairs;
                        }
                    }
                }
            }
        }
    }
}

/// A part's prisms and pads, each with whether it is the part's slab (for a body: the body as drawn).
fn tagged<'p>(prisms: &'p [Placed], pads: &'p [Placed]) -> Vec<(bool, &'p Placed)> {
    let slabs = prisms.iter().enumerate().map(|(k, x)| (k == 0, x));
    slabs.chain(pads.iter().map(|x| (false, x))).collect()
}

/// Every prism standing on a part's slab (the first step of a pin, post or collar, a boss) lies within
/// the slab's outline and outside its holes: nothing hangs in the air.
fn supports(fab: &Fabrication, report: &mut CheckReport) {
    let tol = 1e-9 * fab.dims.half_width.max(1.0);
    for p in &fab.parts {
        let Some((slab, rest)) = p.prisms.split_first() else { continue };
        let base = place(slab, &Rigid::IDENTITY);
        for pr in rest {
            let on_top = (pr.z.0 - slab.z.1).abs() <= tol;
            let under = (pr.z.1 - slab.z.0).abs() <= tol;
            if !(on_top || under) {
                continue;
            }
            if !place(pr, &Rigid::IDENTITY).0.within(&base.0) {
                let c = crate::geom::Polygon::new(pr.outline.clone()).centroid();
                report
                    .supports
                    .push(format!("{}: the pillar at ({:.2}, {:.2}) is not wholly on the part", p.name, c.x, c.y));
            }
        }
    }
}

/// A prism in the world: contours (outline counter-clockwise, holes clockwise), box, heights.
fn place(p: &Prism, pose: &Rigid) -> Placed {
    let orient = |pts: &[Point], ccw: bool| -> Vec<[f64; 2]> {
        let mut v: Vec<[f64; 2]> = pts.iter().map(|&q| pose.apply(q)).map(|q| [q.x, q.y]).collect();
        let area = crate::geom::Polygon::new(pts.to_vec()).signed_area();
        if (area > 0.0) != ccw {
            v.reverse();
        }
        v
    };
    let mut contours = vec![orient(&p.outline, true)];
    contours.extend(p.holes.iter().map(|h| orient(h, false)));
    let bb = Aabb::around(contours[0].iter().map(|&[x, y]| Point::new(x, y)))
        .unwrap_or(Aabb { min: Point::ORIGIN, max: Point::ORIGIN });
    (contours, bb, p.z)
}

fn seats(fab: &Fabrication, report: &mut CheckReport) {
    let d = &fab.dims;
    let tol = 1e-7 * d.half_width.max(1e-9) * 100.0;
    let mut poses: Vec<Rigid> = Vec::new();
    for seat in &fab.seats {
        let name = &fab.layout_joint_name(seat.joint);
        let pin_part = &fab.parts[seat.pin_part];
        for (part, _, r, z) in &seat.holes {
            if ((r - seat.pin_radius) - d.clearance).abs() > 1e-9 * d.half_width {
                report.seats.push(format!(
                    "joint {name}: hole of {} has clearance {}",
                    fab.parts[*part].name,
                    r - seat.pin_radius
                ));
            }
            if z.0 < seat.shaft.0 - 1e-9 || z.1 > seat.shaft.1 + 1e-9 {
                report.seats.push(format!(
                    "joint {name}: the pin ({:.3}..{:.3}) does not go through {} ({:.3}..{:.3})",
                    seat.shaft.0, seat.shaft.1, fab.parts[*part].name, z.0, z.1
                ));
            }
        }
        if seat.holes.is_empty() && seat.slot.is_none() {
            report.seats.push(format!("joint {name}: the pin on {} goes through no hole", pin_part.name));
        }
        for r in 0..fab.trace.len() {
            fab.layout.carrier_poses(fab.trace.row(r), &mut poses);
            let axis = poses[pin_part.carrier].apply(seat.pin_at);
            for (part, at, _, _) in &seat.holes {
                let centre = poses[fab.parts[*part].carrier].apply(*at);
                if centre.distance(axis) > tol {
                    report.seats.push(format!(
                        "joint {name}: the hole of {} is {:.3e} off the pin at crank {:.2}°",
                        fab.parts[*part].name,
                        centre.distance(axis),
                        fab.trace.thetas[r].to_degrees()
                    ));
                    break;
                }
            }
            if let Some((part, (s0, s1), half, _)) = seat.slot {
                let pose = &poses[fab.parts[part].carrier];
                let off = point_segment_distance(axis, pose.apply(s0), pose.apply(s1));
                if off > tol || (half - seat.pin_radius - d.clearance).abs() > 1e-9 * d.half_width {
                    report.seats.push(format!("joint {name}: the pin leaves the guide's slot at row {r}"));
                    break;
                }
            }
        }
    }
}

impl Fabrication {
    /// The mechanism's name of joint `j`, or its index.
    pub fn layout_joint_name(&self, j: usize) -> String {
        self.joint_names.get(j).cloned().unwrap_or_else(|| j.to_string())
    }
}
