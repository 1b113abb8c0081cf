//! The files of a full-size build: the report as data, the sheet, the profiles and the two tables.

use super::outline::{profiles_dxf, profiles_svg, Placed};
use super::report::{bom_csv, cut_list_csv, number, profile_file, thicknesses, Workshop};
use super::sheet::assembly_svg;

/// The files of a full-size build, each a path relative to the output folder and its bytes:
/// `workshop.json` (the [`Workshop`] as data), `workshop_assembly.svg` (the layers side by side and
/// the steps), `profiles_Tmm.dxf` and `profiles_Tmm.svg` for each stock thickness T (every part cut
/// from it, full size, millimetres), `cut_list.csv` and `bill_of_materials.csv`.
pub fn files(workshop: &Workshop) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let json = serde_json::to_vec_pretty(workshop).expect("a workshop always serializes");
    out.push(("workshop.json".to_string(), json));
    out.push(("workshop_assembly.svg".to_string(), assembly_svg(workshop).into_bytes()));
    for t in thicknesses(&workshop.links) {
        let parts: Vec<Placed> = workshop
            .links
            .iter()
            .filter(|l| l.thickness_mm == t)
            .map(|l| Placed { name: &l.name, outline: &l.outline })
            .collect();
        let title = format!("{}: {} mm {}", workshop.scene, number(t), workshop.material.id());
        out.push((profile_file(t, "dxf"), profiles_dxf(&parts).into_bytes()));
        out.push((profile_file(t, "svg"), profiles_svg(&title, &parts).into_bytes()));
    }
    out.push(("cut_list.csv".to_string(), cut_list_csv(&workshop.cut_list).into_bytes()));
    out.push(("bill_of_materials.csv".to_string(), bom_csv(&workshop.bill_of_materials).into_bytes()));
    out
}
