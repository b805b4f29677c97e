use thiserror::Error;

/// Why a TIN could not be built, queried or rasterized.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum TinError {
    /// Fewer than three points.
    #[error("a TIN needs at least 3 points, got {count}")]
    TooFewPoints {
        /// Points given.
        count: usize,
    },
    /// More points than `u32` handles can address.
    #[error("{count} points exceed the maximum of {max} a TIN can index")]
    TooManyPoints {
        /// Points given.
        count: usize,
        /// The maximum.
        max: usize,
    },
    /// A coordinate is NaN or infinite.
    #[error("point {index} is not finite: ({x}, {y})")]
    NonFinitePoint {
        /// Index of the point.
        index: usize,
        /// Its x.
        x: f64,
        /// Its y.
        y: f64,
    },
    /// A coordinate's magnitude is outside the range exact predicates support
    /// (zero or 2^-142 ..= 2^201).
    #[error("point {index} ({x}, {y}) has a coordinate outside 0 or [2^-142, 2^201] in magnitude")]
    CoordinateOutOfRange {
        /// Index of the point.
        index: usize,
        /// Its x.
        x: f64,
        /// Its y.
        y: f64,
    },
    /// Two input points coincide.
    #[error("points {first} and {second} coincide at ({x}, {y})")]
    DuplicatePoint {
        /// Lower index.
        first: usize,
        /// Higher index.
        second: usize,
        /// Shared x.
        x: f64,
        /// Shared y.
        y: f64,
    },
    /// All points lie on one line: no triangle exists.
    #[error("all {count} points are collinear: no triangle can be formed")]
    Collinear {
        /// Points given.
        count: usize,
    },
    /// A triangle given to [`crate::Tin::from_parts`] is malformed.
    #[error("triangle {triangle} is invalid: {reason}")]
    InvalidTriangle {
        /// Index of the triangle.
        triangle: usize,
        /// What is wrong.
        reason: String,
    },
    /// A constraint edge given to [`crate::Tin::constrained`] names a missing or repeated vertex.
    #[error("constraint {constraint} joins vertices {a} and {b}: {reason}")]
    InvalidConstraint {
        /// Index of the constraint.
        constraint: usize,
        /// First vertex.
        a: u32,
        /// Second vertex.
        b: u32,
        /// What is wrong.
        reason: &'static str,
    },
    /// The triangles do not form a manifold, consistently oriented mesh around a vertex.
    #[error("triangles around vertex {vertex} do not form a single fan (non-manifold or inconsistent orientation)")]
    NonManifoldVertex {
        /// The vertex.
        vertex: usize,
    },
    /// A per-node value array has the wrong length.
    #[error("{found} node values given for a TIN of {expected} nodes")]
    ValueCountMismatch {
        /// Nodes in the TIN.
        expected: usize,
        /// Values given.
        found: usize,
    },
    /// A per-node value is infinite (NaN is allowed and rasterizes as no-data).
    #[error("value of node {node} is {value}; node values must be finite (NaN marks no-data)")]
    NonFiniteValue {
        /// The node.
        node: usize,
        /// Its value.
        value: f64,
    },
    /// `check_invariants` found a broken internal invariant.
    #[error("TIN invariant violated: {0}")]
    Invariant(String),
}
