//! # linkwright-core
//!
//! The engine of Linkwright: from a sketched scene (fixed bodies, moving bodies and their key poses) to a
//! one-degree-of-freedom linkage that carries every moving body through its poses in order, after the
//! paper "Multi-Pose Interactive Linkage Design". All computation, no I/O.
//!
//! Modules, in the order data flows through them:
//! - [`geom`]: points, vectors, rigid transforms, polygons; [`xml`]: escaping text for XML files.
//! - [`scene`]: the `scene/1` format and its validation, and the [`scene::Problem`] derived from it.
//! - [`mechanism`]: linkage topologies (the K-body chain, the slider-crank) as joints + rigid parts.
//! - [`kinematics`]: a dyad plan compiled once per topology, evaluated per crank angle.
//! - [`synth`]: sampling, hard constraints, soft costs, the particle filter and the pipeline.
//! - [`design`]: the `design/1` format.
//! - [`render`]: pictures of a design (SVG text, static and animated).
//! - [`fab`]: fabrication: connectors, depth ordering, part solids, STL/3MF/SVG/DXF, plates, sheets.
//! - [`analysis`]: a design's motion replayed for display: frames, error at each pose, Grashof types.
//! - [`testbed`]: scenes made from known mechanisms (so an exact answer exists), for measuring designs.
//!
//! Conventions: world coordinates, y up; angles counter-clockwise, radians inside the library and
//! degrees in files; "the first pose" is pose 0 of every moving body, the configuration in which the
//! mechanism's joints are given. Every threshold is relative to the scene's size.

pub mod analysis;
pub mod design;
pub mod fab;
pub mod geom;
pub mod kinematics;
pub mod mechanism;
pub mod render;
pub mod scene;
pub mod synth;
pub mod testbed;
pub mod verify;
pub mod xml;
