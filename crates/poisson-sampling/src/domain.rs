use glam::DVec2;

use crate::geometry::{SegmentIndex, segment_distance_sq};
use crate::{Polygon, PolygonSet, Rect, SamplingError};

/// A region of the plane that can be sampled: a bounding rectangle and a membership test.
///
/// `contains` is called for every accepted candidate, so it should be fast; the provided shapes
/// answer in O(1) ([`Rect`]) or O(edges in one horizontal band) ([`Polygon`], [`PolygonSet`]).
pub trait Domain {
    /// A rectangle containing every point of the domain.
    fn bounds(&self) -> Rect;
    /// Whether `p` belongs to the domain.
    fn contains(&self, p: DVec2) -> bool;
}

impl Domain for Rect {
    fn bounds(&self) -> Rect {
        *self
    }
    #[inline]
    fn contains(&self, p: DVec2) -> bool {
        Rect::contains(self, p)
    }
}

impl Domain for Polygon {
    fn bounds(&self) -> Rect {
        Polygon::bounds(self)
    }
    #[inline]
    fn contains(&self, p: DVec2) -> bool {
        Polygon::contains(self, p)
    }
}

impl Domain for PolygonSet {
    fn bounds(&self) -> Rect {
        PolygonSet::bounds(self)
    }
    #[inline]
    fn contains(&self, p: DVec2) -> bool {
        PolygonSet::contains(self, p)
    }
}

impl<D: Domain + ?Sized> Domain for &D {
    fn bounds(&self) -> Rect {
        (**self).bounds()
    }
    #[inline]
    fn contains(&self, p: DVec2) -> bool {
        (**self).contains(p)
    }
}

/// A domain given by a closure, e.g. a raster mask lookup: `contains(p) = bounds ∋ p && f(p)`.
#[derive(Debug, Clone, Copy)]
pub struct FnDomain<F> {
    bounds: Rect,
    f: F,
}

impl<F: Fn(DVec2) -> bool> FnDomain<F> {
    /// The points of `bounds` where `f` is true.
    pub fn new(bounds: Rect, f: F) -> Self {
        Self { bounds, f }
    }
}

impl<F: Fn(DVec2) -> bool> Domain for FnDomain<F> {
    fn bounds(&self) -> Rect {
        self.bounds
    }
    #[inline]
    fn contains(&self, p: DVec2) -> bool {
        self.bounds.contains(p) && (self.f)(p)
    }
}

/// The extended domain Ω ⊕ B(m) of the contours paper (§4.3): every point within distance `m` of
/// the polygon set Ω. Sampling it yields the nodes outside Ω that define the graph border ∂G.
///
/// Membership is `Ω ∋ p` or "some edge of Ω lies within `m` of `p`", the latter answered from a
/// grid of edges with cells of about `m`, so a query looks at a handful of nearby edges.
#[derive(Debug, Clone)]
pub struct ExtendedDomain<'a> {
    core: &'a PolygonSet,
    margin: f64,
    edges: Vec<[DVec2; 2]>,
    grid: SegmentIndex,
}

impl<'a> ExtendedDomain<'a> {
    /// Ω ⊕ B(`margin`).
    ///
    /// # Errors
    /// [`SamplingError::InvalidMargin`] for a negative or non-finite margin,
    /// [`SamplingError::InvalidBounds`] for an empty polygon set.
    pub fn new(core: &'a PolygonSet, margin: f64) -> Result<Self, SamplingError> {
        if !(margin.is_finite() && margin >= 0.0) {
            return Err(SamplingError::InvalidMargin { margin });
        }
        let b = core.bounds();
        if !b.is_valid() {
            return Err(SamplingError::InvalidBounds { min: b.min, max: b.max });
        }
        let edges: Vec<[DVec2; 2]> = core.edges().collect();
        let max_cells = (4 * edges.len()).clamp(4096, 1 << 22);
        let grid = SegmentIndex::new(&edges, b, margin.max(b.size().max_element() / 4096.0), max_cells);
        Ok(Self { core, margin, edges, grid })
    }

    /// The core domain Ω.
    pub fn core(&self) -> &PolygonSet {
        self.core
    }

    /// The margin `m`.
    pub fn margin(&self) -> f64 {
        self.margin
    }

    /// Whether `p` lies in Ω itself (the inside/outside tag of a sample).
    #[inline]
    pub fn in_core(&self, p: DVec2) -> bool {
        self.core.contains(p)
    }

    /// Whether an edge of Ω lies within `margin` of `p`.
    fn near_boundary(&self, p: DVec2) -> bool {
        let m = self.margin;
        let m2 = m * m;
        self.grid.for_each_near(p - DVec2::splat(m), p + DVec2::splat(m), |s| {
            let [a, b] = self.edges[s as usize];
            segment_distance_sq(p, a, b) <= m2
        })
    }
}

impl Domain for ExtendedDomain<'_> {
    fn bounds(&self) -> Rect {
        self.core.bounds().grow(self.margin)
    }
    #[inline]
    fn contains(&self, p: DVec2) -> bool {
        self.in_core(p) || (self.margin > 0.0 && self.near_boundary(p))
    }
}
