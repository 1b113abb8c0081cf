//! Cutting a body too large for the print bed into pieces that fit, joined by dovetails: straight cuts
//! across the body's longest extent (and across the pieces' own when still too wide), placed clear of
//! its posts, pins and earlier dovetails, each with a dovetail tab where the cut is wide enough (the
//! pieces then slide together from above and hold in the plane).

use super::settings::Dims;
use super::shapes::overlay;
use crate::geom::{Point, Rigid, Vec2};
use i_overlay::core::overlay_rule::OverlayRule;

/// A region as contours: outline first, then holes.
pub(crate) type Contours = Vec<Vec<Point>>;
/// A disc to keep cuts away from: centre and radius.
type Disc = (Point, f64);

/// Splits `region` into pieces for which `fits` holds, cutting across direction `along` (unit), clear
/// of the discs `keep_clear` (centre, radius); a piece still too large the other way is cut again
/// across its own long side (clear of the dovetails already made). `None` when no cut placement works.
pub(crate) fn split(
    region: &Contours,
    along: Vec2,
    keep_clear: &[Disc],
    dims: &Dims,
    fits: &dyn Fn(&[Point]) -> bool,
) -> Option<Vec<Contours>> {
    split_within(region, along, keep_clear, dims, fits, 2)
}

fn split_within(
    region: &Contours,
    along: Vec2,
    keep_clear: &[Disc],
    dims: &Dims,
    fits: &dyn Fn(&[Point]) -> bool,
    again: u32,
) -> Option<Vec<Contours>> {
    for n in 2..=12usize {
        let Some((pieces, tabs)) = cut(region, along, n, keep_clear, dims) else { continue };
        if pieces.iter().all(|p| fits(&p[0])) {
            return Some(pieces);
        }
        if again == 0 {
            continue;
        }
        let keep: Vec<Disc> = keep_clear.iter().copied().chain(tabs).collect();
        let again = |p: &Contours| match fits(&p[0]) {
            true => Some(vec![p.clone()]),
            false => split_within(p, super::plates::long_axis(&p[0]), &keep, dims, fits, again - 1),
        };
        if let Some(out) = pieces.iter().map(again).collect::<Option<Vec<_>>>() {
            return Some(out.concat());
        }
    }
    None
}

/// `region` cut into `n` pieces across `along`, each cut moved off the discs `keep_clear` and given a
/// dovetail where it is wide enough; also the discs the dovetails occupy. `None` when a cut cannot be
/// placed clear of the discs.
fn cut(
    region: &Contours,
    along: Vec2,
    n: usize,
    keep_clear: &[Disc],
    dims: &Dims,
) -> Option<(Vec<Contours>, Vec<Disc>)> {
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
    // Cut positions, each moved off the pillars.
    let mut cuts = Vec::new();
    for k in 1..n {
        let nominal = lo + length * k as f64 / n as f64;
        let step = length / (n as f64 * 40.0);
        let s = (0..40)
            .flat_map(|i| [nominal + step * i as f64, nominal - step * i as f64])
            .find(|&s| clear_of(s, tab_depth))?;
        cuts.push(s);
    }
    let mut bounds = vec![lo - 1.0];
    bounds.extend(&cuts);
    bounds.push(hi + 1.0);
    let mut pieces: Vec<Vec<Contours>> =
        (0..n).map(|k| overlay(region, &[strip(bounds[k], bounds[k + 1])], OverlayRule::Intersect)).collect();
    let mut tabs = Vec::new();
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
        tabs.push((at(s + 0.5 * tab_depth, mid), (0.5 * tab_depth).hypot(0.5 * tab_top) + dims.clearance));
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
        let right: Vec<Contours> =
            pieces[k + 1].iter().flat_map(|p| overlay(p, &[tab(dims.clearance)], OverlayRule::Difference)).collect();
        pieces[k] = left;
        pieces[k + 1] = right;
    }
    Some((pieces.into_iter().flatten().collect(), tabs))
}
