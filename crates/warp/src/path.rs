use glam::DVec2;

use crate::error::{check_path_strength, check_radius, finite, finite_points};
use crate::warp::solve_monotone;
use crate::{Profile, Warp, WarpError};

/// Parameters of a [`PathWarp`].
#[derive(Debug, Clone)]
pub struct PathOptions {
    /// Radius r of each disc of influence.
    pub radius: f64,
    /// Strength μ in [0, 1]: at 1 the centre of each disc moves exactly one segment along the stroke.
    pub strength: f64,
    /// The displacement profile δ₀ (default `(4x(1−x))²`).
    pub profile: Profile,
    /// A forced segment length ε (at most the bijectivity bound); `None` uses half the bound at
    /// full strength.
    pub segment: Option<f64>,
}

impl PathOptions {
    /// Radius `radius`, strength `strength`, the paper's profile with k = 2, automatic ε.
    ///
    /// # Panics
    /// Never (the k = 2 profile is valid).
    pub fn new(radius: f64, strength: f64) -> Self {
        Self { radius, strength, profile: Profile::power(2).expect("k = 2 is valid"), segment: None }
    }
}

/// Coherent warping along a stroke (§5.2): the stroke is resampled into n segments of length ε, and
/// ω = fₙ ∘ … ∘ f₁ where fᵢ shifts the points of the disc B(vᵢ, r) along the segment direction dᵢ by
/// `μ·δ(u)·|b − a|`, u being the position of p on the chord [a, b] of the disc through p parallel
/// to dᵢ, and `δ = ε·δ₀ / (2r·δ₀(½))` (Appendix B). f₁ applies first, so content at the start of the
/// stroke is dragged along it.
///
/// Bijective by construction: ε never exceeds `2r·δ₀(½) / (μ·(−min δ₀′))`, which keeps each fᵢ
/// monotone along its chords; each fᵢ is inverted exactly by a 1-D monotone solve. By default ε is
/// half that bound at full strength, which bounds how much any disc compresses space (see
/// [`PathOptions::segment`]).
///
/// In JSON (serde), a path warp is what it was built from: `{ "stroke": [[x, y], …], "radius": r,
/// "strength": μ, "exponent": k, "segment": ε }` (strength 1, exponent 2 and an automatic segment
/// by default); deserializing builds and so checks it, naming the offending field. A warp with a
/// [`Profile::custom`] profile has no JSON form. Two warps are equal when they were built from
/// equal parameters.
#[derive(Debug, Clone)]
pub struct PathWarp {
    /// The stroke as given.
    pub(crate) stroke: Vec<DVec2>,
    /// μ as given.
    pub(crate) strength: f64,
    /// The forced ε, if any.
    pub(crate) forced_segment: Option<f64>,
    centers: Vec<DVec2>,
    dirs: Vec<DVec2>,
    radius: f64,
    /// μ·ε/(2r·δ₀(½)): the factor of δ₀ in `u + a·δ₀(u)`.
    amplitude: f64,
    epsilon: f64,
    profile: Profile,
    support: [DVec2; 2],
}

/// Drops repeated consecutive points, checking finiteness; errors if fewer than two remain.
pub(crate) fn clean_stroke(stroke: &[DVec2]) -> Result<(Vec<DVec2>, f64), WarpError> {
    finite_points("stroke point", stroke)?;
    let mut pts: Vec<DVec2> = Vec::with_capacity(stroke.len());
    for &p in stroke {
        if pts.last() != Some(&p) {
            pts.push(p);
        }
    }
    let length: f64 = pts.windows(2).map(|w| w[0].distance(w[1])).sum();
    if pts.len() < 2 || length <= 0.0 {
        return Err(WarpError::DegenerateStroke { distinct: pts.len(), length });
    }
    Ok((pts, length))
}

/// Most discs one path warp may have (2^20: a stroke a million radii long). Each disc is visited
/// for every point it may move, so a stroke near the cap is already minutes of work.
pub const MAX_DISCS: usize = 1 << 20;

impl PathWarp {
    /// A warp along `stroke` (≥ 2 distinct points).
    ///
    /// # Errors
    /// [`WarpError::DegenerateStroke`], [`WarpError::NonFinite`], [`WarpError::InvalidRadius`],
    /// [`WarpError::InvalidStrength`] (μ outside [0, 1]), [`WarpError::SegmentTooLong`] when a forced
    /// ε exceeds the bijectivity limit (named in the message), [`WarpError::TooManyDiscs`] when the
    /// stroke would need more than [`MAX_DISCS`] discs.
    pub fn new(stroke: &[DVec2], options: &PathOptions) -> Result<Self, WarpError> {
        let (pts, length) = clean_stroke(stroke)?;
        let radius = check_radius(options.radius)?;
        let mu = check_path_strength(options.strength)?;
        let profile = options.profile.clone();
        let limit = profile.max_segment(radius, mu);
        let wanted = match options.segment {
            Some(eps) => {
                let eps = finite("segment length", eps)?;
                if !(eps > 0.0 && eps <= limit) {
                    return Err(WarpError::SegmentTooLong { epsilon: eps, limit, radius, mu });
                }
                eps
            }
            // Half the full-strength limit. At the limit itself (the paper's choice) each disc may
            // squeeze the rear of its chords to 1 − μ of their length, nearly nothing at μ = 1, and
            // consecutive discs compound it into tongues thinner than any polyline tolerance; at
            // half, a disc compresses at most 2× and the drag is the same (twice as many discs
            // each moving half as far).
            None => 0.5 * profile.max_segment(radius, 1.0),
        };
        let discs = (length / wanted).ceil().max(1.0);
        // Also catches an infinite length (finite points ±1e308 apart), which would saturate.
        if discs.is_nan() || discs > MAX_DISCS as f64 {
            return Err(WarpError::TooManyDiscs { length, radius, discs, max: MAX_DISCS });
        }
        let n = discs as usize;
        let epsilon = length / n as f64;
        let centers = resample(&pts, n);
        let dirs: Vec<DVec2> = centers.windows(2).map(|w| (w[1] - w[0]).normalize_or_zero()).collect();
        let centers: Vec<DVec2> = centers[..n].to_vec();
        let lo = centers.iter().fold(DVec2::INFINITY, |m, c| m.min(*c)) - DVec2::splat(radius);
        let hi = centers.iter().fold(DVec2::NEG_INFINITY, |m, c| m.max(*c)) + DVec2::splat(radius);
        let amplitude = mu * epsilon / (2.0 * radius * profile.center());
        Ok(Self {
            stroke: stroke.to_vec(),
            strength: mu,
            forced_segment: options.segment,
            centers,
            dirs,
            radius,
            amplitude,
            epsilon,
            profile,
            support: [lo, hi],
        })
    }

    /// The radius r of the discs.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The displacement profile δ₀.
    pub fn profile(&self) -> &Profile {
        &self.profile
    }

    /// The segment length ε used.
    pub fn segment(&self) -> f64 {
        self.epsilon
    }

    /// Number of discs (segments).
    pub fn discs(&self) -> usize {
        self.centers.len()
    }

    /// Disc `i`: centre and direction.
    pub fn disc(&self, i: usize) -> (DVec2, DVec2) {
        (self.centers[i], self.dirs[i])
    }

    /// fᵢ(p).
    pub fn disc_forward(&self, i: usize, p: DVec2) -> DVec2 {
        let (c, d) = (self.centers[i], self.dirs[i]);
        let w = p - c;
        let r2 = self.radius * self.radius;
        if w.length_squared() >= r2 || d == DVec2::ZERO {
            return p;
        }
        let along = w.dot(d);
        let h = (r2 - (w - along * d).length_squared()).max(0.0).sqrt();
        if h <= 0.0 {
            return p;
        }
        let u = ((along + h) / (2.0 * h)).clamp(0.0, 1.0);
        p + (self.amplitude * self.profile.value(u) * 2.0 * h) * d
    }

    /// fᵢ⁻¹(q): the disc maps each chord onto itself, so the inverse is a 1-D solve on the chord.
    pub fn disc_inverse(&self, i: usize, q: DVec2) -> DVec2 {
        let (c, d) = (self.centers[i], self.dirs[i]);
        let w = q - c;
        let r2 = self.radius * self.radius;
        if w.length_squared() >= r2 || d == DVec2::ZERO {
            return q;
        }
        let along = w.dot(d);
        let perp = w - along * d;
        let h = (r2 - perp.length_squared()).max(0.0).sqrt();
        if h <= 0.0 {
            return q;
        }
        let t = ((along + h) / (2.0 * h)).clamp(0.0, 1.0);
        let u = solve_monotone(t, self.amplitude, |x| self.profile.value(x), |x| self.profile.slope(x));
        c + perp + (2.0 * h * u - h) * d
    }

    fn outside(&self, p: DVec2) -> bool {
        p.cmplt(self.support[0]).any() || p.cmpgt(self.support[1]).any()
    }
}

/// `n + 1` points at equal arc-length spacing along the polyline (first and last kept).
fn resample(pts: &[DVec2], n: usize) -> Vec<DVec2> {
    let length: f64 = pts.windows(2).map(|w| w[0].distance(w[1])).sum();
    let step = length / n as f64;
    let mut out = Vec::with_capacity(n + 1);
    out.push(pts[0]);
    let (mut seg, mut into) = (0usize, 0.0f64);
    for _ in 1..n {
        let mut remaining = step;
        loop {
            let (a, b) = (pts[seg], pts[seg + 1]);
            let left = a.distance(b) - into;
            if remaining <= left || seg + 2 == pts.len() {
                into += remaining;
                out.push(a + (b - a) * (into / a.distance(b)).min(1.0));
                break;
            }
            remaining -= left;
            seg += 1;
            into = 0.0;
        }
    }
    out.push(pts[pts.len() - 1]);
    out
}

impl Warp for PathWarp {
    fn forward(&self, p: DVec2) -> DVec2 {
        if self.outside(p) {
            return p;
        }
        (0..self.centers.len()).fold(p, |p, i| self.disc_forward(i, p))
    }

    fn inverse(&self, q: DVec2) -> DVec2 {
        if self.outside(q) {
            return q;
        }
        (0..self.centers.len()).rev().fold(q, |q, i| self.disc_inverse(i, q))
    }

    fn support(&self) -> Option<[DVec2; 2]> {
        Some(self.support)
    }
}
