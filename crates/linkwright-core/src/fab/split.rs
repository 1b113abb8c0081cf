//! Cutting a body too large for the print bed into pieces that fit, joined by dovetails: straight cuts
//! across the body's longest extent, placed clear of its posts and pins, each with a dovetail tab
//! where the cut is wide enough (the pieces then slide together from above and hold in the plane).

use super::settings::Dims;
use crate::geom::{Point, Rigid, Vec2};
use i_overlay::core::fill_rule::FillRule;
use i_overlay::core::overlay_rule::OverlayRule;
use i_overlay::float::single::SingleFloatOverlay;

/// A region as contours: outline first, then holes.
pub type Contours = Vec<Vec<Point>>;

fn to_f(c: &[Point]) -> Vec<[f64; 2]> {
    c.iter().map(|p| [p.x, p.y]).collect()
}
fn from_f(c: Vec<[f64; 2]>) -> Vec<Point> {
    c.into_iter().map(|[x, y]| Point::new(x, y)).collect()
}

fn overlay(subject: &[Vec<Point>], clip: &[Vec<Point>], rule: OverlayRule) -> Vec<Contours> {
    let s: Vec<Vec<[f64; 2]>> = subject.iter().map(|c| to_f(c)).collect();
    let c: Vec<Vec<[f64; 2]>> = clip.iter().map(|c| to_f(c)).collect();
    s.overlay(&c, rule, FillRule::EvenOdd)
        .into_iter()
        .map(|shape| shape.into_iter().map(from_f).collect::<Contours>())
        .filter(|c: &Contours| !c.is_empty() && crate::geom::Polygon::new(c[0].clone()).area() > 0.0)
        .collect()
}

/// Splits `region` into pieces for which `fits` holds, cutting across direction `along` (unit), clear
/// of the discs `keep_clear` (centre, radius). `None` when no cut placement works.
pub fn split(
    region: &Contours,
    along: Vec2,
    keep_clear: &[(Point, f64)],
    dims: &Dims,
    fits: &dyn Fn(&[Point]) -> bool,
) -> Option<Vec<Contours>> {
    let u = along.normalized();
    let v = u.perp();
    let pts: Vec<Point> = region.iter().flatten().copied().collect();
    let proj = |p: Point| p.to_vec2().dot(u);
    let (lo, hi) = pts.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &p| (a.min(proj(p)), b.max(proj(p))));
    let (vlo, vhi) = pts.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &p| {
        let t = p.to_vec2().dot(v);
        (a.min(t), b.max(t))
    });
    let length = hi - lo;
    let margin = 2.0 * dims.wall;
    let mm = 1.0 / dims.mm_per_unit;
    let (tab_base, tab_top, tab_depth) = (8.0 * mm, 11.0 * mm, 6.0 * mm);
    let frame = Rigid::from_frame(Point::ORIGIN, u);
    let at = |s: f64, t: f64| frame.apply(Point::new(s, t));
    let strip = |a: f64, b: f64| vec![at(a, vlo - 1.0), at(b, vlo - 1.0), at(b, vhi + 1.0), at(a, vhi + 1.0)];
    let clear_of = |s: f64, extra: f64| keep_clear.iter().all(|&(c, r)| (proj(c) - s).abs() >= r + extra + margin);
    for n in 2..=12usize {
        // Cut positions, each moved off the pillars.
        let mut cuts = Vec::new();
        let mut ok = true;
        for k in 1..n {
            let nominal = lo + length * k as f64 / n as f64;
            let step = length / (n as f64 * 40.0);
            let found = (0..40)
                .flat_map(|i| [nominal + step * i as f64, nominal - step * i as f64])
                .find(|&s| clear_of(s, tab_depth));
            match found {
                Some(s) => cuts.push(s),
                None => {
                    ok = false;
                    break;
                }
            }
        }
        if !ok {
            continue;
        }
        let mut bounds = vec![lo - 1.0];
        bounds.extend(&cuts);
        bounds.push(hi + 1.0);
        let mut pieces: Vec<Vec<Contours>> =
            (0..n).map(|k| overlay(region, &[strip(bounds[k], bounds[k + 1])], OverlayRule::Intersect)).collect();
        // A dovetail across each cut, on the widest stretch of the cut inside the region.
        let inside = crate::fab::shapes::Region { contours: region.clone() };
        for (k, &s) in cuts.iter().enumerate() {
            let samples = 200;
            let mut best: Option<(f64, f64)> = None;
            let mut run: Option<f64> = None;
            for i in 0..=samples {
                let t = vlo + (vhi - vlo) * i as f64 / samples as f64;
                let deep = inside.depth(at(s, t)) > dims.wall && inside.depth(at(s + tab_depth, t)) > dims.wall;
                match (deep, run) {
                    (true, None) => run = Some(t),
                    (false, Some(t0)) => {
                        if best.is_none_or(|(a, b)| t - t0 > b - a) {
                            best = Some((t0, t));
                        }
                        run = None;
                    }
                    _ => {}
                }
            }
            if let Some(t0) = run {
                if best.is_none_or(|(a, b)| vhi - t0 > b - a) {
                    best = Some((t0, vhi));
                }
            }
            let Some((t0, t1)) = best else { continue };
            // The run is already a wall inside the region on both sides.
            if t1 - t0 < tab_top {
                continue;
            }
            let mid = 0.5 * (t0 + t1);
            let tab = |grow: f64| {
                vec![
                    at(s - grow, mid - 0.5 * tab_base - grow),
                    at(s + tab_depth + grow, mid - 0.5 * tab_top - grow),
                    at(s + tab_depth + grow, mid + 0.5 * tab_top + grow),
                    at(s - grow, mid + 0.5 * tab_base + grow),
                ]
            };
            if !clear_of(s + 0.5 * tab_depth, 0.5 * tab_depth + tab_top) {
                continue;
            }
            // Left piece gains the tab (clipped to the region); right piece loses it with clearance.
            let tab_in_region = overlay(region, &[tab(0.0)], OverlayRule::Intersect);
            let mut left = Vec::new();
            for p in &pieces[k] {
                let mut merged = vec![p.clone()];
                for t in &tab_in_region {
                    merged = merged.iter().flat_map(|m| overlay(m, t, OverlayRule::Union)).collect();
                }
                left.extend(merged);
            }
            let right: Vec<Contours> = pieces[k + 1]
                .iter()
                .flat_map(|p| overlay(p, &[tab(dims.clearance)], OverlayRule::Difference))
                .collect();
            pieces[k] = left;
            pieces[k + 1] = right;
        }
        let all: Vec<Contours> = pieces.into_iter().flatten().collect();
        if all.iter().all(|p| fits(&p[0])) {
            return Some(all);
        }
    }
    None
}
