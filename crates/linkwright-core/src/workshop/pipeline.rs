//! [`plan`]: from a design to a [`Workshop`].
//!
//! 1. The moving bodies' masses (the scene's, or from their stock, or from their outline and the
//!    settings' thickness in the build's material).
//! 2. The links are sized in rounds: their weight from the last round's sizes, the forces along the
//!    motion ([`super::equilibrium`]), the smallest bolt whose shear holds every joint, each link's
//!    peak loads (kept from round to round, so sizes only grow and the rounds settle), and each
//!    link's section from the strength rule ([`super::sizing`]).
//! 3. The layers: fabrication's layout and depth ordering (`crate::fab::fabricate`) run at full size
//!    with the workshop's sizes as print settings: link width the widest link, pin the bolt, hole its
//!    clearance hole, the pin's column the washer, the gap between layers room for a nut. Its
//!    connectors become brackets, fixed to their body at the post by two bolts across them and sized
//!    for the force and moment they carry there. Every part as cut is then checked along the motion
//!    against every other on its face (`Context::clearances`): parts of one layer must not overlap,
//!    and no part may cross a bolt between the layers it joins. When a bracket wider than the links
//!    meets something, the layers are laid out again as if every part were that wide, and the layout
//!    that meets less is kept (what still meets is a note).
//! 4. The stack, the bolts, the cut list, the bill of materials and the steps.

use super::error::WorkshopError;
use super::forces::{equilibrium, RowForces};
use super::outline::{Hole, Outline};
use super::report::{
    file_names, number, profile_file, thicknesses, BomItem, CutItem, JointPlan, LinkKind, LinkLoads, LinkPlan,
    PartMass, PivotLength, Workshop, WORKSHOP_FORMAT,
};
use super::settings::WorkshopSettings;
use super::sizing::{Bending, Check, Demand, EdgeLoad, Rule, Section};
use super::stack::{Layered, Stack};
use super::standards::{BoltSize, BoltSpec, MaterialValues};
use crate::design::DesignFile;
use crate::fab::{
    Bed, Carrier, FabError, Fabrication, Face, Faces, Layout, Member, MemberKind, PrintSettings, SnapCap, Travel,
};
use crate::geom::{point_segment_distance, Point, Rigid, Vec2};
use crate::kinematics::Trace;
use crate::mechanism::{Mechanism, PartKind};
use crate::scene::{Material, Problem, Ratio};
use std::collections::BTreeMap;

/// Rounds of sizing the links before their weights are taken as settled.
const LINK_ROUNDS: usize = 12;

/// Plans the full-size build of `design` (a design of `problem`'s scene) in `material`: every link's
/// pivot lengths, section and holes, the bolts, the layer stack, the cut list, the bill of materials
/// and the assembly steps. The design must be valid and pass its check against the scene.
///
/// ```
/// use linkwright_core::testbed::{known_scene, Known};
/// use linkwright_core::workshop::{files, plan, WorkshopSettings};
/// use linkwright_core::{Material, Problem};
///
/// // A known four-bar drawn a metre across, its body weighing 20 kg, built in steel.
/// let mut known = known_scene(Known::chain(1), 3, 7, 1000.0)?;
/// known.scene.moving_bodies[0].mass_kg = Some(20.0);
/// let problem = Problem::new(&known.scene).expect("a valid scene");
/// let workshop = plan(&problem, &known.design(), Material::Steel, &WorkshopSettings::default())?;
///
/// // Its crank and rocker, each sized so that every inequality of the strength rule holds.
/// assert_eq!(workshop.links.iter().filter(|l| l.name == "crank" || l.name == "rocker").count(), 2);
/// assert!(workshop.links.iter().all(|l| l.checks.iter().all(|c| c.ok)));
/// let written = files(&workshop);
/// assert!(written.iter().any(|(name, _)| name == "workshop.json"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn plan(
    problem: &Problem,
    design: &DesignFile,
    material: Material,
    settings: &WorkshopSettings,
) -> Result<Workshop, WorkshopError> {
    let issues = settings.validate();
    if !issues.is_empty() {
        return Err(WorkshopError::Settings(issues));
    }
    let mm = problem.units.millimetres();
    let (mechanism, travel) = crate::fab::checked_design(problem, design).map_err(WorkshopError::Design)?;
    let trace = crate::fab::motion_trace(&mechanism, travel).map_err(WorkshopError::Design)?;
    let ctx = Context::new(problem, &mechanism, travel, &trace, mm, material, settings);
    let mut bolt_min = settings.bolt.unwrap_or(BoltSize::M5);
    let mut fixing_min: BTreeMap<String, BoltSize> = BTreeMap::new();
    let mut last = None;
    for _ in 0..BOLT_ROUNDS {
        let links = ctx.size_links(bolt_min)?;
        let (fab, fixed, gaps, conflicts) = ctx.lay_out(&links, &fixing_min)?;
        let notes =
            conflicts.into_iter().map(|c| format!("{c}: move the bracket's post, or choose another design.")).collect();
        let workshop = ctx.assemble(&links, &fab, &fixed, &gaps, notes);
        // A bolt that bends too far between the parts it holds: a larger one, and everything again.
        let mut again = false;
        for b in &workshop.bolts {
            if let Some(bracket) = b.at.strip_suffix(FIXING) {
                // A bracket's bolts, clamped through its stand-off: a size up while any check fails.
                let next = BoltSize::ALL.into_iter().find(|&s| s > b.bolt);
                if let (false, Some(next)) = (b.checks.iter().all(|c| c.ok), next) {
                    fixing_min.insert(bracket.to_string(), next);
                    again = true;
                }
                continue;
            }
            let Some(needed) = ctx.bolt_for_bending(b.moment_nm) else { continue };
            if needed <= b.bolt {
                continue;
            }
            again = true;
            match settings.bolt {
                Some(_) => {
                    return Err(WorkshopError::BoltTooWeak {
                        bolt: b.bolt,
                        at: b.at.clone(),
                        why: format!(
                            "it bends {:.1} N·m between the parts it holds, {} times that is more than the {:.1} N·m its thread \
                             core holds",
                            b.moment_nm,
                            settings.safety_factor,
                            b.bolt.spec().bending_strength_nm()
                        ),
                        needed: Some(needed),
                    });
                }
                None => bolt_min = bolt_min.max(needed),
            }
        }
        if !again {
            return Ok(workshop);
        }
        last = Some(workshop);
    }
    Ok(last.expect("at least one round"))
}

/// Rounds of choosing the bolts again when one bends too far (a larger bolt makes the parts around
/// it wider and its gaps larger, so its bending is checked again).
const BOLT_ROUNDS: usize = 5;

/// What a bracket's fixing bolts are called in [`JointPlan::at`]: the bracket's name, then this.
const FIXING: &str = " fixing";

/// What every stage reads.
struct Context<'a> {
    problem: &'a Problem,
    mechanism: &'a Mechanism,
    travel: Travel,
    trace: &'a Trace,
    /// Millimetres per scene unit.
    mm: f64,
    values: MaterialValues,
    settings: &'a WorkshopSettings,
    /// Per moving body: its mass, where the mass comes from, its thickness (mm) and material.
    bodies: Vec<(f64, &'static str, f64, Material)>,
    /// The ground's index among the topology's parts.
    ground: usize,
    /// The crank's index among the topology's parts.
    crank: Option<usize>,
}

/// The links sized: the bolt, each link part's loads and section, and the forces they were sized with.
struct LinkSizing {
    bolt: BoltSize,
    /// Per part of the topology (links only): its peak loads and section.
    sections: Vec<Option<(Demand, Section)>>,
    /// Per part of the topology: its mass, kg.
    masses: Vec<f64>,
    /// The forces along the motion with those masses.
    rows: Vec<RowForces>,
}

impl LinkSizing {
    fn widest(&self) -> f64 {
        self.sections.iter().flatten().map(|(_, s)| s.width_mm).fold(0.0, f64::max)
    }
    fn thickest(&self) -> f64 {
        self.sections.iter().flatten().map(|(_, s)| s.thickness_mm).fold(0.0, f64::max)
    }
}

/// A bracket, guide or frame sized: fixed to its carrier by two bolts at its post.
struct FixedPart {
    member: usize,
    name: String,
    demand: Demand,
    section: Section,
    /// The two fixing bolts' centres, carrier frame, scene units.
    fixings: Vec<Point>,
    /// The fixing bolts' size.
    fixing_bolt: BoltSpec,
    /// The largest shear on one fixing bolt, N.
    fixing_shear_n: f64,
}

impl<'a> Context<'a> {
    fn new(
        problem: &'a Problem,
        mechanism: &'a Mechanism,
        travel: Travel,
        trace: &'a Trace,
        mm: f64,
        material: Material,
        settings: &'a WorkshopSettings,
    ) -> Context<'a> {
        let bodies = problem
            .bodies
            .iter()
            .map(|b| {
                let area_mm2 = b.outline.area() * mm * mm;
                let (thickness, body_material) = match b.stock {
                    Some((m, t)) => (t * mm, m),
                    None => (settings.body_thickness_mm, material),
                };
                let weight = |m: Material| area_mm2 * thickness * m.density_kg_m3() * 1e-9;
                match (b.mass_kg, b.stock) {
                    (Some(kg), _) => (kg, "scene", thickness, body_material),
                    (None, Some((m, _))) => (weight(m), "stock", thickness, body_material),
                    (None, None) => (weight(material), "default", thickness, body_material),
                }
            })
            .collect();
        let topo = &mechanism.topology;
        let ground = topo.parts.iter().position(|p| p.kind == PartKind::Fixed).unwrap_or(0);
        let crank = topo.parts.iter().position(|p| {
            p.kind == PartKind::Link && p.joints.contains(&topo.driver_pivot) && p.joints.contains(&topo.driver_tip)
        });
        Context {
            problem,
            mechanism,
            travel,
            trace,
            mm,
            values: MaterialValues::of(material),
            settings,
            bodies,
            ground,
            crank,
        }
    }

    fn joint_name(&self, j: usize) -> String {
        self.mechanism.topology.joint_names[j].clone()
    }

    fn rule<'b>(&'b self, bolt: &'b BoltSpec, fixing: &'b BoltSpec) -> Rule<'b> {
        Rule { values: &self.values, bolt, fixing, factor: self.settings.safety_factor }
    }

    /// The smallest bolt whose one shear plane holds `shear_n` with the safety factor.
    fn bolt_for(&self, shear_n: f64, at: &str) -> Result<BoltSize, WorkshopError> {
        let s = self.settings.safety_factor;
        BoltSize::ALL
            .into_iter()
            .find(|b| s * shear_n <= b.spec().shear_strength_n())
            .ok_or_else(|| WorkshopError::NoBoltStrongEnough { at: at.to_string(), shear_n })
    }

    fn too_weak(&self, asked: BoltSize, needed: BoltSize, shear_n: f64, at: String) -> WorkshopError {
        WorkshopError::BoltTooWeak {
            bolt: asked,
            at,
            why: format!(
                "it takes {shear_n:.0} N in shear, {} times that is more than the {:.0} N one shear plane of it holds",
                self.settings.safety_factor,
                asked.spec().shear_strength_n()
            ),
            needed: Some(needed),
        }
    }

    /// A part's joints at the first pose, millimetres.
    fn core_mm(&self, joints: &[usize]) -> Vec<Point> {
        joints.iter().map(|&j| scaled(self.mechanism.joints[j], self.mm)).collect()
    }

    /// Every part's mass with the links at `sizes` (width, thickness per topology part).
    fn masses(&self, sizes: &[Option<(f64, f64)>]) -> Vec<f64> {
        self.mechanism
            .topology
            .parts
            .iter()
            .zip(sizes)
            .map(|(part, size)| match (part.kind, size) {
                (PartKind::Body(b), _) => self.bodies[b].0,
                (PartKind::Link, Some((w, t))) => {
                    // The solid outline, holes not taken out: a little heavier than cut.
                    Outline::new(&self.core_mm(&part.joints), 0.5 * w, Vec::new()).area_mm2()
                        * t
                        * self.values.density_kg_m3
                        * 1e-9
                }
                _ => 0.0,
            })
            .collect()
    }

    /// Link part `k`'s peak loads along `rows`.
    fn link_demand(&self, k: usize, rows: &[RowForces]) -> Demand {
        let part = &self.mechanism.topology.parts[k];
        let mut edges: Vec<EdgeLoad> = Vec::new();
        let mut hole_n = 0.0f64;
        let mut bending = (Some(k) == self.crank).then_some(Bending { moment_nm: 0.0, axial_n: 0.0, fixing: false });
        for row in rows {
            for e in row.edges.iter().filter(|e| e.part == k) {
                let label = format!("{}–{}", self.joint_name(e.joints[0]), self.joint_name(e.joints[1]));
                let at = match edges.iter().position(|x| x.label == label) {
                    Some(at) => at,
                    None => {
                        let [a, b] = e.joints;
                        let length_mm = self.mechanism.joints[a].distance(self.mechanism.joints[b]) * self.mm;
                        edges.push(EdgeLoad { label, length_mm, tension_n: 0.0, compression_n: 0.0 });
                        edges.len() - 1
                    }
                };
                edges[at].tension_n = edges[at].tension_n.max(-e.compression_n);
                edges[at].compression_n = edges[at].compression_n.max(e.compression_n);
                if let Some(b) = bending.as_mut() {
                    b.axial_n = b.axial_n.max(e.compression_n.abs());
                }
            }
            for &j in &part.joints {
                hole_n = hole_n.max(row.pin_force(k, j).norm());
            }
            if let Some(b) = bending.as_mut() {
                b.moment_nm = b.moment_nm.max(row.torque_nm.abs());
            }
        }
        Demand { edges, hole_n, bending }
    }

    /// Sizes every link, in rounds until their weights settle, with bolts of at least `bolt_min`.
    fn size_links(&self, bolt_min: BoltSize) -> Result<LinkSizing, WorkshopError> {
        let topo = &self.mechanism.topology;
        let n = topo.parts.len();
        let mut bolt = bolt_min;
        let mut demands: Vec<Option<Demand>> = vec![None; n];
        let thinnest = self.values.thicknesses_mm[0];
        let mut sizes: Vec<Option<(f64, f64)>> = topo
            .parts
            .iter()
            .map(|p| (p.kind == PartKind::Link).then(|| (self.values.min_width_mm(&bolt.spec()), thinnest)))
            .collect();
        let mut sections: Vec<Option<(Demand, Section)>> = vec![None; n];
        for _ in 0..LINK_ROUNDS {
            let masses = self.masses(&sizes);
            let rows = equilibrium(self.problem, self.mechanism, self.trace, &masses)?;
            let joint_shear: Vec<f64> =
                (0..topo.joint_count()).map(|j| rows.iter().map(|r| r.bolt_shear_n(j)).fold(0.0, f64::max)).collect();
            let (worst, shear) =
                joint_shear.iter().copied().enumerate().max_by(|a, b| a.1.total_cmp(&b.1)).unwrap_or((0, 0.0));
            let needed = self.bolt_for(shear, &self.joint_name(worst))?;
            let before = bolt;
            match self.settings.bolt {
                Some(asked) if needed > asked => {
                    return Err(self.too_weak(asked, needed, shear, self.joint_name(worst)))
                }
                Some(asked) => bolt = asked,
                None => bolt = bolt.max(needed),
            }
            let spec = bolt.spec();
            let rule = self.rule(&spec, &spec);
            for k in (0..n).filter(|&k| topo.parts[k].kind == PartKind::Link) {
                let fresh = self.link_demand(k, &rows);
                let demand = match &demands[k] {
                    Some(d) => d.max(&fresh),
                    None => fresh,
                };
                let section = rule.size(&demand);
                sections[k] = Some((demand.clone(), section));
                demands[k] = Some(demand);
            }
            let new_sizes: Vec<Option<(f64, f64)>> =
                sections.iter().map(|s| s.as_ref().map(|(_, s)| (s.width_mm, s.thickness_mm))).collect();
            let settled = new_sizes == sizes && bolt == before;
            sizes = new_sizes;
            if settled {
                return Ok(LinkSizing { bolt, sections, masses, rows });
            }
        }
        // Still growing after every round (it never has): the last round's sizes, their loads computed.
        let masses = self.masses(&sizes);
        let rows = equilibrium(self.problem, self.mechanism, self.trace, &masses)?;
        Ok(LinkSizing { bolt, sections, masses, rows })
    }

    /// Fabrication's layout and depth ordering with the workshop's sizes as print settings.
    fn layers(&self, bolt: &BoltSpec, width: f64, thickness: f64) -> Result<Fabrication, WorkshopError> {
        let (d, d0) = (bolt.diameter_mm, bolt.hole_mm);
        let clearance = 0.5 * (d0 - d);
        let half = 0.5 * width;
        let washer = 0.5 * bolt.washer_outer_mm;
        // The pin's column (boss) is the washer, so what passes over a bolt passes over its washers.
        let wall = (0.5 * (bolt.washer_outer_mm - d0)).min(half - washer).min(0.5 * (half - 0.5 * d0)).max(0.05);
        // A connector's square post stands for the bracket's fixing: a bolt's washer, where it fits.
        let post_needed = bolt.washer_outer_mm / std::f64::consts::SQRT_2;
        let post_room = 2.0 * ((half - wall) / std::f64::consts::SQRT_2 - clearance);
        let settings = PrintSettings {
            link_width: width,
            link_thickness: thickness,
            axial_gap: Stack::gap(bolt),
            radial_clearance: clearance,
            pin_radius: 0.5 * d,
            snap_cap: SnapCap { height: bolt.nut_mm, lip: 0.1, tip_inset: 0.25 * d },
            body_thickness: self.settings.body_thickness_mm,
            connector_post: post_needed.min(post_room).max(0.5),
            wall,
            circle_segments: 16,
            faces: Faces::Auto,
            bed: Bed { width: 1e6, depth: 1e6, margin: 0.0, spacing: 10.0 },
            density: 1.0,
            fill_fraction: 1.0,
        };
        crate::fab::fabricate(self.problem, Ratio::ONE, self.mechanism, self.travel, &settings, &[]).map_err(
            |e| match e {
                FabError::JointsTooClose { link, a, b, need_mm } => {
                    let at = |name: &str| self.mechanism.joint(name).unwrap_or(Point::ORIGIN);
                    WorkshopError::JointsTooClose {
                        apart_mm: at(&a).distance(at(&b)) * self.mm,
                        link,
                        a,
                        b,
                        need_mm,
                        width_mm: width,
                        bolt: bolt.size,
                    }
                }
                FabError::NoOrdering => WorkshopError::Layers {
                    width_mm: width,
                    bolt: bolt.size,
                    why: "no depth ordering exists on one face or on both".into(),
                },
                other => WorkshopError::Layers { width_mm: width, bolt: bolt.size, why: other.to_string() },
            },
        )
    }

    /// The layers and the brackets: fabrication's layout with the links' width, the brackets sized on
    /// it (fixing bolts no smaller than `fixing_min` asks), and what meets along the motion. When
    /// something does, the layout is made again as if every part were as wide as the widest bracket,
    /// and the one where less meets is kept. Also the gaps between layers the bolts' ends need.
    #[allow(clippy::type_complexity, reason = "one tuple of the stage's four results, used once")]
    fn lay_out(
        &self,
        links: &LinkSizing,
        fixing_min: &BTreeMap<String, BoltSize>,
    ) -> Result<(Fabrication, Vec<FixedPart>, [Vec<f64>; 2], Vec<String>), WorkshopError> {
        let bolt = links.bolt.spec();
        let width = links.widest();
        let fab = self.layers(&bolt, width, links.thickest())?;
        let fixed = self.size_fixed(&fab, &links.rows, &bolt, fixing_min);
        let (conflicts, gaps) = self.clearances(&fab, links, &fixed, &bolt);
        if conflicts.is_empty() {
            return Ok((fab, fixed, gaps, conflicts));
        }
        let widest = fixed.iter().map(|f| f.section.width_mm).fold(width, f64::max);
        let again = self.layers(&bolt, widest, links.thickest()).ok().map(|fab| {
            let fixed = self.size_fixed(&fab, &links.rows, &bolt, fixing_min);
            let (conflicts, gaps) = self.clearances(&fab, links, &fixed, &bolt);
            (fab, fixed, gaps, conflicts)
        });
        Ok(match again {
            Some(better) if better.3.len() < conflicts.len() => better,
            _ => (fab, fixed, gaps, conflicts),
        })
    }

    /// The smallest bolt whose thread core holds a bending moment of `moment_nm` with the safety
    /// factor (`None` when none does).
    fn bolt_for_bending(&self, moment_nm: f64) -> Option<BoltSize> {
        let s = self.settings.safety_factor;
        BoltSize::ALL.into_iter().find(|b| s * moment_nm <= b.spec().bending_strength_nm())
    }

    /// The topology part a layout carrier is, when it is the ground or a body.
    fn carrier_part(&self, carrier: Carrier) -> Option<usize> {
        let parts = &self.mechanism.topology.parts;
        match carrier {
            Carrier::Ground => Some(self.ground),
            Carrier::Body(b) => parts.iter().position(|p| p.kind == PartKind::Body(b)),
            Carrier::Link(_) => None,
        }
    }

    /// Sizes the brackets, the guide and the frame: each fixed to its carrier at its post by two bolts
    /// across it, an edge distance from its sides, carrying its joints' forces there as a force and a
    /// moment.
    fn size_fixed(
        &self,
        fab: &Fabrication,
        rows: &[RowForces],
        bolt: &BoltSpec,
        fixing_min: &BTreeMap<String, BoltSize>,
    ) -> Vec<FixedPart> {
        let layout = &fab.layout;
        let mut poses: Vec<Rigid> = Vec::new();
        let mut out = Vec::new();
        for (i, m) in layout.members.iter().enumerate() {
            if !matches!(m.kind, MemberKind::Connector | MemberKind::Guide | MemberKind::Frame) {
                continue;
            }
            let Some(part) = self.carrier_part(layout.carriers[m.carrier]) else { continue };
            // The joints whose forces it carries, and the force on it at each.
            let loaded: Vec<usize> = match m.kind {
                MemberKind::Guide => m.slot.map(|s| vec![s.joint]).unwrap_or_default(),
                _ => m.joints.clone(),
            };
            let (mut moment, mut resultant, mut hole) = (0.0f64, 0.0f64, 0.0f64);
            for (r, forces) in rows.iter().enumerate() {
                let row = self.trace.row(r);
                layout.carrier_poses(row, &mut poses);
                let post = m.post.map(|p| poses[m.carrier].apply(p));
                let (mut sum, mut turn) = (Vec2::ZERO, 0.0);
                for &j in &loaded {
                    let f = forces.pin_force(part, j);
                    sum += f;
                    hole = hole.max(f.norm());
                    if let Some(post) = post {
                        turn += ((row[j] - post) * self.mm).cross(f);
                    }
                }
                resultant = resultant.max(sum.norm());
                moment = moment.max(turn.abs() / 1000.0);
            }
            let bending = m.post.map(|_| Bending { moment_nm: moment, axial_n: resultant, fixing: true });
            let demand = Demand { edges: Vec::new(), hole_n: hole, bending };
            // The smallest fixing bolt (no smaller than the joints') with which the bracket holds on
            // some stock; when none does, the one that makes it narrowest.
            let least = fixing_min.get(&m.name).map_or(bolt.size, |&b| b.max(bolt.size));
            let sized: Vec<(BoltSpec, Section)> = BoltSize::ALL
                .into_iter()
                .filter(|&b| b >= least || demand.bending.is_none())
                .take(if demand.bending.is_none() { 1 } else { BoltSize::ALL.len() })
                .map(|b| {
                    let fixing = b.spec();
                    let section = self.rule(bolt, &fixing).size(&demand);
                    (fixing, section)
                })
                .collect();
            let (fixing_bolt, section) = sized
                .iter()
                .find(|(_, s)| s.checks.iter().all(|c| c.ok))
                .or_else(|| sized.iter().min_by(|a, b| a.1.width_mm.total_cmp(&b.1.width_mm)))
                .cloned()
                .expect("at least one bolt size is tried");
            let rule = self.rule(bolt, &fixing_bolt);
            let fixing_shear_n = demand.bending.as_ref().map_or(0.0, |b| rule.fixing_shear(b, section.width_mm));
            let spacing = rule.fixing_spacing(section.width_mm);
            let fixings = match m.post {
                Some(post) => {
                    let toward = match m.kind {
                        MemberKind::Guide => m.slot.map(|s| s.ends.0.lerp(s.ends.1, 0.5)),
                        _ => m.joints.first().and_then(|&j| m.joint_at(j)),
                    };
                    let along = toward
                        .map(|t| t - post)
                        .filter(|v| v.norm() > 0.0)
                        .map_or(Vec2::new(1.0, 0.0), Vec2::normalized);
                    let across = along.perp() * (0.5 * spacing / self.mm);
                    vec![post + across, post - across]
                }
                None => Vec::new(),
            };
            out.push(FixedPart {
                member: i,
                name: m.name.clone(),
                demand,
                section,
                fixings,
                fixing_bolt,
                fixing_shear_n,
            });
        }
        out
    }

    /// Where the parts as cut meet along the motion, and the gaps between layers that bolts' ends
    /// need. Two parts on one layer of a face must not overlap, and no part may cross a bolt between
    /// the layers it joins (a joint's, from its innermost part, or from the body it stands in, to its
    /// outermost; a bracket's fixing bolts, from the body to the bracket): each such meeting is a
    /// sentence with the first crank angle where it happens. A part passing over a bolt beyond its
    /// outermost part (or under its innermost, with the head) needs the gap there to hold the bolt's
    /// end ([`Stack::gap`]); next to the bodies, the heads of bolts through them from the other face.
    fn clearances(
        &self,
        fab: &Fabrication,
        links: &LinkSizing,
        fixed: &[FixedPart],
        bolt: &BoltSpec,
    ) -> (Vec<String>, [Vec<f64>; 2]) {
        let layout = &fab.layout;
        let radius = self.cut_radii(layout, links, fixed);
        let clearance = 0.5 * (bolt.hole_mm - bolt.diameter_mm) / self.mm;
        let columns = self.columns(fab, fixed, bolt);
        let mut gaps = head_gaps(fab, fixed, &columns);
        let mut found: BTreeMap<String, f64> = BTreeMap::new();
        let mut poses: Vec<Rigid> = Vec::new();
        let mut cores: Vec<Vec<Point>> = layout.members.iter().map(|m| m.core.clone()).collect();
        for r in 0..self.trace.len() {
            let row = self.trace.row(r);
            let deg = self.trace.thetas[r].to_degrees();
            layout.carrier_poses(row, &mut poses);
            for (i, m) in layout.members.iter().enumerate() {
                for (k, &c) in m.core.iter().enumerate() {
                    cores[i][k] = poses[m.carrier].apply(c);
                }
            }
            // A meeting is told once, at the first row where it happens.
            let mut note = |text: String| {
                found.entry(text).or_insert(deg);
            };
            let parts = PartsAt { fab, cores: &cores, radius: &radius, clearance };
            parts.overlaps(r == 0, &mut note);
            parts.crossings(&columns, row, &poses, &mut gaps, &mut note);
        }
        let conflicts = found.into_iter().map(|(what, deg)| format!("{what} (first at crank {deg:.1}°)")).collect();
        (conflicts, gaps)
    }

    /// Every layout member's half width as cut, scene units: a link's from its section, a bracket's
    /// (or the guide's, or the frame's) from its own sizing, zero for a member with neither. The
    /// clearance checks test the members' cores this far apart.
    fn cut_radii(&self, layout: &Layout, links: &LinkSizing, fixed: &[FixedPart]) -> Vec<f64> {
        (0..layout.members.len())
            .map(|i| {
                let width = match layout.carriers[layout.members[i].carrier] {
                    Carrier::Link(k) => links.sections[k].as_ref().map(|(_, s)| s.width_mm),
                    _ => fixed.iter().find(|f| f.member == i).map(|f| f.section.width_mm),
                };
                0.5 * width.unwrap_or(0.0) / self.mm
            })
            .collect()
    }

    /// Every column a part must not cross, or must leave room over for its end: each joint's bolt
    /// (from the body it stands in, or from its innermost part, to its outermost), each bracket's
    /// stand-off block (from the body up to the bracket) and the bracket's fixing bolts (their nuts on
    /// top of it).
    fn columns(&self, fab: &Fabrication, fixed: &[FixedPart], bolt: &BoltSpec) -> Vec<Column> {
        let layout = &fab.layout;
        let (face, layer) = (&fab.ordering.face, &fab.ordering.layer);
        let mut columns: Vec<Column> = Vec::new();
        for (j, members) in layout.joint_members.iter().enumerate() {
            let Some(&first) = members.first() else { continue };
            let layers = members.iter().map(|&i| layer[i]);
            let from = if layout.body_pins[j].is_some() { 0 } else { layers.clone().min().unwrap_or(0) };
            columns.push(Column {
                what: format!("the bolt at {}", self.joint_name(j)),
                carrier: 0,
                at: Point::ORIGIN,
                joint: Some(j),
                face: face[first],
                from,
                to: layers.max().unwrap_or(0),
                own: members.clone(),
                reach: 0.5 * bolt.washer_outer_mm / self.mm,
                end_mm: Stack::gap(bolt),
            });
        }
        for f in fixed {
            let m = &layout.members[f.member];
            // The stand-off block under its post end, from the body up to the bracket.
            if let Some(post) = m.post {
                columns.push(Column {
                    what: format!("the stand-off block of {}", f.name),
                    carrier: m.carrier,
                    at: post,
                    joint: None,
                    face: face[f.member],
                    from: 0,
                    to: layer[f.member],
                    own: vec![f.member],
                    reach: 0.5 * f.section.width_mm / self.mm,
                    end_mm: 0.0,
                });
            }
            // Its bolts' nuts, on top of it.
            for &p in &f.fixings {
                columns.push(Column {
                    what: format!("a fixing bolt of {}", f.name),
                    carrier: m.carrier,
                    at: p,
                    joint: None,
                    face: face[f.member],
                    from: layer[f.member],
                    to: layer[f.member],
                    own: vec![f.member],
                    reach: 0.5 * f.fixing_bolt.washer_outer_mm / self.mm,
                    end_mm: Stack::gap(&f.fixing_bolt),
                });
            }
        }
        columns
    }

    /// The name of what a layout carrier is.
    fn carrier_name(&self, carrier: Carrier) -> String {
        match carrier {
            Carrier::Ground => "ground".into(),
            Carrier::Body(b) => self.mechanism.topology.body_part(b).name.clone(),
            Carrier::Link(k) => self.mechanism.topology.parts[k].name.clone(),
        }
    }

    /// The thickness (mm) and material of what a bolt through `carrier` passes through.
    fn carrier_stock(&self, carrier: Carrier) -> (f64, Material) {
        match carrier {
            Carrier::Body(b) => (self.bodies[b].2, self.bodies[b].3),
            _ => (self.settings.body_thickness_mm, self.values.material),
        }
    }

    /// Everything together: every part's plan, the layer stack, the bolts (each joint's, then the
    /// brackets' fixings), the notes and the tables a workshop works from. `notes` are the layout's
    /// (what meets along the motion); the bolts', the parts' checks' and the build's own follow.
    fn assemble(
        &self,
        links: &LinkSizing,
        fab: &Fabrication,
        fixed: &[FixedPart],
        gaps: &[Vec<f64>; 2],
        mut notes: Vec<String>,
    ) -> Workshop {
        let layout = &fab.layout;
        let bolt = links.bolt.spec();
        let mut plans: Vec<LinkPlan> =
            (0..layout.members.len()).filter_map(|i| self.part_plan(links, fab, fixed, i, &bolt)).collect();
        let layered: Vec<Layered> = plans
            .iter()
            .map(|p| Layered { name: p.name.clone(), face: p.face, layer: p.layer, thickness_mm: p.thickness_mm })
            .collect();
        let stack = Stack::new(&layered, &bolt, gaps);
        let by_member: BTreeMap<usize, usize> = layout
            .members
            .iter()
            .enumerate()
            .filter_map(|(i, m)| plans.iter().position(|p| p.name == m.name).map(|k| (i, k)))
            .collect();
        let laid = Laid { fab, links, bolt, layered, stack, by_member };
        let mut bolts = self.joint_bolts(&laid, &mut notes);
        let fixings = self.fixing_bolts(&laid, fixed, &mut plans, &mut notes);
        bolts.extend(fixings);
        notes.extend(failed_check_notes(&bolts, &plans));
        notes.extend(self.assumption_notes(layout, fixed, &bolts));
        let (peak_torque_nm, peak_torque_crank_deg) = peak_torque(&links.rows);
        notes.extend(self.holding_note(peak_torque_nm, peak_torque_crank_deg));
        let masses = self.part_masses(links);
        let cut_list = self.cut_list(&plans);
        let bill_of_materials = self.bill_of_materials(&plans, &bolts);
        let steps = self.steps(&plans, &bolts, &laid.stack.layers(&laid.layered), &bolt);
        Workshop {
            linkwright: WORKSHOP_FORMAT,
            scene: self.problem.name.clone(),
            material: self.values.material,
            values: self.values.clone(),
            settings: self.settings.clone(),
            bolt,
            masses,
            peak_torque_nm,
            peak_torque_crank_deg,
            files: file_names(&plans),
            layers: laid.stack.layers(&laid.layered),
            links: plans,
            bolts,
            cut_list,
            bill_of_materials,
            steps,
            notes,
        }
    }

    /// Layout member `i`'s plan as cut: its outline and holes, the pivot-to-pivot lengths between
    /// its joints' holes, its stock, layer and loads. `None` for a member the workshop does not cut
    /// (a link without a section, a bracket without a sizing, a member of any other kind).
    fn part_plan(
        &self,
        links: &LinkSizing,
        fab: &Fabrication,
        fixed: &[FixedPart],
        i: usize,
        bolt: &BoltSpec,
    ) -> Option<LinkPlan> {
        let m = &fab.layout.members[i];
        let sized = self.part_sizing(links, &fab.layout, fixed, i)?;
        let (outline, centres) = self.part_outline(m, &sized, bolt);
        let (demand, section) = (sized.demand, sized.section);
        let (_, size_mm) = outline.bounds();
        let bending = demand.bending.as_ref();
        Some(LinkPlan {
            name: m.name.clone(),
            kind: sized.kind,
            on: sized.on,
            joints: m.joints.iter().map(|&j| self.joint_name(j)).collect(),
            pivot_lengths: pivot_lengths(&centres),
            width_mm: section.width_mm,
            thickness_mm: section.thickness_mm,
            hole_mm: bolt.hole_mm,
            fixing_bolt: sized.fixing_bolt.map(|b| b.size),
            face: fab.ordering.face[i],
            layer: fab.ordering.layer[i],
            mass_kg: outline.area_mm2() * section.thickness_mm * self.values.density_kg_m3 * 1e-9,
            size_mm,
            loads: LinkLoads {
                tension_n: demand.edges.iter().map(|e| e.tension_n).fold(0.0, f64::max),
                compression_n: demand.edges.iter().map(|e| e.compression_n).fold(0.0, f64::max),
                hole_n: demand.hole_n,
                moment_nm: bending.map_or(0.0, |b| b.moment_nm),
                axial_n: bending.map_or(0.0, |b| b.axial_n),
                fixing_shear_n: sized.fixing_shear_n,
            },
            checks: section.checks.clone(),
            thinner_fails: section.thinner_fails.clone(),
            outline,
            profile_file: profile_file(section.thickness_mm, "dxf"),
        })
    }

    /// What layout member `i` is sized with: a link its section from the link sizing, a bracket
    /// (or the guide, or the frame) its own sizing with its fixing bolts and what it is fixed to.
    /// `None` for a member with neither.
    fn part_sizing<'s>(
        &self,
        links: &'s LinkSizing,
        layout: &Layout,
        fixed: &'s [FixedPart],
        i: usize,
    ) -> Option<PartSizing<'s>> {
        let m = &layout.members[i];
        match (m.kind, layout.carriers[m.carrier]) {
            (MemberKind::Link, Carrier::Link(k)) => {
                let (demand, section) = links.sections[k].as_ref()?;
                Some(PartSizing {
                    kind: LinkKind::Link,
                    demand,
                    section,
                    fixings: &[],
                    fixing_bolt: None,
                    fixing_shear_n: 0.0,
                    on: None,
                })
            }
            (MemberKind::Connector | MemberKind::Guide | MemberKind::Frame, carrier) => {
                let f = fixed.iter().find(|f| f.member == i)?;
                let kind = match m.kind {
                    MemberKind::Connector => LinkKind::Bracket,
                    MemberKind::Guide => LinkKind::Guide,
                    _ => LinkKind::Frame,
                };
                Some(PartSizing {
                    kind,
                    demand: &f.demand,
                    section: &f.section,
                    fixings: &f.fixings[..],
                    fixing_bolt: (!f.fixings.is_empty()).then_some(f.fixing_bolt),
                    fixing_shear_n: f.fixing_shear_n,
                    on: Some(self.carrier_name(carrier)),
                })
            }
            _ => None,
        }
    }

    /// A part's outline as cut, millimetres: its core widened to its section's half width, with a
    /// clearance hole at each joint it turns on, its slot, and its fixing bolts' holes. Also the
    /// joints' hole centres by joint name, which its pivot lengths are measured between.
    fn part_outline(&self, m: &Member, sized: &PartSizing<'_>, bolt: &BoltSpec) -> (Outline, Vec<(String, Point)>) {
        let d0 = bolt.hole_mm;
        let mut holes: Vec<Hole> = Vec::new();
        let mut centres: Vec<(String, Point)> = Vec::new();
        for &j in &m.joints {
            if let Some(p) = m.joint_at(j) {
                let centre = scaled(p, self.mm);
                holes.push(Hole::Round { centre, diameter_mm: d0, purpose: self.joint_name(j) });
                centres.push((self.joint_name(j), centre));
            }
        }
        if let Some(slot) = m.slot {
            holes.push(Hole::Slot { ends: [scaled(slot.ends.0, self.mm), scaled(slot.ends.1, self.mm)], width_mm: d0 });
        }
        for (&p, spec) in sized.fixings.iter().zip(std::iter::repeat(sized.fixing_bolt.unwrap_or(*bolt))) {
            holes.push(Hole::Round { centre: scaled(p, self.mm), diameter_mm: spec.hole_mm, purpose: "fixing".into() });
        }
        let core: Vec<Point> = m.core.iter().map(|&p| scaled(p, self.mm)).collect();
        (Outline::new(&core, 0.5 * sized.section.width_mm, holes), centres)
    }

    /// The topology part whose force a layout member passes to its bolts: a link its own, a bracket
    /// (or the guide, or the frame) its carrier's.
    fn member_part(&self, layout: &Layout, i: usize) -> Option<usize> {
        match layout.carriers[layout.members[i].carrier] {
            Carrier::Link(k) => Some(k),
            carrier => self.carrier_part(carrier),
        }
    }

    /// The joints' bolts, innermost parts first (the order they are put together in), each through
    /// its parts and the body it stands in. A bolt bearing harder on that body than the body holds
    /// adds a note to `notes`.
    fn joint_bolts(&self, laid: &Laid<'_>, notes: &mut Vec<String>) -> Vec<JointPlan> {
        let layout = &laid.fab.layout;
        let mut bolts: Vec<JointPlan> = Vec::new();
        let mut joints: Vec<usize> =
            (0..self.mechanism.topology.joint_count()).filter(|&j| !layout.joint_members[j].is_empty()).collect();
        joints.sort_by_key(|&j| layout.joint_members[j].iter().map(|&i| laid.fab.ordering.layer[i]).min().unwrap_or(0));
        for j in joints {
            let Some(plan) = self.joint_bolt(laid, j) else { continue };
            bolts.push(plan);
            notes.extend(self.bearing_note(laid, j));
        }
        bolts
    }

    /// Joint `j`'s bolt: its stack from the body it stands in (if any) through its planned parts,
    /// innermost first, its length, and its shear and bending from the forces of what presses on
    /// it along the motion. `None` when no planned part turns on the joint.
    fn joint_bolt(&self, laid: &Laid<'_>, j: usize) -> Option<JointPlan> {
        let layout = &laid.fab.layout;
        let (bolt, links) = (&laid.bolt, laid.links);
        let mut members: Vec<usize> =
            layout.joint_members[j].iter().copied().filter(|i| laid.by_member.contains_key(i)).collect();
        members.sort_by_key(|&i| laid.fab.ordering.layer[i]);
        let parts: Vec<&Layered> = members.iter().map(|i| &laid.layered[laid.by_member[i]]).collect();
        let face = parts.first().map(|p| p.face)?;
        let body = layout.body_pins[j].map(|pin| layout.carriers[pin.carrier]);
        let named = body.map(|c| (self.carrier_name(c), self.carrier_stock(c).0));
        let stack_items = laid.stack.bolt(bolt, named.as_ref().map(|(n, t)| (n.as_str(), *t)), &parts);
        let (needed_mm, length_mm) = Stack::bolt_length(&stack_items, bolt);
        // What presses on the bolt, in the stack's order.
        let pressing: Vec<Option<usize>> = body
            .map(|c| self.carrier_part(c))
            .into_iter()
            .chain(members.iter().map(|&i| self.member_part(layout, i)))
            .collect();
        let (shear_n, moment_nm) = bolt_loads(
            &stack_items,
            |r, k| pressing[k].map_or(Vec2::ZERO, |part| links.rows[r].pin_force(part, j)),
            links.rows.len(),
        );
        Some(JointPlan {
            at: self.joint_name(j),
            count: 1,
            bolt: bolt.size,
            face,
            stack: stack_items,
            needed_mm,
            length_mm,
            shear_n,
            moment_nm,
            checks: bolt_checks(bolt, self.settings.safety_factor, shear_n, moment_nm),
        })
    }

    /// The note when joint `j`'s bolt bears on the body it stands in harder than that body's stock
    /// holds with the safety factor: the body needs reinforcing there. `None` when it holds, or the
    /// bolt stands in no moving body.
    fn bearing_note(&self, laid: &Laid<'_>, j: usize) -> Option<String> {
        let layout = &laid.fab.layout;
        let bolt = &laid.bolt;
        let carrier = layout.body_pins[j].map(|pin| layout.carriers[pin.carrier])?;
        if !matches!(carrier, Carrier::Body(_)) {
            return None;
        }
        let part = self.carrier_part(carrier)?;
        let force = laid.links.rows.iter().map(|r| r.pin_force(part, j).norm()).fold(0.0, f64::max);
        let (t, material) = self.carrier_stock(carrier);
        let holds = MaterialValues::of(material).bearing_mpa(bolt) * bolt.diameter_mm * t;
        (self.settings.safety_factor * force > holds).then(|| {
            format!(
                "The bolt at {} bears {:.0} N on {} ({} mm of {}); with the safety factor that is more than \
                 the {:.0} N it holds: reinforce around the hole (a plate on each side).",
                self.joint_name(j),
                force,
                self.carrier_name(carrier),
                number(t),
                material.id(),
                holds
            )
        })
    }

    /// The brackets' (and the guide's, and the frame's) fixing bolts: two through each and the body
    /// it is fixed to, checked in shear and tension. A stand-off block under a bracket's post end
    /// adds its bending check to the bracket's plan in `plans`; fixing bolts outside the body as
    /// drawn add a note to `notes`.
    fn fixing_bolts(
        &self,
        laid: &Laid<'_>,
        fixed: &[FixedPart],
        plans: &mut [LinkPlan],
        notes: &mut Vec<String>,
    ) -> Vec<JointPlan> {
        let layout = &laid.fab.layout;
        let factor = self.settings.safety_factor;
        let mut bolts: Vec<JointPlan> = Vec::new();
        for f in fixed.iter().filter(|f| !f.fixings.is_empty()) {
            let m = &layout.members[f.member];
            let Some(&k) = laid.by_member.get(&f.member) else { continue };
            let carrier = layout.carriers[m.carrier];
            let (t, _) = self.carrier_stock(carrier);
            let name = self.carrier_name(carrier);
            let part = &laid.layered[k];
            let (stack_items, stand_off) = fixing_stack(&laid.stack, f, (name.as_str(), t), part);
            let (needed_mm, length_mm) = Stack::bolt_length(&stack_items, &f.fixing_bolt);
            let spec = &f.fixing_bolt;
            let resultant = f.demand.bending.as_ref().map_or(0.0, |b| b.axial_n);
            // The force at the bracket's middle, a block's height and half the body off the body's
            // middle, tips the bracket about the block's edge: one bolt, an edge distance from that
            // edge, holds it in tension.
            let lever = stand_off + 0.5 * (t + part.thickness_mm);
            let tension = resultant * lever / self.values.edge_mm(spec);
            let share = f.fixing_shear_n;
            if stand_off > 0.0 {
                let block = self.stand_off_check(plans[k].width_mm, resultant, stand_off, part.thickness_mm);
                plans[k].checks.push(block);
            }
            bolts.push(JointPlan {
                at: format!("{}{FIXING}", f.name),
                count: 2,
                bolt: spec.size,
                face: part.face,
                stack: stack_items,
                needed_mm,
                length_mm,
                shear_n: share,
                moment_nm: 0.0,
                checks: fixing_checks(spec, factor, share, tension),
            });
            notes.extend(self.fixings_outside_note(f, carrier, &name));
        }
        bolts
    }

    /// The stand-off block's check under a bracket `width` mm wide and `thickness_mm` thick: a disc
    /// as wide as the bracket, bent by the bracket's force (`resultant`, N) over the block's height
    /// (`stand_off`, mm) and half the bracket.
    fn stand_off_check(&self, width: f64, resultant: f64, stand_off: f64, thickness_mm: f64) -> Check {
        let modulus = std::f64::consts::PI * width.powi(3) / 32.0;
        Check::new(
            "stand-off bending",
            self.settings.safety_factor * resultant * (stand_off + 0.5 * thickness_mm) / modulus,
            self.values.tension_mpa,
            "MPa",
        )
    }

    /// The note when a fixing bolt of `f` lies outside what it is fixed to (`carrier`, called
    /// `name`) as drawn, where it would hold nothing. `None` when every one lies inside.
    fn fixings_outside_note(&self, f: &FixedPart, carrier: Carrier, name: &str) -> Option<String> {
        let inside = |p: Point| match carrier {
            Carrier::Body(b) => self.problem.bodies[b].outline.contains(p),
            _ => self.problem.fixed.iter().any(|poly| poly.contains(p)),
        };
        (!f.fixings.iter().all(|&p| inside(p))).then(|| {
            format!(
                "A fixing bolt of {} lies outside {} as drawn: fix the bracket where the body is, or extend the body \
                 under it.",
                f.name, name
            )
        })
    }

    /// What the plan takes for granted and the workshop must see to: the fixed bodies taken as
    /// panels of the settings' thickness (when anything is bolted to them), bolts too long to be
    /// standard, and counterbalance springs left out of the loads.
    fn assumption_notes(&self, layout: &Layout, fixed: &[FixedPart], bolts: &[JointPlan]) -> Vec<String> {
        let mut notes = Vec::new();
        if layout.body_pins.iter().flatten().any(|pin| layout.carriers[pin.carrier] == Carrier::Ground)
            || fixed.iter().any(|f| layout.carriers[layout.members[f.member].carrier] == Carrier::Ground)
        {
            notes.push(format!(
                "Bolts into the fixed bodies take them for {} mm panels; into a wall or floor use anchors rated for the \
                 force listed at each bolt, with the safety factor.",
                number(self.settings.body_thickness_mm)
            ));
        }
        for b in bolts.iter().filter(|b| b.length_mm > 300.0) {
            notes.push(format!(
                "The bolt at {} is longer than standard bolts ({:.0} mm): use threaded rod.",
                b.at, b.length_mm
            ));
        }
        if !self.settings.springs.is_empty() {
            notes.push(
                "The counterbalance springs listed are not in the loads: the links are sized for the weights held at the \
                 crank, which the springs relieve there but may load elsewhere; hook them where the spring search placed \
                 them."
                    .into(),
            );
        }
        notes
    }

    /// The note on the torque that holds the linkage at its crank (`peak_torque_nm` at its peak, at
    /// `peak_torque_crank_deg`), which something must supply. `None` without a crank.
    fn holding_note(&self, peak_torque_nm: f64, peak_torque_crank_deg: f64) -> Option<String> {
        let parts = &self.mechanism.topology.parts;
        self.crank.map(|crank| {
            format!(
                "The linkage is held at the {} with up to {:.1} N·m (at crank {:.1}°): the torque a lock, a motor or the \
                 counterbalance springs must supply; the {} is sized to carry it as bending at its pivot.",
                parts[crank].name, peak_torque_nm, peak_torque_crank_deg, parts[crank].name
            )
        })
    }

    /// Every moving part's mass as sized, with where it comes from: a body's as the scene gives it
    /// (or its stock, or the default), a link's from its section.
    fn part_masses(&self, links: &LinkSizing) -> Vec<PartMass> {
        self.mechanism
            .topology
            .parts
            .iter()
            .enumerate()
            .filter_map(|(k, p)| match p.kind {
                PartKind::Fixed => None,
                PartKind::Body(b) => {
                    Some(PartMass { part: p.name.clone(), kg: links.masses[k], source: self.bodies[b].1 })
                }
                PartKind::Link => Some(PartMass { part: p.name.clone(), kg: links.masses[k], source: "sized" }),
            })
            .collect()
    }

    /// Identical parts (kind, stock, width, pivot lengths and holes alike to 0.1 mm) on one line.
    fn cut_list(&self, plans: &[LinkPlan]) -> Vec<CutItem> {
        let key = |p: &LinkPlan| {
            let mut lengths: Vec<i64> = p.pivot_lengths.iter().map(|l| (l.length_mm * 10.0).round() as i64).collect();
            lengths.sort_unstable();
            let tenth = |x: f64| (x * 10.0).round() as i64;
            (p.kind, tenth(p.thickness_mm), tenth(p.width_mm), tenth(p.size_mm[0]), lengths, p.outline.holes.len())
        };
        let mut out: Vec<(CutItem, _)> = Vec::new();
        for p in plans {
            let k = key(p);
            if let Some((item, _)) = out.iter_mut().find(|(_, other)| *other == k) {
                item.parts.push(p.name.clone());
                item.count += 1;
                continue;
            }
            out.push((
                CutItem {
                    parts: vec![p.name.clone()],
                    kind: p.kind,
                    material: self.values.material,
                    thickness_mm: p.thickness_mm,
                    length_mm: p.size_mm[0],
                    width_mm: p.size_mm[1],
                    holes: p.outline.holes.len(),
                    hole_mm: p.hole_mm,
                    count: 1,
                    file: p.profile_file.clone(),
                },
                k,
            ));
        }
        out.into_iter().map(|(item, _)| item).collect()
    }

    fn bill_of_materials(&self, plans: &[LinkPlan], bolts: &[JointPlan]) -> Vec<BomItem> {
        let mut out = Vec::new();
        // By size, then length (tenths of a millimetre for spacers).
        let mut lengths: BTreeMap<(BoltSize, i64), u32> = BTreeMap::new();
        let mut per_size: BTreeMap<BoltSize, (u32, u32)> = BTreeMap::new();
        let mut spacers: BTreeMap<(BoltSize, i64), u32> = BTreeMap::new();
        let mut blocks: Vec<(String, f64)> = Vec::new();
        for b in bolts {
            *lengths.entry((b.bolt, b.length_mm.round() as i64)).or_default() += b.count;
            let (nuts, washers) = per_size.entry(b.bolt).or_default();
            *nuts += b.count;
            for item in &b.stack {
                match item.item {
                    "washer" => *washers += b.count,
                    "spacer" => {
                        *spacers.entry((b.bolt, (item.thickness_mm * 10.0).round() as i64)).or_default() += b.count
                    }
                    "block" => blocks.push((b.at.trim_end_matches(FIXING).to_string(), item.thickness_mm)),
                    _ => {}
                }
            }
        }
        for ((size, length), count) in &lengths {
            out.push(BomItem {
                item: "hex bolt, property class 8.8, zinc plated".into(),
                standard: "ISO 4014 (partly threaded)".into(),
                size: format!("{size} × {length}"),
                count: *count,
            });
        }
        for (size, (nuts, washers)) in &per_size {
            let spec = size.spec();
            out.push(BomItem {
                item: "hex nut with nylon insert (holds at any tightness, so a pivot turns freely)".into(),
                standard: "ISO 10511".into(),
                size: size.to_string(),
                count: *nuts,
            });
            out.push(BomItem {
                item: "plain washer".into(),
                standard: "ISO 7089".into(),
                size: format!(
                    "{} ({} × {} × {} mm)",
                    &size.name()[1..],
                    spec.washer_inner_mm,
                    spec.washer_outer_mm,
                    spec.washer_mm
                ),
                count: *washers,
            });
        }
        for ((size, tenths), count) in spacers {
            let spec = size.spec();
            out.push(BomItem {
                item: "spacer tube (steel or nylon), ends square".into(),
                standard: String::new(),
                size: format!(
                    "{} mm bore, {} mm outside, {:.1} mm long",
                    spec.washer_inner_mm,
                    spec.washer_outer_mm,
                    tenths as f64 / 10.0
                ),
                count,
            });
        }
        for (bracket, height) in blocks {
            let width = plans.iter().find(|p| p.name == bracket).map_or(0.0, |p| p.width_mm);
            out.push(BomItem {
                item: format!(
                    "stand-off block under {bracket}'s post end ({}, glued up from its stock, or solid)",
                    material_words(self.values.material)
                ),
                standard: String::new(),
                size: format!("{} mm across, {:.1} mm high", number(width), height),
                count: 1,
            });
        }
        for s in &self.settings.springs {
            out.push(BomItem {
                item: "extension spring (counterbalance)".into(),
                standard: String::new(),
                size: format!("rate {} N/mm, free length {} mm", s.rate_n_per_mm, number(s.free_length_mm)),
                count: s.count,
            });
        }
        for t in thicknesses(plans) {
            let parts: Vec<&LinkPlan> = plans.iter().filter(|p| p.thickness_mm == t).collect();
            let area: f64 = parts.iter().map(|p| p.size_mm[0] * p.size_mm[1]).sum::<f64>() / 1e6;
            out.push(BomItem {
                item: format!("{} stock, {} mm", material_words(self.values.material), number(t)),
                standard: String::new(),
                size: format!("{area:.2} m² of parts' outline boxes"),
                count: parts.len() as u32,
            });
        }
        out
    }

    fn steps(
        &self,
        plans: &[LinkPlan],
        bolts: &[JointPlan],
        layers: &[super::report::LayerPlan],
        spec: &BoltSpec,
    ) -> Vec<String> {
        let mut out = Vec::new();
        for t in thicknesses(plans) {
            let names: Vec<&str> = plans.iter().filter(|p| p.thickness_mm == t).map(|p| p.name.as_str()).collect();
            out.push(format!(
                "Cut {} from {} mm {} ({} or {}, full size in millimetres; the cut list gives each one's size).",
                names.join(", "),
                number(t),
                material_words(self.values.material),
                profile_file(t, "dxf"),
                profile_file(t, "svg")
            ));
        }
        let mut sizes: Vec<BoltSize> = bolts.iter().map(|b| b.bolt).collect();
        sizes.push(spec.size);
        sizes.sort();
        sizes.dedup();
        let holes: Vec<String> = sizes.iter().map(|b| format!("{} mm for {b}", b.spec().hole_mm)).collect();
        out.push(format!(
            "Drill or ream every bolt hole to its ISO 273 medium clearance ({}) if the cutter did not, and break the \
             edges.",
            holes.join(", ")
        ));
        let words = |b: &JointPlan| {
            b.stack
                .iter()
                .map(|s| match (&s.name, s.item) {
                    (Some(name), _) => format!("{name} ({} mm)", number_tenth(s.thickness_mm)),
                    (None, "spacer") => format!("a {} mm spacer", number_tenth(s.thickness_mm)),
                    (None, item) => item.to_string(),
                })
                .collect::<Vec<_>>()
                .join(", ")
        };
        for b in bolts.iter().filter(|b| b.count == 2) {
            out.push(format!(
                "{}: two {} × {:.0} bolts, each through {}, then a nut; tighten fully (the bracket must not turn).",
                b.at,
                b.bolt,
                b.length_mm,
                words(b)
            ));
        }
        out.push("Lay the bodies and the fixed parts in their first pose as drawn.".into());
        for l in layers.iter().filter(|l| !l.parts.is_empty()) {
            out.push(format!(
                "{} face, layer {} ({:.1} mm from the face): {}.",
                if l.face == Face::Front { "Front" } else { "Back" },
                l.layer,
                l.from_face_mm,
                l.parts.join(", ")
            ));
        }
        for b in bolts.iter().filter(|b| b.count == 1) {
            out.push(format!(
                "Joint {}: a {} × {:.0} bolt from the bodies' side through {}, then the nut: tighten until the parts \
                 touch, then back it off until they turn freely (the nylon insert holds it there).",
                b.at,
                b.bolt,
                b.length_mm,
                words(b)
            ));
        }
        for s in &self.settings.springs {
            out.push(format!(
                "Hook {} counterbalance spring{} ({} N/mm, {} mm free) where the spring search placed {}.",
                s.count,
                if s.count == 1 { "" } else { "s" },
                s.rate_n_per_mm,
                number(s.free_length_mm),
                if s.count == 1 { "it" } else { "them" }
            ));
        }
        out.push(
            "Move the object slowly through its whole travel before loading it: nothing may rub; then load it and \
             check every nut again."
                .into(),
        );
        out
    }
}

/// Something standing across the layers that parts must not cross: a bolt, or a bracket's stand-off
/// block. Where it stands, on which face, from which layer to which (0 is the body), and the room
/// its end needs.
struct Column {
    /// What it is, in the notes' words.
    what: String,
    /// The layout carrier it stands on, when it is not a joint's bolt.
    carrier: usize,
    /// Where it stands in its carrier's frame, when it is not a joint's bolt.
    at: Point,
    /// The joint whose bolt it is; such a column stands where the joint is.
    joint: Option<usize>,
    face: Face,
    from: u32,
    to: u32,
    /// The members it holds, which do not cross it.
    own: Vec<usize>,
    /// How far it reaches from its centre (a washer's radius, or the block's half width), scene units.
    reach: f64,
    /// The room its end needs beyond the parts it holds, mm.
    end_mm: f64,
}

/// The gaps between layers the bolts' heads need before any part moves, per face from the bodies
/// outwards: heads of bolts through a body stand out of its other face, so the gap next to the
/// bodies on that face holds them. Every other gap starts at zero.
fn head_gaps(fab: &Fabrication, fixed: &[FixedPart], columns: &[Column]) -> [Vec<f64>; 2] {
    let face = &fab.ordering.face;
    let layers_on = |f: Face| fab.ordering.layers_on(f) as usize;
    let mut gaps: [Vec<f64>; 2] = [vec![0.0; layers_on(Face::Front)], vec![0.0; layers_on(Face::Back)]];
    // The joints' bolts standing in a body, and the brackets' fixing bolts.
    let through = columns.iter().filter(|c| c.from == 0 && c.end_mm > 0.0).map(|c| (c.face, c.end_mm));
    let fixing = fixed.iter().filter(|f| !f.fixings.is_empty()).map(|f| (face[f.member], Stack::gap(&f.fixing_bolt)));
    for (on, end_mm) in through.chain(fixing).collect::<Vec<_>>() {
        let other = super::stack::side(if on == Face::Front { Face::Back } else { Face::Front });
        if let Some(g) = gaps[other].first_mut() {
            *g = g.max(end_mm);
        }
    }
    gaps
}

/// The layout's members as cut, placed at one row of the motion: what the clearance checks test
/// against each other and against the columns.
struct PartsAt<'a> {
    fab: &'a Fabrication,
    /// Every member's core at this row, scene units.
    cores: &'a [Vec<Point>],
    /// Every member's half width as cut, scene units.
    radius: &'a [f64],
    /// The bolt holes' radial clearance, scene units: the play a part has about its bolt, so the
    /// margin two things must keep apart not to touch.
    clearance: f64,
}

impl PartsAt<'_> {
    /// Notes every two members on one layer of one face whose outlines overlap. Members on one
    /// carrier keep their places against each other along the motion, so they are only tested at
    /// the first row.
    fn overlaps(&self, first_row: bool, note: &mut impl FnMut(String)) {
        let layout = &self.fab.layout;
        let (face, layer) = (&self.fab.ordering.face, &self.fab.ordering.layer);
        let n = layout.members.len();
        for a in 0..n {
            for b in a + 1..n {
                let same_carrier = layout.members[a].carrier == layout.members[b].carrier;
                if face[a] != face[b] || layer[a] != layer[b] || (same_carrier && !first_row) {
                    continue;
                }
                if core_distance(&self.cores[a], &self.cores[b]) < self.radius[a] + self.radius[b] + self.clearance {
                    note(format!("{} and {} overlap on one layer", layout.members[a].name, layout.members[b].name));
                }
            }
        }
    }

    /// Tests every member on a column's face that passes over the column at this row (`row` the
    /// joints, `poses` the carriers): beyond its outermost layer, the gap over that layer must hold
    /// the column's end (the nut); under its innermost, the gap under that one (the head); between
    /// the layers it joins, the member crosses it, which is noted.
    fn crossings(
        &self,
        columns: &[Column],
        row: &[Point],
        poses: &[Rigid],
        gaps: &mut [Vec<f64>; 2],
        note: &mut impl FnMut(String),
    ) {
        let layout = &self.fab.layout;
        let (face, layer) = (&self.fab.ordering.face, &self.fab.ordering.layer);
        for c in columns {
            let at = match c.joint {
                Some(j) => row[j],
                None => poses[c.carrier].apply(c.at),
            };
            for i in 0..layout.members.len() {
                if c.own.contains(&i) || face[i] != c.face {
                    continue;
                }
                if core_distance(&self.cores[i], &[at]) >= self.radius[i] + c.reach + self.clearance {
                    continue;
                }
                let side = super::stack::side(c.face);
                if layer[i] > c.to {
                    // Over the nut.
                    gaps[side][c.to as usize] = gaps[side][c.to as usize].max(c.end_mm);
                } else if layer[i] < c.from {
                    // Under the head.
                    gaps[side][c.from as usize - 1] = gaps[side][c.from as usize - 1].max(c.end_mm);
                } else if layer[i] > c.from || c.from == 0 {
                    note(format!("{} crosses {}", layout.members[i].name, c.what));
                }
            }
        }
    }
}

/// What a cut part is sized with: its kind, peak loads and section, and for a bracket (or the
/// guide, or the frame) the bolts fixing it and what it is fixed to.
struct PartSizing<'s> {
    kind: LinkKind,
    demand: &'s Demand,
    section: &'s Section,
    /// The fixing bolts' centres, carrier frame, scene units (none for a link).
    fixings: &'s [Point],
    /// The fixing bolts' size, when there are any.
    fixing_bolt: Option<BoltSpec>,
    /// The largest shear on one fixing bolt, N.
    fixing_shear_n: f64,
    /// The name of what it is fixed to (none for a link).
    on: Option<String>,
}

/// The planned parts on their layers: what the bolts through them are planned from.
struct Laid<'a> {
    fab: &'a Fabrication,
    links: &'a LinkSizing,
    /// The joints' bolt.
    bolt: BoltSpec,
    /// Every planned part on its layer, in the plans' order.
    layered: Vec<Layered>,
    stack: Stack,
    /// Per layout member that has a plan, its index among the plans.
    by_member: BTreeMap<usize, usize>,
}

/// The distance between every two of a part's joint holes (`centres`, by joint name), in the order
/// the joints are listed: what a workshop marks out before it drills.
fn pivot_lengths(centres: &[(String, Point)]) -> Vec<PivotLength> {
    let mut out = Vec::new();
    for (a, (na, pa)) in centres.iter().enumerate() {
        for (nb, pb) in &centres[a + 1..] {
            out.push(PivotLength { joints: [na.clone(), nb.clone()], length_mm: pa.distance(*pb) });
        }
    }
    out
}

/// A fixing bolt's stack through the body `f` is fixed to (`body`: its name and thickness, mm) and
/// `f` itself (`part`), with the stand-off block's height (mm, zero when the bracket lies on the
/// body). Off the body's face the bracket stands on a block under its post end, clamped by the
/// bolts: they do not bend across it, and the block carries the bracket's load to the body, so the
/// spacer the stack puts there is that block.
fn fixing_stack(
    stack: &Stack,
    f: &FixedPart,
    body: (&str, f64),
    part: &Layered,
) -> (Vec<super::report::StackItem>, f64) {
    let mut stack_items = stack.bolt(&f.fixing_bolt, Some(body), &[part]);
    let mut stand_off = 0.0;
    for item in stack_items.iter_mut().filter(|i| i.item == "spacer") {
        item.item = "block";
        item.name = Some(format!("{} stand-off", f.name));
        stand_off = item.thickness_mm;
    }
    (stack_items, stand_off)
}

/// A fixing bolt's checks, `factor` the safety factor: its share of the bracket's force in shear,
/// the tension that keeps the bracket from tipping, and the two together.
fn fixing_checks(spec: &BoltSpec, factor: f64, share: f64, tension: f64) -> Vec<Check> {
    vec![
        Check::new("bolt shear", factor * share, spec.shear_strength_n(), "N"),
        Check::new("bolt tension", factor * tension, spec.tension_strength_n(), "N"),
        Check::new(
            "bolt shear and tension",
            factor * (share / spec.shear_strength_n() + tension / (1.4 * spec.tension_strength_n())),
            1.0,
            "",
        ),
    ]
}

/// A note for every check that does not hold: the bolts' first, then the parts', each with what
/// to change.
fn failed_check_notes(bolts: &[JointPlan], plans: &[LinkPlan]) -> Vec<String> {
    let mut notes = Vec::new();
    for b in bolts {
        for c in b.checks.iter().filter(|c| !c.ok) {
            notes.push(format!(
                "The {} bolt{} at {}: {} does not hold ({:.0} {} against {:.0} {}): bring its parts closer together \
                 (fewer layers between them) or choose a larger bolt.",
                b.bolt,
                if b.count > 1 { "s" } else { "" },
                b.at,
                c.rule,
                c.demand,
                c.unit,
                c.capacity,
                c.unit
            ));
        }
    }
    for p in plans {
        for c in p.checks.iter().filter(|c| !c.ok) {
            notes.push(format!(
                "{}: {} does not hold ({:.0} {} against {:.0} {}) even at the thickest stock ({} mm): {}.",
                p.name,
                c.rule,
                c.demand,
                c.unit,
                c.capacity,
                c.unit,
                number(p.thickness_mm),
                match p.kind {
                    LinkKind::Link => "choose a stronger material, a lighter load or a design with shorter links",
                    _ => {
                        "draw the body it is fixed to reaching nearer its joint (a shorter bracket), or choose a \
                         stronger material"
                    }
                }
            ));
        }
    }
    notes
}

/// The largest torque holding the linkage at its crank along `rows`, N·m, and the crank angle at
/// that peak, degrees (the last such row on a tie; both zero without rows).
fn peak_torque(rows: &[RowForces]) -> (f64, f64) {
    let (peak_row, peak_torque_nm) = rows
        .iter()
        .enumerate()
        .map(|(r, row)| (r, row.torque_nm.abs()))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((0, 0.0));
    (peak_torque_nm, rows.get(peak_row).map_or(0.0, |r| r.crank_deg))
}

/// The largest shear across a bolt and the largest bending moment in it along the motion: the
/// parts (and the body) of `stack` press on it, the k-th of them with `force(row, k)` (N) at the
/// middle of its thickness, over `rows` rows. The shear at an interface is the sum of the forces on
/// one side; the moment at a part's middle is half that shear times the distance to the next part's
/// middle (the two parts share the couple of the offset forces, holding the bolt square in their
/// holes).
fn bolt_loads(stack: &[super::report::StackItem], force: impl Fn(usize, usize) -> Vec2, rows: usize) -> (f64, f64) {
    let mut middles = Vec::new();
    let mut z = 0.0;
    for item in stack {
        if matches!(item.item, "part" | "body") {
            middles.push(z + 0.5 * item.thickness_mm);
        }
        z += item.thickness_mm;
    }
    let (mut shear, mut moment) = (0.0f64, 0.0f64);
    for r in 0..rows {
        let mut sum = Vec2::ZERO;
        for k in 0..middles.len().saturating_sub(1) {
            sum += force(r, k);
            let v = sum.norm();
            shear = shear.max(v);
            moment = moment.max(0.5 * v * (middles[k + 1] - middles[k]) / 1000.0);
        }
    }
    (shear, moment)
}

/// A bolt's shear (one plane) and bending (thread core) checks, the safety factor applied.
fn bolt_checks(bolt: &BoltSpec, factor: f64, shear_n: f64, moment_nm: f64) -> Vec<Check> {
    vec![
        Check::new("bolt shear", factor * shear_n, bolt.shear_strength_n(), "N"),
        Check::new("bolt bending", factor * moment_nm, bolt.bending_strength_nm(), "N·m"),
    ]
}

/// The distance between two convex cores (one, two or three points: a point, a segment, a triangle),
/// zero when they overlap.
fn core_distance(a: &[Point], b: &[Point]) -> f64 {
    let edges = |c: &[Point]| -> Vec<(Point, Point)> {
        match c.len() {
            0 => Vec::new(),
            1 => vec![(c[0], c[0])],
            2 => vec![(c[0], c[1])],
            k => (0..k).map(|i| (c[i], c[(i + 1) % k])).collect(),
        }
    };
    let inside = |p: Point, c: &[Point]| {
        c.len() >= 3 && {
            let sides: Vec<f64> = (0..c.len()).map(|i| (c[(i + 1) % c.len()] - c[i]).cross(p - c[i])).collect();
            sides.iter().all(|&s| s >= 0.0) || sides.iter().all(|&s| s <= 0.0)
        }
    };
    if a.iter().any(|&p| inside(p, b)) || b.iter().any(|&p| inside(p, a)) {
        return 0.0;
    }
    let mut best = f64::INFINITY;
    for &(p, q) in &edges(a) {
        for &(u, v) in &edges(b) {
            if crate::geom::segments_cross(p, q, u, v, 0.0) {
                return 0.0;
            }
            let d = point_segment_distance(p, u, v)
                .min(point_segment_distance(q, u, v))
                .min(point_segment_distance(u, p, q))
                .min(point_segment_distance(v, p, q));
            best = best.min(d);
        }
    }
    best
}

/// A point in scene units as millimetres.
fn scaled(p: Point, mm: f64) -> Point {
    Point::new(p.x * mm, p.y * mm)
}

/// A length to a tenth of a millimetre, without a trailing `.0`.
fn number_tenth(x: f64) -> String {
    let t = (x * 10.0).round() / 10.0;
    number(t)
}

fn material_words(material: Material) -> &'static str {
    match material {
        Material::Plywood => "birch plywood",
        Material::Aluminium => "6061-T6 aluminium plate",
        Material::Steel => "S235 steel plate",
    }
}
