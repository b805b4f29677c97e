use glam::DVec2;
use thiserror::Error;

/// Why a polygon was rejected. Rings are numbered 0 for the exterior, `1..` for the holes in the
/// order given; edge `e` of a ring joins its vertices `e` and `e + 1` (wrapping).
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum PolygonError {
    /// A ring has fewer than three distinct vertices.
    #[error("ring {ring} has {count} distinct vertices; a ring needs at least 3")]
    TooFewVertices {
        /// Ring index.
        ring: usize,
        /// Distinct vertices found.
        count: usize,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("ring {ring} vertex {vertex} is not finite: ({x}, {y})")]
    NonFiniteVertex {
        /// Ring index.
        ring: usize,
        /// Vertex index within the ring.
        vertex: usize,
        /// Its x.
        x: f64,
        /// Its y.
        y: f64,
    },
    /// A ring encloses no area (all vertices collinear).
    #[error("ring {ring} has zero area (its vertices are collinear)")]
    ZeroArea {
        /// Ring index.
        ring: usize,
    },
    /// Two edges touch or cross; rings must be simple and may not touch each other.
    #[error("ring {ring_a} edge {edge_a} touches or crosses ring {ring_b} edge {edge_b} near ({}, {})", at.x, at.y)]
    SelfIntersection {
        /// Ring of the first edge.
        ring_a: usize,
        /// First edge.
        edge_a: usize,
        /// Ring of the second edge.
        ring_b: usize,
        /// Second edge.
        edge_b: usize,
        /// A point near the contact.
        at: DVec2,
    },
    /// A hole lies outside the exterior ring, or inside another hole.
    #[error("hole ring {ring} is not strictly inside the exterior ring (or lies inside another hole)")]
    HoleOutside {
        /// Ring index of the hole.
        ring: usize,
    },
}

/// Why sampling could not run.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum SamplingError {
    /// The disc radius is not a finite positive number.
    #[error("radius {radius} must be finite and > 0")]
    InvalidRadius {
        /// The radius given.
        radius: f64,
    },
    /// The extended-domain margin is negative or not finite.
    #[error("margin {margin} must be finite and >= 0")]
    InvalidMargin {
        /// The margin given.
        margin: f64,
    },
    /// The number of candidates per point is zero.
    #[error("attempts per point must be at least 1, got {attempts}")]
    InvalidAttempts {
        /// The count given.
        attempts: u32,
    },
    /// The domain's bounds are empty, inverted or not finite.
    #[error("domain bounds [{}, {}] x [{}, {}] are not a finite, non-empty rectangle", min.x, max.x, min.y, max.y)]
    InvalidBounds {
        /// Minimum corner.
        min: DVec2,
        /// Maximum corner.
        max: DVec2,
    },
    /// The radius is so small for the domain that the result would exceed the point budget.
    #[error(
        "radius {radius} over a {width} x {height} domain needs about {estimated} points, over the limit of {limit}; raise the radius or the limit (`with_max_points`)"
    )]
    TooManyPoints {
        /// Radius (smallest radius for variable sampling).
        radius: f64,
        /// Domain bounds width.
        width: f64,
        /// Domain bounds height.
        height: f64,
        /// Points (or background-grid cells) the run would need.
        estimated: u64,
        /// The configured limit.
        limit: u64,
    },
    /// A target point count of zero, or an area that is not finite and positive.
    #[error("cannot derive a radius from {count} points over an area of {area}")]
    InvalidCount {
        /// Requested points.
        count: usize,
        /// Domain area.
        area: f64,
    },
}
