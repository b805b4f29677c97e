use glam::{DMat2, DVec2};

/// A continuous bijection of the plane: the contours paper's warps (§5.2–5.3), composable and
/// invertible, so warping contours never makes them cross and rasters warp by backward mapping.
pub trait Warp: Send + Sync {
    /// Where `p` goes.
    fn forward(&self, p: DVec2) -> DVec2;

    /// Where `q` came from: `forward(inverse(q)) = q`.
    fn inverse(&self, q: DVec2) -> DVec2;

    /// A rectangle `[min, max]` outside which the warp is the identity (`None`: unbounded).
    fn support(&self) -> Option<[DVec2; 2]>;

    /// The Jacobian of [`Warp::forward`] at `p`, by central differences with step `h`.
    fn jacobian(&self, p: DVec2, h: f64) -> DMat2 {
        let dx = (self.forward(p + DVec2::X * h) - self.forward(p - DVec2::X * h)) / (2.0 * h);
        let dy = (self.forward(p + DVec2::Y * h) - self.forward(p - DVec2::Y * h)) / (2.0 * h);
        DMat2::from_cols(dx, dy)
    }

    /// Whether the map preserves orientation around `p` (positive Jacobian determinant): a local
    /// check of bijectivity.
    fn is_locally_bijective(&self, p: DVec2, h: f64) -> bool {
        self.jacobian(p, h).determinant() > 0.0
    }
}

/// Warps applied one after another: `forward` applies them in order, `inverse` in reverse order.
#[derive(Default)]
pub struct Composition {
    warps: Vec<Box<dyn Warp>>,
}

impl std::fmt::Debug for Composition {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Composition({} warps)", self.warps.len())
    }
}

impl Composition {
    /// The identity.
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends `warp`, applied after those already there.
    #[must_use]
    pub fn then(mut self, warp: impl Warp + 'static) -> Self {
        self.warps.push(Box::new(warp));
        self
    }

    /// Appends a boxed warp.
    pub fn push(&mut self, warp: Box<dyn Warp>) {
        self.warps.push(warp);
    }

    /// Number of warps.
    pub fn len(&self) -> usize {
        self.warps.len()
    }

    /// Whether this is the identity.
    pub fn is_empty(&self) -> bool {
        self.warps.is_empty()
    }

    /// The `index`-th warp (0 applies first).
    pub fn get(&self, index: usize) -> Option<&dyn Warp> {
        self.warps.get(index).map(|w| &**w)
    }
}

impl Warp for Composition {
    fn forward(&self, p: DVec2) -> DVec2 {
        self.warps.iter().fold(p, |p, w| w.forward(p))
    }

    fn inverse(&self, q: DVec2) -> DVec2 {
        self.warps.iter().rev().fold(q, |q, w| w.inverse(q))
    }

    fn support(&self) -> Option<[DVec2; 2]> {
        self.warps.iter().try_fold([DVec2::INFINITY, DVec2::NEG_INFINITY], |[lo, hi], w| {
            w.support().map(|[a, b]| [lo.min(a), hi.max(b)])
        })
    }
}

/// Solves `g(u) = u + a·δ(u) = t` for `u` in [0, 1], where `g` increases from 0 to 1 (the
/// bijectivity condition `1 + a·δ′ ≥ 0`): Newton's method kept inside a shrinking bracket.
pub(crate) fn solve_monotone(t: f64, a: f64, value: impl Fn(f64) -> f64, slope: impl Fn(f64) -> f64) -> f64 {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let mut u = t.clamp(0.0, 1.0);
    for _ in 0..100 {
        let g = u + a * value(u) - t;
        if g.abs() <= 1e-15 {
            return u;
        }
        if g > 0.0 {
            hi = u;
        } else {
            lo = u;
        }
        let d = 1.0 + a * slope(u);
        let next = u - g / d;
        u = if d > 0.0 && next > lo && next < hi { next } else { 0.5 * (lo + hi) };
        if hi - lo <= 1e-16 {
            break;
        }
    }
    u
}
