//! What the app's 3D preview needs to show a fabrication moving: every part's triangle mesh in its
//! carrier's frame, and each carrier's rigid pose at every row of the motion. Millimetres, rounded to
//! what a screen shows, so the payload stays small.

use linkwright_core::fab::{Carrier, Fabrication, Face, Role};
use serde::Serialize;

/// Lengths are rounded to hundredths of a millimetre (far below a pixel).
const PER_MM: f64 = 100.0;
/// Angles are rounded to thousandths of a degree.
const PER_DEG: f64 = 1000.0;

/// The preview of one fabrication.
#[derive(Clone, Debug, Serialize)]
pub(super) struct Preview {
    /// Always `"mm"`.
    pub units: &'static str,
    pub parts: Vec<PartMesh>,
    /// Number of carriers (the fixed bodies, each moving body, each link).
    pub carriers: usize,
    /// The crank angle of each row, degrees, in travel order.
    pub crank_deg: Vec<f64>,
    /// Per row, every carrier's pose as `x, y, angle_deg` one after another (`3 × carriers` numbers);
    /// angles unwrapped along the motion so they interpolate smoothly.
    pub poses: Vec<Vec<f64>>,
    /// The counterbalance springs hooked, each a coil between its hooks.
    pub springs: Vec<SpringPreview>,
}

/// A counterbalance spring: a coil between its two hooks, along its axis.
#[derive(Clone, Debug, Serialize)]
pub(super) struct SpringPreview {
    /// Each hook as `[carrier, x, y]`: the carrier it rides on (an index into each row of
    /// [`Preview::poses`]) and its place in that carrier's frame, mm.
    pub hooks: [[f64; 3]; 2],
    /// Height of the spring's axis, mm (z = 0 the bodies' front face).
    pub z: f64,
    /// The coil's radius, mm.
    pub radius: f64,
}

/// One part's mesh in its carrier's frame, at its assembled height (z = 0 is the bodies' front face).
#[derive(Clone, Debug, Serialize)]
pub(super) struct PartMesh {
    pub name: String,
    pub role: Role,
    pub face: Face,
    pub layer: u32,
    /// Index into each row of [`Preview::poses`].
    pub carrier: usize,
    /// The moving body a body part belongs to (its index in the scene), so it takes that body's colour.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub body: Option<usize>,
    /// `x, y, z` of each vertex, mm.
    pub positions: Vec<f64>,
    /// Three vertex indices per triangle, counter-clockwise seen from outside.
    pub indices: Vec<u32>,
}

/// `v` rounded to a multiple of `1 / per` (dividing by the exact `per` gives the shortest decimal);
/// `+ 0.0` turns a rounded -0 into 0, one character shorter in JSON.
fn round(v: f64, per: f64) -> f64 {
    (v * per).round() / per + 0.0
}

/// The preview of `fab`.
pub(super) fn preview(fab: &Fabrication) -> Preview {
    let mm = fab.dims.mm_per_unit;
    let parts = fab
        .parts
        .iter()
        .map(|p| PartMesh {
            name: p.name.clone(),
            role: p.role,
            face: p.face,
            layer: p.layer,
            carrier: p.carrier,
            body: match fab.layout.carriers.get(p.carrier) {
                Some(&Carrier::Body(b)) => Some(b),
                _ => None,
            },
            positions: p.mesh.vertices.iter().flat_map(|v| v.map(|x| round(x * mm, PER_MM))).collect(),
            indices: p.mesh.triangles.iter().flatten().copied().collect(),
        })
        .collect();
    let carriers = fab.layout.carriers.len();
    let mut poses: Vec<Vec<f64>> = Vec::with_capacity(fab.trace.len());
    let mut row_poses = Vec::new();
    for r in 0..fab.trace.len() {
        fab.layout.carrier_poses(fab.trace.row(r), &mut row_poses);
        let mut row = Vec::with_capacity(3 * carriers);
        for (c, pose) in row_poses.iter().enumerate() {
            let [x, y, mut angle] = pose.to_pose();
            if let Some(before) = poses.last() {
                angle = unwrap_near(angle, before[3 * c + 2]);
            }
            row.extend([round(x * mm, PER_MM), round(y * mm, PER_MM), round(angle, PER_DEG)]);
        }
        poses.push(row);
    }
    Preview {
        units: "mm",
        parts,
        carriers,
        crank_deg: fab.trace.thetas.iter().map(|t| round(t.to_degrees(), PER_DEG)).collect(),
        poses,
        springs: (0..fab.springs.len())
            .map(|n| {
                let hook = |k: usize| {
                    let h = &fab.layout.hooks[2 * n + k];
                    [h.carrier as f64, round(h.at.x * mm, PER_MM), round(h.at.y * mm, PER_MM)]
                };
                SpringPreview {
                    hooks: [hook(0), hook(1)],
                    z: round(fab.spring_axis_z(n) * mm, PER_MM),
                    radius: round(fab.dims.spring_radius() * mm, PER_MM),
                }
            })
            .collect(),
    }
}

/// `angle_deg` plus the whole turns that bring it closest to `previous_deg`.
fn unwrap_near(angle_deg: f64, previous_deg: f64) -> f64 {
    angle_deg - 360.0 * ((angle_deg - previous_deg) / 360.0).round()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles_unwrap_to_the_nearest_turn() {
        assert_eq!(unwrap_near(-179.0, 179.0), 181.0);
        assert_eq!(unwrap_near(179.0, -179.0), -181.0);
        assert_eq!(unwrap_near(10.0, 725.0), 730.0);
        assert_eq!(unwrap_near(5.0, 4.0), 5.0);
    }

    #[test]
    fn the_first_row_places_every_part_where_the_assembly_has_it() {
        use linkwright_core::fab::{assembled_meshes, fabricate_design_or_alternative, PrintSettings};
        use linkwright_core::{synthesize, DesignFile, Problem, Scene, Silent};
        let text = include_str!("../../../../examples/k1_garbage_truck.json");
        let mut scene = Scene::from_json(text).unwrap();
        scene.settings.samples = 3000;
        let problem = Problem::new(&scene).unwrap();
        let design = DesignFile::from_outcome(&problem, &synthesize(&problem, &Silent).unwrap());
        let fab = fabricate_design_or_alternative(&problem, &design, &PrintSettings::default()).unwrap().fabrication;
        let preview = preview(&fab);
        assert_eq!((preview.poses.len(), preview.crank_deg.len()), (fab.trace.len(), fab.trace.len()));
        assert!(preview.poses.iter().all(|row| row.len() == 3 * preview.carriers));
        let mm = fab.dims.mm_per_unit;
        for (part, assembled) in preview.parts.iter().zip(assembled_meshes(&fab)) {
            assert_eq!(part.indices.len(), 3 * assembled.triangles.len());
            let pose = &preview.poses[0][3 * part.carrier..3 * part.carrier + 3];
            let (sin, cos) = pose[2].to_radians().sin_cos();
            for (p, v) in part.positions.chunks(3).zip(&assembled.vertices) {
                let world = [pose[0] + cos * p[0] - sin * p[1], pose[1] + sin * p[0] + cos * p[1], p[2]];
                for k in 0..3 {
                    assert!((world[k] - v[k] * mm).abs() < 0.05, "{}: {world:?} vs {v:?}", part.name);
                }
            }
        }
    }

    #[test]
    fn rounding_keeps_hundredths_and_drops_negative_zero() {
        assert_eq!(round(1.23456, PER_MM), 1.23);
        assert_eq!(round(-0.001, PER_MM).to_string(), "0");
    }
}
