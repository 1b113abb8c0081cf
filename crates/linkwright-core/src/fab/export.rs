//! Exporters, each writing to an `impl Write` or returning bytes: binary STL (one mesh), 3MF (named
//! objects in one model, a zip of XML), SVG and DXF profiles (outlines with holes, for laser cutting).
//! Every exporter writes millimetres; `scale` is millimetres per unit of the geometry given.

use super::solid::Mesh;
use crate::geom::Point;
use std::fmt::Write as _;
use std::io::{self, Write};

/// Writes `mesh` as a binary STL (80-byte header, triangle count, per triangle its unit normal and
/// three vertices as little-endian f32, and a zero attribute).
pub(crate) fn write_stl(mesh: &Mesh, scale: f64, header: &str, w: &mut impl Write) -> io::Result<()> {
    let mut head = [0u8; 80];
    for (k, b) in header.bytes().take(80).enumerate() {
        head[k] = b;
    }
    // A header starting with "solid" makes some readers take the file for ASCII.
    if head.starts_with(b"solid") {
        head[0] = b'S';
    }
    w.write_all(&head)?;
    w.write_all(&(mesh.triangles.len() as u32).to_le_bytes())?;
    let mut buf = Vec::with_capacity(50 * mesh.triangles.len());
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.vertices[i as usize].map(|x| x * scale));
        let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        let n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        let n = if len > 0.0 { n.map(|x| x / len) } else { [0.0; 3] };
        for x in n.iter().chain(&a).chain(&b).chain(&c) {
            buf.extend_from_slice(&(*x as f32).to_le_bytes());
        }
        buf.extend_from_slice(&0u16.to_le_bytes());
    }
    w.write_all(&buf)
}

/// The binary STL of `mesh` as bytes.
pub(crate) fn stl_bytes(mesh: &Mesh, scale: f64, header: &str) -> Vec<u8> {
    let mut out = Vec::new();
    write_stl(mesh, scale, header, &mut out).expect("writing to memory never fails");
    out
}

fn xml_escape(s: &str) -> std::borrow::Cow<'_, str> {
    crate::xml::escape(s)
}

/// The 3MF model XML of named objects (each a mesh already in place), millimetres.
pub(crate) fn three_mf_model(title: &str, objects: &[(String, &Mesh)], scale: f64) -> String {
    let mut s = String::new();
    s.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    s.push_str(
        "<model unit=\"millimeter\" xml:lang=\"en-US\" xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\">\n",
    );
    let _ = writeln!(s, " <metadata name=\"Title\">{}</metadata>", xml_escape(title));
    s.push_str(" <metadata name=\"Application\">Linkwright</metadata>\n <resources>\n");
    for (k, (name, mesh)) in objects.iter().enumerate() {
        let _ = writeln!(
            s,
            "  <object id=\"{}\" type=\"model\" name=\"{}\">\n   <mesh>\n    <vertices>",
            k + 1,
            xml_escape(name)
        );
        for v in &mesh.vertices {
            let _ = writeln!(
                s,
                "     <vertex x=\"{:.5}\" y=\"{:.5}\" z=\"{:.5}\"/>",
                v[0] * scale,
                v[1] * scale,
                v[2] * scale
            );
        }
        s.push_str("    </vertices>\n    <triangles>\n");
        for t in &mesh.triangles {
            let _ = writeln!(s, "     <triangle v1=\"{}\" v2=\"{}\" v3=\"{}\"/>", t[0], t[1], t[2]);
        }
        s.push_str("    </triangles>\n   </mesh>\n  </object>\n");
    }
    s.push_str(" </resources>\n <build>\n");
    for k in 0..objects.len() {
        let _ = writeln!(s, "  <item objectid=\"{}\"/>", k + 1);
    }
    s.push_str(" </build>\n</model>\n");
    s
}

const CONTENT_TYPES: &str = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Types xmlns=\"http://schemas.openxmlformats.org/package/2006/content-types\"><Default Extension=\"rels\" ContentType=\"application/vnd.openxmlformats-package.relationships+xml\"/><Default Extension=\"model\" ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/></Types>\n";
const RELS: &str = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Relationships xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\"><Relationship Target=\"/3D/3dmodel.model\" Id=\"rel0\" Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/></Relationships>\n";

/// A 3MF package (zip) of named objects, each mesh already in place, millimetres.
pub(crate) fn three_mf(title: &str, objects: &[(String, &Mesh)], scale: f64) -> Result<Vec<u8>, io::Error> {
    use zip::write::SimpleFileOptions;
    let mut z = zip::ZipWriter::new(io::Cursor::new(Vec::new()));
    let opts = SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    let err = |e: zip::result::ZipError| io::Error::other(e.to_string());
    for (name, body) in [
        ("[Content_Types].xml", CONTENT_TYPES.to_string()),
        ("_rels/.rels", RELS.to_string()),
        ("3D/3dmodel.model", three_mf_model(title, objects, scale)),
    ] {
        z.start_file(name, opts).map_err(err)?;
        z.write_all(body.as_bytes())?;
    }
    Ok(z.finish().map_err(err)?.into_inner())
}

/// A named planar profile: its outline first, then its holes.
pub(crate) struct Profile<'a> {
    pub name: &'a str,
    pub contours: &'a [Vec<Point>],
}

/// Where each profile goes on the sheet: offsets (mm) in rows, left to right.
/// Where a profile goes: x and y offsets of its frame's origin, its width and height (mm).
type Spot = (f64, f64, f64, f64);

fn sheet_layout(profiles: &[Profile], scale: f64, width: f64, gap: f64) -> (Vec<Spot>, f64, f64) {
    let mut out = Vec::new();
    let (mut x, mut y, mut row_h, mut max_w) = (gap, gap, 0.0f64, 0.0f64);
    for p in profiles {
        let pts = p.contours.iter().flatten();
        let bb = crate::geom::Aabb::around(pts.copied())
            .unwrap_or(crate::geom::Aabb { min: Point::ORIGIN, max: Point::ORIGIN });
        let (w, h) = (bb.width() * scale, bb.height() * scale);
        if x + w + gap > width && x > gap {
            x = gap;
            y += row_h + gap + 6.0;
            row_h = 0.0;
        }
        out.push((x - bb.min.x * scale, y + bb.max.y * scale, w, h));
        x += w + gap;
        row_h = row_h.max(h);
        max_w = max_w.max(x);
    }
    (out, max_w.max(width.min(max_w + gap)), y + row_h + gap + 6.0)
}

/// Every profile on one SVG sheet (millimetres, y up in the parts' frames, flipped for SVG), each with
/// its name; holes cut by the even-odd rule.
pub(crate) fn profiles_svg(profiles: &[Profile], scale: f64) -> String {
    let (places, w, h) = sheet_layout(profiles, scale, 600.0, 8.0);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w:.1}mm\" height=\"{h:.1}mm\" viewBox=\"0 0 {w:.3} {h:.3}\">"
    );
    s.push_str("<style>path{fill:#d9e4f2;stroke:#1d3557;stroke-width:0.2;fill-rule:evenodd}text{font:3px sans-serif;fill:#333}</style>\n");
    for (p, &(ox, oy, _, ph)) in profiles.iter().zip(&places) {
        let mut d = String::new();
        for c in p.contours {
            for (k, q) in c.iter().enumerate() {
                let _ = write!(d, "{}{:.3},{:.3} ", if k == 0 { 'M' } else { 'L' }, ox + q.x * scale, oy - q.y * scale);
            }
            d.push('Z');
        }
        let _ = writeln!(s, "<g id=\"{}\"><path d=\"{}\"/>", xml_escape(p.name), d.trim());
        let _ = writeln!(
            s,
            "<text x=\"{:.2}\" y=\"{:.2}\">{}</text></g>",
            ox + p.contours.iter().flatten().map(|q| q.x).fold(f64::INFINITY, f64::min) * scale,
            oy - p.contours.iter().flatten().map(|q| q.y).fold(f64::NEG_INFINITY, f64::max) * scale + ph + 4.0,
            xml_escape(p.name)
        );
    }
    s.push_str("</svg>\n");
    s
}

/// Every profile as closed polylines in an ASCII DXF (R12), millimetres, one layer per part, placed
/// as on the SVG sheet.
pub(crate) fn profiles_dxf(profiles: &[Profile], scale: f64) -> String {
    let (places, _, h) = sheet_layout(profiles, scale, 600.0, 8.0);
    let mut s = String::new();
    let mut pair = |code: i32, value: &str| {
        let _ = write!(s, "{code}\n{value}\n");
    };
    pair(0, "SECTION");
    pair(2, "HEADER");
    pair(9, "$ACADVER");
    pair(1, "AC1009");
    pair(9, "$INSUNITS");
    pair(70, "4");
    pair(0, "ENDSEC");
    pair(0, "SECTION");
    pair(2, "ENTITIES");
    for (p, &(ox, oy, _, _)) in profiles.iter().zip(&places) {
        let layer = super::names::sanitize(p.name);
        for c in p.contours {
            pair(0, "POLYLINE");
            pair(8, &layer);
            pair(66, "1");
            pair(70, "1");
            for q in c {
                pair(0, "VERTEX");
                pair(8, &layer);
                pair(10, &format!("{:.4}", ox + q.x * scale));
                pair(20, &format!("{:.4}", h - (oy - q.y * scale)));
                pair(30, "0.0");
            }
            pair(0, "SEQEND");
            pair(8, &layer);
        }
    }
    pair(0, "ENDSEC");
    pair(0, "EOF");
    s
}
