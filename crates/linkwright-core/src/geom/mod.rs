//! Plane geometry: points and vectors, rigid transforms, polygons and the predicates the engine needs.
//!
//! Conventions: y points up, angles are radians counter-clockwise inside the library (degrees only in
//! files), `Point - Point = Vec2` and there is no `Point + Point`.

mod curve;
mod obstacle;
mod polygon;
mod rigid;
mod segment;
mod vector;

pub(crate) use curve::{length as curve_length, path_error, resample, resample_into, size as curve_size, smoothed};
pub use curve::{nearest, ExactMiss, PathError};
pub(crate) use obstacle::Obstacle;
pub(crate) use polygon::penetrates_unchecked;
pub use polygon::{outline_distance, Aabb, Polygon, PolygonError};
pub use rigid::{Isometry, Rigid};
pub(crate) use segment::{point_segment_distance, segments_cross};
pub use vector::{Point, Vec2};

#[cfg(test)]
pub(crate) mod testing {
    /// The one approximate-equality helper of the crate's tests.
    pub(crate) fn assert_close(a: f64, b: f64, tol: f64) {
        assert!((a - b).abs() <= tol, "{a} != {b} (tolerance {tol})");
    }
}
