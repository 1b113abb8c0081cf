//! The layer stack: how far from the bodies' face each layer lies, and what each bolt passes through.
//!
//! Layer k of a face is as thick as its thickest part. Between two layers (and between the bodies
//! and layer 1) lies a gap: a washer's thickness, or, where a bolt's end stands in it under a part
//! that passes over that bolt, room for the end: a washer, the nut and two threads, and a washer's
//! thickness to spare ([`Stack::gap`]; a head is lower than its nut). So layer k starts
//! `Σ_{i<k} (g_i + T_i) + g_{k−1}`… from the face, `g_0` the gap next to the bodies. A part thinner
//! than its layer lies on the layer's inner side. On a bolt, two parts a washer apart get a washer
//! between them, farther apart a spacer tube of the gap's length; a washer sits under the head and
//! under the nut. Bolts are inserted from the bodies' side, so the head is under the body (or the
//! innermost part) and the nut outermost.

use super::report::{LayerPlan, StackItem};
use super::standards::BoltSpec;
use crate::fab::Face;

/// A part on a layer.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Layered {
    pub name: String,
    pub face: Face,
    pub layer: u32,
    pub thickness_mm: f64,
}

/// The layers of both faces.
#[derive(Clone, Debug)]
pub(crate) struct Stack {
    /// Per face (front, back), the thickness of each layer from 1.
    thickness: [Vec<f64>; 2],
    /// Per face, the gap under each layer from 1 (the first between the bodies and layer 1).
    gaps: [Vec<f64>; 2],
    washer_mm: f64,
}

pub(crate) fn side(face: Face) -> usize {
    match face {
        Face::Front => 0,
        Face::Back => 1,
    }
}

impl Stack {
    /// The layers of `parts`, a washer of `bolt` apart except where `gaps` (per face, under layer
    /// k + 1 at index k) asks for more.
    pub(crate) fn new(parts: &[Layered], bolt: &BoltSpec, gaps: &[Vec<f64>; 2]) -> Stack {
        let mut thickness: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
        for p in parts {
            let layers = &mut thickness[side(p.face)];
            let k = p.layer.max(1) as usize;
            if layers.len() < k {
                layers.resize(k, 0.0);
            }
            layers[k - 1] = layers[k - 1].max(p.thickness_mm);
        }
        let gaps = [0, 1].map(|f| {
            (0..thickness[f].len()).map(|k| gaps[f].get(k).copied().unwrap_or(0.0).max(bolt.washer_mm)).collect()
        });
        Stack { thickness, gaps, washer_mm: bolt.washer_mm }
    }

    /// The room a bolt's end needs under a part passing over it, mm: a washer, the nut and two
    /// threads, and a washer's thickness to spare.
    pub(crate) fn gap(bolt: &BoltSpec) -> f64 {
        2.0 * bolt.washer_mm + bolt.nut_mm + 2.0 * bolt.pitch_mm
    }

    /// How far layer `k` of `face` starts from the bodies' face, mm.
    pub(crate) fn layer_start(&self, face: Face, k: u32) -> f64 {
        let f = side(face);
        let k = k.max(1) as usize;
        let below: f64 = self.thickness[f].iter().take(k - 1).sum();
        let gaps: f64 = self.gaps[f].iter().take(k).sum();
        below + gaps
    }

    /// Every layer, front face first, from the bodies outwards.
    pub(crate) fn layers(&self, parts: &[Layered]) -> Vec<LayerPlan> {
        let mut out = Vec::new();
        for face in [Face::Front, Face::Back] {
            for (i, &t) in self.thickness[side(face)].iter().enumerate() {
                let k = i as u32 + 1;
                out.push(LayerPlan {
                    face,
                    layer: k,
                    from_face_mm: self.layer_start(face, k),
                    thickness_mm: t,
                    parts: parts.iter().filter(|p| p.face == face && p.layer == k).map(|p| p.name.clone()).collect(),
                });
            }
        }
        out
    }

    /// What `bolt` passes through, from under its head to the nut: the body (name and thickness)
    /// when it stands in one, then `parts` (all on one face), innermost first.
    pub(crate) fn bolt(&self, bolt: &BoltSpec, body: Option<(&str, f64)>, parts: &[&Layered]) -> Vec<StackItem> {
        let mut sorted: Vec<&Layered> = parts.to_vec();
        sorted.sort_by_key(|p| p.layer);
        let washer = || StackItem { item: "washer", name: None, thickness_mm: bolt.washer_mm };
        let mut out = vec![washer()];
        // Where the last item ends, measured from the bodies' face.
        let mut top = None;
        if let Some((name, t)) = body {
            out.push(StackItem { item: "body", name: Some(name.to_string()), thickness_mm: t });
            top = Some(0.0);
        }
        for p in sorted {
            let start = self.layer_start(p.face, p.layer);
            if let Some(top) = top {
                let gap: f64 = start - top;
                if (gap - self.washer_mm).abs() < 1e-9 && (bolt.washer_mm - self.washer_mm).abs() < 1e-9 {
                    out.push(washer());
                } else if gap > 1e-9 {
                    out.push(StackItem { item: "spacer", name: None, thickness_mm: gap });
                }
            }
            out.push(StackItem { item: "part", name: Some(p.name.clone()), thickness_mm: p.thickness_mm });
            top = Some(start + p.thickness_mm);
        }
        out.push(washer());
        out
    }

    /// The length a bolt needs through `stack` (then its nut, and two threads beyond it), and the
    /// standard length to buy, mm.
    pub(crate) fn bolt_length(stack: &[StackItem], bolt: &BoltSpec) -> (f64, f64) {
        let grip: f64 = stack.iter().map(|s| s.thickness_mm).sum();
        let needed = grip + bolt.nut_mm + 2.0 * bolt.pitch_mm;
        (needed, BoltSpec::standard_length(needed))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::workshop::standards::BoltSize;

    #[test]
    fn gaps_take_washers_or_spacers() {
        let bolt = BoltSize::M8.spec();
        let room = Stack::gap(&bolt);
        assert!((room - (1.6 + 8.0 + 2.5 + 1.6)).abs() < 1e-12);
        let part = |name: &str, layer, t| Layered { name: name.into(), face: Face::Front, layer, thickness_mm: t };
        let parts = [part("a", 1, 18.0), part("b", 2, 12.0), part("c", 3, 18.0), part("d", 2, 15.0)];
        // A nut stands between layers 2 and 3.
        let stack = Stack::new(&parts, &bolt, &[vec![0.0, 0.0, room], Vec::new()]);
        assert_eq!(stack.layer_start(Face::Front, 1), 1.6);
        assert!((stack.layer_start(Face::Front, 3) - (1.6 + 18.0 + 1.6 + 15.0 + room)).abs() < 1e-12);
        // a (layer 1) and c (layer 3): a spacer over layer 2 and its gaps.
        let items = stack.bolt(&bolt, Some(("bed", 20.0)), &[&parts[2], &parts[0]]);
        let kinds: Vec<&str> = items.iter().map(|i| i.item).collect();
        assert_eq!(kinds, ["washer", "body", "washer", "part", "spacer", "part", "washer"]);
        assert!((items[4].thickness_mm - (1.6 + 15.0 + room)).abs() < 1e-12);
        // a then b, a washer apart; b (12 mm on a 15 mm layer) then c: 3 mm of the layer and the room.
        let items = stack.bolt(&bolt, None, &[&parts[0], &parts[1]]);
        assert_eq!(items[2].item, "washer");
        let items = stack.bolt(&bolt, None, &[&parts[1], &parts[2]]);
        assert!((items[2].thickness_mm - (3.0 + room)).abs() < 1e-12 && items[2].item == "spacer");
        let (needed, length) = Stack::bolt_length(&items, &bolt);
        assert!((needed - (1.6 + 12.0 + 3.0 + room + 18.0 + 1.6 + 8.0 + 2.5)).abs() < 1e-12);
        assert_eq!(length, 65.0);
    }
}
