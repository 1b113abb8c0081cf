//! Closed triangle meshes of 2.5D parts: a slab (an outline with holes, extruded between two heights)
//! with round or square features through it (holes, holes with a boss) or standing on its top face
//! (pins with a snap cap, posts), every feature a solid of revolution of a profile.
//!
//! Every vertex of a face's hole is the vertex of the feature that meets it, so meshes are closed,
//! consistently oriented 2-manifolds by construction (outward normals, counter-clockwise triangles
//! seen from outside).

use crate::geom::{Point, Vec2};

/// An indexed triangle mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions `[x, y, z]`.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles as three indices into `vertices`, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

/// Why a slab could not be meshed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("cannot mesh {0}")]
pub(crate) struct MeshError(pub String);

impl Mesh {
    fn add(&mut self, p: [f64; 3]) -> u32 {
        self.vertices.push(p);
        (self.vertices.len() - 1) as u32
    }
    /// Signed volume (positive for outward normals).
    pub fn volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.vertices[i as usize]);
                (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                    + a[2] * (b[0] * c[1] - b[1] * c[0]))
                    / 6.0
            })
            .sum()
    }
    /// The smallest box around the vertices: `(min, max)`.
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for v in &self.vertices {
            for k in 0..3 {
                lo[k] = lo[k].min(v[k]);
                hi[k] = hi[k].max(v[k]);
            }
        }
        (lo, hi)
    }
    /// The mesh with every vertex mapped by `f`; `mirror` must be true when `f` reverses orientation
    /// (the triangles are then flipped to keep normals outward).
    pub fn mapped(&self, f: impl Fn([f64; 3]) -> [f64; 3], mirror: bool) -> Mesh {
        Mesh {
            vertices: self.vertices.iter().map(|&v| f(v)).collect(),
            triangles: if mirror {
                self.triangles.iter().map(|t| [t[0], t[2], t[1]]).collect()
            } else {
                self.triangles.clone()
            },
        }
    }
    /// Appends another mesh (as a separate shell).
    pub fn append(&mut self, other: &Mesh) {
        let base = self.vertices.len() as u32;
        self.vertices.extend_from_slice(&other.vertices);
        self.triangles.extend(other.triangles.iter().map(|t| t.map(|i| i + base)));
    }
    /// Checks that the mesh is a closed, consistently oriented 2-manifold: every directed edge appears
    /// exactly once and its reverse exactly once, no triangle is degenerate. Returns the first problem.
    pub fn check_closed(&self) -> Result<(), String> {
        use std::collections::HashMap;
        let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
        for (k, t) in self.triangles.iter().enumerate() {
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                return Err(format!("triangle {k} repeats a vertex"));
            }
            if t.iter().any(|&i| i as usize >= self.vertices.len()) {
                return Err(format!("triangle {k} names a missing vertex"));
            }
            for e in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                *edges.entry(e).or_default() += 1;
            }
        }
        for (&(a, b), &n) in &edges {
            if n != 1 {
                return Err(format!("edge {a}-{b} is used {n} times in one direction"));
            }
            if edges.get(&(b, a)) != Some(&1) {
                return Err(format!("edge {a}-{b} has no opposite: the mesh is open or inconsistently oriented"));
            }
        }
        Ok(())
    }
}

/// The cross-section of a feature at one height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum RingShape {
    /// A circle of this radius.
    Circle(f64),
    /// A square of this half side, corners on the axes (a diamond in the part's frame).
    Square(f64),
    /// The point on the axis that closes a stud.
    Apex,
}

/// One ring of a feature's profile.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Ring {
    pub z: f64,
    pub shape: RingShape,
}

/// A solid of revolution around a vertical axis: its profile runs with the material on its right
/// (looking along the profile in the plane of radius and height). A through feature starts with a
/// ring on the slab's bottom face and ends with one on its top face; a stud starts with its apex and
/// ends with a ring on the top face.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Feature {
    pub centre: Point,
    pub rings: Vec<Ring>,
}

impl Feature {
    /// A plain round hole of radius `r` through the slab `z0..z1`.
    pub(crate) fn hole(centre: Point, r: f64, z0: f64, z1: f64) -> Feature {
        Feature { centre, rings: vec![ring(z0, RingShape::Circle(r)), ring(z1, RingShape::Circle(r))] }
    }
    /// A square socket through the slab.
    pub(crate) fn socket(centre: Point, half: f64, z0: f64, z1: f64) -> Feature {
        Feature { centre, rings: vec![ring(z0, RingShape::Square(half)), ring(z1, RingShape::Square(half))] }
    }
    /// A round hole through the slab and through a boss of radius `rb` standing on the top face up
    /// to `top`.
    pub(crate) fn bossed_hole(centre: Point, r: f64, rb: f64, z0: f64, z1: f64, top: f64) -> Feature {
        let rings = vec![
            ring(z0, RingShape::Circle(r)),
            ring(top, RingShape::Circle(r)),
            ring(top, RingShape::Circle(rb)),
            ring(z1, RingShape::Circle(rb)),
        ];
        Feature { centre, rings }
    }
    /// A stud standing on the top face at `z1`, given bottom-up as `(height, shape)` steps: each step
    /// is the cross-section from its height to the next step's. The last step rises to `top`, tapering
    /// to `tip` when given (a snap cap's lead-in), and is closed by a flat top.
    pub(crate) fn stud(
        centre: Point,
        z1: f64,
        steps: &[(f64, RingShape)],
        top: f64,
        tip: Option<RingShape>,
    ) -> Feature {
        // Bottom-up rings: at each step's height the previous shape, then the new one.
        let mut up: Vec<Ring> = Vec::new();
        let mut prev: Option<RingShape> = None;
        for &(z, shape) in steps {
            if let Some(p) = prev {
                up.push(ring(z, p));
            } else {
                debug_assert!((z - z1).abs() < 1e-12);
            }
            up.push(ring(z, shape));
            prev = Some(shape);
        }
        if let Some(p) = prev {
            up.push(ring(top, tip.unwrap_or(p)));
        }
        up.push(ring(top, RingShape::Apex));
        up.reverse();
        let mut rings: Vec<Ring> = Vec::new();
        for r in up {
            if rings.last().is_some_and(|l: &Ring| l.z == r.z && l.shape == r.shape) {
                continue;
            }
            rings.push(r);
        }
        Feature { centre, rings }
    }
}

fn ring(z: f64, shape: RingShape) -> Ring {
    Ring { z, shape }
}

/// Vertices of a ring around `c`, counter-clockwise from angle 0, with their angles.
fn ring_points(c: Point, shape: RingShape, segments: usize) -> Vec<(Point, f64)> {
    match shape {
        RingShape::Circle(r) => (0..segments)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / segments as f64;
                (c + Vec2::from_angle(a) * r, a)
            })
            .collect(),
        RingShape::Square(h) => (0..4)
            .map(|i| {
                let a = std::f64::consts::FRAC_PI_2 * i as f64;
                (c + Vec2::from_angle(a) * (h * std::f64::consts::SQRT_2), a)
            })
            .collect(),
        RingShape::Apex => vec![(c, 0.0)],
    }
}

/// The planar points of a ring (for profiles and hole outlines).
pub(crate) fn ring_outline(c: Point, shape: RingShape, segments: usize) -> Vec<Point> {
    ring_points(c, shape, segments).into_iter().map(|(p, _)| p).collect()
}

/// A slab: `outline` (any winding) with contour `holes`, between `z0` and `z1`, with features.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Slab {
    pub outline: Vec<Point>,
    pub holes: Vec<Vec<Point>>,
    pub z0: f64,
    pub z1: f64,
    /// Features through the slab (first ring at `z0`, last at `z1`).
    pub through: Vec<Feature>,
    /// Features on the top face (first ring an apex, last at `z1`).
    pub studs: Vec<Feature>,
}

/// The ring without repeated or collinear vertices (the triangulator drops those, which would leave
/// the walls' vertices out of the faces and the mesh open).
pub(crate) fn clean_ring(pts: &[Point]) -> Vec<Point> {
    let mut out: Vec<Point> = pts.to_vec();
    loop {
        let n = out.len();
        if n < 3 {
            return out;
        }
        let size = crate::geom::Aabb::around(out.iter().copied()).map_or(1.0, |b| b.diagonal().max(1e-300));
        let drop = (0..n).find(|&i| {
            let (a, p, b) = (out[(i + n - 1) % n], out[i], out[(i + 1) % n]);
            p.distance(a) <= 1e-9 * size || (p - a).cross(b - p).abs() <= 1e-12 * size * size
        });
        match drop {
            Some(i) => {
                out.remove(i);
            }
            None => return out,
        }
    }
}

fn signed_area(p: &[Point]) -> f64 {
    crate::geom::Polygon::new(p.to_vec()).signed_area()
}

impl Slab {
    /// The closed mesh of the slab and its features.
    pub(crate) fn mesh(&self, segments: usize) -> Result<Mesh, MeshError> {
        if self.outline.len() < 3 || self.z1 <= self.z0 {
            return Err(MeshError("an empty or flat slab".into()));
        }
        let mut mesh = Mesh::default();
        let mut outline = clean_ring(&self.outline);
        if outline.len() < 3 {
            return Err(MeshError("a degenerate outline".into()));
        }
        if signed_area(&outline) < 0.0 {
            outline.reverse();
        }
        let holes: Vec<Vec<Point>> = self
            .holes
            .iter()
            .map(|h| clean_ring(h))
            .filter(|h| h.len() >= 3)
            .map(|mut h| {
                if signed_area(&h) > 0.0 {
                    h.reverse();
                }
                h
            })
            .collect();
        // Contours: vertices at both heights, walls between them.
        let mut bottom_loops: Vec<(Vec<Point>, Vec<u32>)> = Vec::new();
        let mut top_loops: Vec<(Vec<Point>, Vec<u32>)> = Vec::new();
        for c in std::iter::once(&outline).chain(holes.iter()) {
            let b: Vec<u32> = c.iter().map(|p| mesh.add([p.x, p.y, self.z0])).collect();
            let t: Vec<u32> = c.iter().map(|p| mesh.add([p.x, p.y, self.z1])).collect();
            let n = c.len();
            for i in 0..n {
                let k = (i + 1) % n;
                mesh.triangles.push([b[i], b[k], t[k]]);
                mesh.triangles.push([b[i], t[k], t[i]]);
            }
            bottom_loops.push((c.clone(), b));
            top_loops.push((c.clone(), t));
        }
        // Features: rings, stitched in profile order.
        for (list, through) in [(&self.through, true), (&self.studs, false)] {
            for f in list {
                let mut prev: Option<Vec<(u32, f64)>> = None;
                for (k, r) in f.rings.iter().enumerate() {
                    let pts = ring_points(f.centre, r.shape, segments);
                    let ids: Vec<(u32, f64)> = pts.iter().map(|&(p, a)| (mesh.add([p.x, p.y, r.z]), a)).collect();
                    if let Some(a) = &prev {
                        stitch(&mut mesh, a, &ids);
                    }
                    let hole_loop = |ids: &[(u32, f64)]| -> (Vec<Point>, Vec<u32>) {
                        (pts.iter().map(|&(p, _)| p).collect(), ids.iter().map(|&(i, _)| i).collect())
                    };
                    if through && k == 0 {
                        bottom_loops.push(hole_loop(&ids));
                    }
                    if k + 1 == f.rings.len() {
                        top_loops.push(hole_loop(&ids));
                    }
                    prev = Some(ids);
                }
            }
        }
        cap(&mut mesh, &bottom_loops, false)?;
        cap(&mut mesh, &top_loops, true)?;
        Ok(mesh)
    }
}

/// Triangulates the strip between two rings (`a` earlier in the profile than `b`), merging by angle.
fn stitch(mesh: &mut Mesh, a: &[(u32, f64)], b: &[(u32, f64)]) {
    let (na, nb) = (a.len(), b.len());
    let ang = |r: &[(u32, f64)], i: usize| r[i % r.len()].1 + std::f64::consts::TAU * (i / r.len()) as f64;
    if na == 1 && nb == 1 {
        return;
    }
    let (mut i, mut j) = (0usize, 0usize);
    let a_steps = if na == 1 { 0 } else { na };
    let b_steps = if nb == 1 { 0 } else { nb };
    while i < a_steps || j < b_steps {
        let advance_b = j < b_steps && (i >= a_steps || ang(b, j + 1) <= ang(a, i + 1));
        if advance_b {
            mesh.triangles.push([a[i % na].0, b[j % nb].0, b[(j + 1) % nb].0]);
            j += 1;
        } else {
            mesh.triangles.push([a[i % na].0, b[j % nb].0, a[(i + 1) % na].0]);
            i += 1;
        }
    }
}

/// Triangulates a horizontal face: the first loop is the outline, the others its holes; `up` chooses
/// the normal.
fn cap(mesh: &mut Mesh, loops: &[(Vec<Point>, Vec<u32>)], up: bool) -> Result<(), MeshError> {
    let mut coords = Vec::new();
    let mut ids = Vec::new();
    let mut hole_starts = Vec::new();
    for (k, (pts, idx)) in loops.iter().enumerate() {
        if k > 0 {
            hole_starts.push(ids.len());
        }
        for (p, &i) in pts.iter().zip(idx) {
            coords.push(p.x);
            coords.push(p.y);
            ids.push(i);
        }
    }
    let tris = earcutr::earcut(&coords, &hole_starts, 2).map_err(|e| MeshError(format!("a face: {e:?}")))?;
    let expected: f64 = loops
        .iter()
        .enumerate()
        .map(|(k, (p, _))| if k == 0 { signed_area(p).abs() } else { -signed_area(p).abs() })
        .sum();
    let mut covered = 0.0;
    for t in tris.chunks_exact(3) {
        let p = |k: usize| Point::new(coords[2 * t[k]], coords[2 * t[k] + 1]);
        let area = (p(1) - p(0)).cross(p(2) - p(0));
        covered += area.abs() / 2.0;
        let (a, b, c) = (ids[t[0]], ids[t[1]], ids[t[2]]);
        if (area > 0.0) == up {
            mesh.triangles.push([a, b, c]);
        } else {
            mesh.triangles.push([a, c, b]);
        }
    }
    if (covered - expected).abs() > 1e-6 * expected.abs().max(1e-12) {
        return Err(MeshError(format!("a face: triangulated area {covered} differs from {expected}")));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::testing::assert_close;

    fn square(s: f64) -> Vec<Point> {
        vec![Point::new(0., 0.), Point::new(s, 0.), Point::new(s, s), Point::new(0., s)]
    }

    #[test]
    fn plain_slab_is_closed_with_its_volume() {
        let m = Slab { outline: square(10.0), z0: 0.0, z1: 2.0, ..Slab::default() }.mesh(32).unwrap();
        m.check_closed().unwrap();
        assert_close(m.volume(), 200.0, 1e-9);
    }

    #[test]
    fn holes_bosses_studs_and_posts_are_closed() {
        let c = Point::new(5.0, 5.0);
        let slab = Slab {
            outline: square(20.0),
            holes: vec![vec![Point::new(14., 14.), Point::new(16., 14.), Point::new(16., 16.), Point::new(14., 16.)]],
            z0: 0.0,
            z1: 3.0,
            through: vec![
                Feature::bossed_hole(c, 1.0, 2.0, 0.0, 3.0, 5.0),
                Feature::socket(Point::new(15.0, 5.0), 1.0, 0.0, 3.0),
            ],
            studs: vec![
                Feature::stud(
                    Point::new(5.0, 15.0),
                    3.0,
                    &[(3.0, RingShape::Circle(2.0)), (4.0, RingShape::Circle(1.0)), (6.0, RingShape::Circle(1.3))],
                    7.0,
                    None,
                ),
                Feature::stud(
                    Point::new(10.0, 10.0),
                    3.0,
                    &[(3.0, RingShape::Circle(2.5)), (4.0, RingShape::Square(1.0)), (6.0, RingShape::Square(1.2))],
                    7.0,
                    None,
                ),
            ],
        };
        let m = slab.mesh(24).unwrap();
        m.check_closed().unwrap();
        assert!(m.volume() > 0.0);
        // Volume: slab minus holes plus boss plus studs, with polygonal circles.
        let poly = |r: f64, n: usize| 0.5 * n as f64 * r * r * (std::f64::consts::TAU / n as f64).sin();
        let sq = |h: f64| 4.0 * h * h;
        let expected = 3.0 * (400.0 - 4.0 - poly(1.0, 24) - sq(1.0))
            + 2.0 * (poly(2.0, 24) - poly(1.0, 24))
            + poly(2.0, 24)
            + 2.0 * poly(1.0, 24)
            + poly(1.3, 24)
            + poly(2.5, 24)
            + 2.0 * sq(1.0)
            + sq(1.2);
        assert_close(m.volume(), expected, 1e-6);
        // A tapered snap cap closes too.
        let pin = Feature::stud(
            c,
            3.0,
            &[(3.0, RingShape::Circle(2.0)), (4.0, RingShape::Circle(1.0)), (6.0, RingShape::Circle(1.3))],
            7.0,
            Some(RingShape::Circle(0.6)),
        );
        let m = Slab { outline: square(10.0), z0: 0.0, z1: 3.0, studs: vec![pin], ..Slab::default() }.mesh(24).unwrap();
        m.check_closed().unwrap();
    }
}
