//! Every output file of a fabrication as bytes, with its path relative to the output directory (the
//! caller writes them): `parts/NAME.stl`, `assembly.3mf`, `plate_N.3mf`, `profiles.svg`,
//! `profiles.dxf`, `assembly.svg` and `fabrication.json`.

use super::check::check;
use super::error::FabError;
use super::export::{profiles_dxf, profiles_svg, stl_bytes, three_mf, Profile};
use super::fabrication::Fabrication;
use super::plates::{pack, placed_mesh};
use super::report::{report, Report};
use super::solid::Mesh;
use crate::geom::Point;

/// The files every bundle holds besides its parts (`parts/NAME.stl`), its plates (`plate_N.3mf`) and
/// `fabrication.json`, which lists those.
pub const FIXED_FILES: [&str; 4] = ["assembly.3mf", "profiles.svg", "profiles.dxf", "assembly.svg"];

/// The files of a fabrication and its report.
#[derive(Clone, Debug)]
pub struct Bundle {
    /// `(relative path, contents)`, in a stable order.
    pub files: Vec<(String, Vec<u8>)>,
    /// The report `fabrication.json` holds.
    pub report: Report,
}

/// Every part's mesh in the world at the first pose (millimetres not applied: scene units).
pub fn assembled_meshes(fab: &Fabrication) -> Vec<Mesh> {
    let mut poses = Vec::new();
    fab.layout.carrier_poses(fab.trace.row(0), &mut poses);
    fab.parts
        .iter()
        .map(|p| {
            let pose = poses[p.carrier];
            p.mesh.mapped(
                |v| {
                    let q = pose.apply(Point::new(v[0], v[1]));
                    [q.x, q.y, v[2]]
                },
                false,
            )
        })
        .collect()
}

/// Builds every output of `fab`, running the checks for the report.
pub fn bundle(fab: &Fabrication) -> Result<Bundle, FabError> {
    let s = fab.dims.mm_per_unit;
    let io = |e: std::io::Error| FabError::Mesh(format!("cannot encode a 3MF file: {e}"));
    let mut files = Vec::new();
    for p in &fab.parts {
        let header = format!("Linkwright {} {}", fab.scene_name, p.name);
        files.push((format!("parts/{}.stl", p.name), stl_bytes(&p.print_mesh, s, &header)));
    }
    let assembled = assembled_meshes(fab);
    let objects: Vec<(String, &Mesh)> = fab.parts.iter().map(|p| p.name.clone()).zip(assembled.iter()).collect();
    files.push(("assembly.3mf".into(), three_mf(&format!("{} (assembled)", fab.scene_name), &objects, s).map_err(io)?));
    let print: Vec<&Mesh> = fab.parts.iter().map(|p| &p.print_mesh).collect();
    let plates = pack(&print, s, &fab.settings.bed);
    for (k, plate) in plates.plates.iter().enumerate() {
        let meshes: Vec<Mesh> =
            plate.placements.iter().map(|pl| placed_mesh(&fab.parts[pl.part].print_mesh, s, pl)).collect();
        let objects: Vec<(String, &Mesh)> =
            plate.placements.iter().map(|pl| fab.parts[pl.part].name.clone()).zip(meshes.iter()).collect();
        let title = format!("{} plate {}", fab.scene_name, k + 1);
        files.push((format!("plate_{}.3mf", k + 1), three_mf(&title, &objects, 1.0).map_err(io)?));
    }
    let profiles: Vec<Profile> = fab.parts.iter().map(|p| Profile { name: &p.name, contours: &p.profile }).collect();
    files.push(("profiles.svg".into(), profiles_svg(&profiles, s).into_bytes()));
    files.push(("profiles.dxf".into(), profiles_dxf(&profiles, s).into_bytes()));
    files.push(("assembly.svg".into(), super::sheet::assembly_svg(fab).into_bytes()));
    let report = report(fab, &plates, check(fab));
    let json = serde_json::to_string_pretty(&report).map_err(|e| FabError::Mesh(e.to_string()))?;
    files.push(("fabrication.json".into(), json.into_bytes()));
    Ok(Bundle { files, report })
}
