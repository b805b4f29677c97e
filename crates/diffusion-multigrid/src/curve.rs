//! Feature curves (§3.1): piecewise cubic Bézier splines carrying constraint points, and the
//! interpolation of their attributes along the curve.

use glam::DVec2;
use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize};

use crate::DiffusionError;

/// A condition a constraint value must meet, and what an error says when it does not. The same
/// rules check values as they are deserialized (so a scene error names the field) and in
/// [`FeatureCurve::validate`] (for curves built in code).
struct Rule {
    ok: fn(f64) -> bool,
    reason: &'static str,
}

const FINITE: Rule = Rule { ok: f64::is_finite, reason: "must be finite" };
const NON_NEGATIVE: Rule = Rule { ok: |v| v.is_finite() && v >= 0.0, reason: "must be finite and ≥ 0" };
const UNIT: Rule = Rule { ok: |v| v.is_finite() && (0.0..=1.0).contains(&v), reason: "must lie in [0, 1]" };
const ANGLE: Rule =
    Rule { ok: |v| v.is_finite() && v.abs() < 90.0, reason: "must lie strictly between −90° and 90°" };

impl Rule {
    fn check(&self, value: f64) -> Result<(), &'static str> {
        if (self.ok)(value) { Ok(()) } else { Err(self.reason) }
    }

    fn read<'de, D: Deserializer<'de>>(&self, d: D) -> Result<f64, D::Error> {
        let value = f64::deserialize(d)?;
        self.check(value).map_err(|reason| D::Error::custom(format!("{value} {reason}")))?;
        Ok(value)
    }
}

fn finite<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    FINITE.read(d)
}
fn non_negative<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    NON_NEGATIVE.read(d)
}
fn unit<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    UNIT.read(d)
}
fn angle<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    ANGLE.read(d)
}

/// A strict elevation constraint: height `h` over a band of half-width `r` around the curve.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct Elevation {
    /// Elevation (finite).
    #[serde(deserialize_with = "finite")]
    pub h: f64,
    /// Half-width of the band, world units (≥ 0; default 0: the curve itself).
    #[serde(default, deserialize_with = "non_negative")]
    pub r: f64,
}

/// A slope constraint: beyond the elevation band, the ground falls away at `theta` degrees over
/// `a` world units on the left of the curve (left of its direction of travel) and at `phi`
/// degrees over `b` on the right. Negative angles rise away from the curve (riverbanks, cracks);
/// zero keeps the ground level (hills). The prescribed slope fades to nothing at the band's end.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct Slope {
    /// Extent on the left, world units (≥ 0).
    #[serde(deserialize_with = "non_negative")]
    pub a: f64,
    /// Extent on the right, world units (≥ 0).
    #[serde(deserialize_with = "non_negative")]
    pub b: f64,
    /// Slope angle on the left, degrees in (−90, 90), positive descending away from the curve.
    #[serde(deserialize_with = "angle")]
    pub theta: f64,
    /// Slope angle on the right, degrees in (−90, 90), positive descending away from the curve.
    #[serde(deserialize_with = "angle")]
    pub phi: f64,
}

/// Noise constraints: amplitude (elevation units) and roughness in [0, 1] of the detail noise.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct Noise {
    /// Amplitude A (≥ 0).
    #[serde(deserialize_with = "non_negative")]
    pub amplitude: f64,
    /// Roughness R in [0, 1]: 1 blends all octaves equally, 0 damps the fine ones.
    #[serde(deserialize_with = "unit")]
    pub roughness: f64,
}

/// A constraint point Pᵢ at curve parameter `u` ∈ [0, 1] (normalised arc length), with any subset
/// of elevation, slope and noise constraints.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct Constraint {
    /// Position along the curve, in [0, 1]: 0 at its start, 1 at its end (by arc length).
    #[serde(deserialize_with = "unit")]
    pub u: f64,
    /// Elevation (h, r).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elevation: Option<Elevation>,
    /// Slope (a, b, θ, φ).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slope: Option<Slope>,
    /// Noise (A, R).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noise: Option<Noise>,
}

impl Constraint {
    /// The first value breaking its rule: `(group, field, value, reason)`, the group being the
    /// JSON object holding the field (`""`, `"elevation"`, `"slope"` or `"noise"`).
    fn invalid(&self) -> Option<(&'static str, &'static str, f64, &'static str)> {
        let mut checks: Vec<(&'static str, &'static str, f64, &Rule)> = vec![("", "u", self.u, &UNIT)];
        if let Some(e) = self.elevation {
            checks.extend([("elevation", "h", e.h, &FINITE), ("elevation", "r", e.r, &NON_NEGATIVE)]);
        }
        if let Some(s) = self.slope {
            checks.extend([
                ("slope", "a", s.a, &NON_NEGATIVE),
                ("slope", "b", s.b, &NON_NEGATIVE),
                ("slope", "theta", s.theta, &ANGLE),
                ("slope", "phi", s.phi, &ANGLE),
            ]);
        }
        if let Some(n) = self.noise {
            checks.extend([
                ("noise", "amplitude", n.amplitude, &NON_NEGATIVE),
                ("noise", "roughness", n.roughness, &UNIT),
            ]);
        }
        checks
            .into_iter()
            .find_map(|(group, field, v, rule)| rule.check(v).err().map(|reason| (group, field, v, reason)))
    }
}

/// A feature curve: a piecewise cubic Bézier spline (control polygon of 3k + 1 points, or 2 points
/// for a straight segment) with its constraint points. Deserialization checks every field (see
/// [`FeatureCurve::validate`]), naming the one at fault.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct FeatureCurve {
    /// Control points `[x, y]`: p₀, c₀, c₁, p₁, c₂, c₃, p₂, … (3k + 1 of them, or just two end
    /// points), finite.
    #[serde(deserialize_with = "control_points")]
    #[cfg_attr(feature = "schemars", schemars(with = "Vec<[f64; 2]>"))]
    pub points: Vec<DVec2>,
    /// Constraint points, in any order (at least one).
    #[serde(deserialize_with = "constraints")]
    pub constraints: Vec<Constraint>,
}

/// Whether `n` control points make a control polygon: 2, or 3k + 1 for k ≥ 1 cubic pieces.
fn polygon_size_ok(n: usize) -> bool {
    n == 2 || (n >= 4 && (n - 1).is_multiple_of(3))
}

/// Why a control polygon is unusable, if it is.
fn control_polygon_error(points: &[DVec2]) -> Option<String> {
    let n = points.len();
    if !polygon_size_ok(n) {
        return Some(format!("{n} control points; give 2 (a straight segment) or 3k + 1 (k cubic Bézier pieces)"));
    }
    points.iter().position(|p| !p.is_finite()).map(|k| format!("control point {k} is not finite"))
}

fn control_points<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<DVec2>, D::Error> {
    let points = Vec::<DVec2>::deserialize(d)?;
    match control_polygon_error(&points) {
        Some(message) => Err(D::Error::custom(message)),
        None => Ok(points),
    }
}

fn constraints<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Constraint>, D::Error> {
    let constraints = Vec::<Constraint>::deserialize(d)?;
    if constraints.is_empty() {
        return Err(D::Error::custom("give at least one constraint point"));
    }
    Ok(constraints)
}

/// One sample of a curve's centre line with its interpolated attributes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Station {
    pub(crate) p: DVec2,
    /// Unit normal on the left of the direction of travel.
    pub(crate) left: DVec2,
    pub(crate) elevation: Option<Elevation>,
    pub(crate) slope: Option<Slope>,
    pub(crate) noise: Option<Noise>,
}

impl FeatureCurve {
    /// A curve through `points` as a polyline (each segment a straight cubic piece).
    pub fn polyline(points: &[DVec2], constraints: Vec<Constraint>) -> Self {
        let mut control = Vec::with_capacity(3 * points.len());
        for (k, w) in points.windows(2).enumerate() {
            if k == 0 {
                control.push(w[0]);
            }
            control.extend([w[0].lerp(w[1], 1.0 / 3.0), w[0].lerp(w[1], 2.0 / 3.0), w[1]]);
        }
        if points.len() == 1 {
            control.push(points[0]);
        }
        Self { points: control, constraints }
    }

    /// Checks the control polygon and every constraint value; `index` names the curve in errors.
    ///
    /// # Errors
    /// [`DiffusionError::ControlPoints`], [`DiffusionError::NonFinitePoint`],
    /// [`DiffusionError::NoConstraints`] or [`DiffusionError::InvalidConstraint`].
    pub fn validate(&self, index: usize) -> Result<(), DiffusionError> {
        if !polygon_size_ok(self.points.len()) {
            return Err(DiffusionError::ControlPoints { curve: index, count: self.points.len() });
        }
        if let Some(k) = self.points.iter().position(|p| !p.is_finite()) {
            return Err(DiffusionError::NonFinitePoint { curve: index, index: k });
        }
        if self.constraints.is_empty() {
            return Err(DiffusionError::NoConstraints { curve: index });
        }
        for (k, c) in self.constraints.iter().enumerate() {
            if let Some((_, field, value, reason)) = c.invalid() {
                return Err(DiffusionError::InvalidConstraint { curve: index, constraint: k, field, value, reason });
            }
        }
        Ok(())
    }

    /// Whether any constraint carries an elevation.
    pub fn has_elevation(&self) -> bool {
        self.constraints.iter().any(|c| c.elevation.is_some())
    }

    /// About how many points [`Self::centre_line`] takes at `step` (from the control polygon, which
    /// bounds each piece's length), in f64 so that absurd curves cannot overflow it.
    pub(crate) fn samples_at(&self, step: f64) -> f64 {
        let p = &self.points;
        if p.len() == 2 {
            return (p[0].distance(p[1]) / step).ceil() + 1.0;
        }
        let hull: f64 = p.windows(2).map(|w| w[0].distance(w[1])).sum();
        hull / step + 8.0 * (p.len() / 3) as f64 + 1.0
    }

    /// The centre line as points `step` apart or closer (at least 8 per cubic piece, at most
    /// 2²⁰), as drawn over a preview.
    ///
    /// ```
    /// use glam::DVec2;
    /// use relief_diffusion_multigrid::{Constraint, FeatureCurve};
    ///
    /// let curve = FeatureCurve::polyline(&[DVec2::ZERO, DVec2::new(10.0, 0.0)], vec![Constraint::default()]);
    /// let line = curve.centre_line(1.0);
    /// assert_eq!((line[0], *line.last().unwrap()), (DVec2::ZERO, DVec2::new(10.0, 0.0)));
    /// assert!(line.windows(2).all(|w| w[0].distance(w[1]) <= 1.0 + 1e-9));
    /// ```
    pub fn centre_line(&self, step: f64) -> Vec<DVec2> {
        let p = &self.points;
        if p.len() == 2 {
            let n = ((p[0].distance(p[1]) / step).ceil() as usize).clamp(1, 1 << 20);
            return (0..=n).map(|k| p[0].lerp(p[1], k as f64 / n as f64)).collect();
        }
        let mut out = vec![p[0]];
        for piece in p.windows(4).step_by(3) {
            let [p0, c0, c1, p1] = [piece[0], piece[1], piece[2], piece[3]];
            let hull = p0.distance(c0) + c0.distance(c1) + c1.distance(p1);
            let n = ((hull / step).ceil() as usize).clamp(8, 1 << 20);
            for k in 1..=n {
                let t = k as f64 / n as f64;
                let s = 1.0 - t;
                out.push(p0 * (s * s * s) + c0 * (3.0 * s * s * t) + c1 * (3.0 * s * t * t) + p1 * (t * t * t));
            }
        }
        out.dedup();
        out
    }

    /// Stations along the curve at most `step` apart, with attributes interpolated at each: all
    /// linearly in u, except the elevation h (a cubic Catmull-Rom spline through the constraint
    /// points carrying it, so ridge lines are smooth). Beyond the first/last constraint carrying
    /// an attribute, it stays constant. Expects a validated curve.
    pub(crate) fn stations(&self, step: f64) -> Vec<Station> {
        let line = self.centre_line(step);
        let mut length = vec![0.0; line.len()];
        for k in 1..line.len() {
            length[k] = length[k - 1] + line[k - 1].distance(line[k]);
        }
        let total = length.last().copied().unwrap_or(0.0).max(f64::MIN_POSITIVE);
        let mut cs = self.constraints.clone();
        cs.sort_by(|a, b| a.u.total_cmp(&b.u));
        let track = |get: &dyn Fn(&Constraint) -> Option<Vec<f64>>| -> Vec<(f64, Vec<f64>)> {
            cs.iter().filter_map(|c| get(c).map(|v| (c.u, v))).collect()
        };
        let elev = track(&|c| c.elevation.map(|e| vec![e.h, e.r]));
        let slope = track(&|c| c.slope.map(|s| vec![s.a, s.b, s.theta, s.phi]));
        let noise = track(&|c| c.noise.map(|n| vec![n.amplitude, n.roughness]));
        line.iter()
            .enumerate()
            .map(|(k, &p)| {
                let u = length[k] / total;
                let (prev, next) = (line[k.saturating_sub(1)], line[(k + 1).min(line.len() - 1)]);
                let t = (next - prev).normalize_or_zero();
                let left = DVec2::new(-t.y, t.x);
                Station {
                    p,
                    left,
                    elevation: (!elev.is_empty()).then(|| {
                        let v = linear(&elev, u);
                        Elevation { h: catmull_rom(&elev, u), r: v[1] }
                    }),
                    slope: (!slope.is_empty()).then(|| {
                        let v = linear(&slope, u);
                        Slope { a: v[0], b: v[1], theta: v[2], phi: v[3] }
                    }),
                    noise: (!noise.is_empty()).then(|| {
                        let v = linear(&noise, u);
                        Noise { amplitude: v[0], roughness: v[1] }
                    }),
                }
            })
            .collect()
    }
}

/// Linear interpolation of the attribute vectors at `u`, constant beyond the ends.
fn linear(keys: &[(f64, Vec<f64>)], u: f64) -> Vec<f64> {
    let k = keys.partition_point(|(ku, _)| *ku <= u);
    if k == 0 {
        return keys[0].1.clone();
    }
    if k == keys.len() {
        return keys[k - 1].1.clone();
    }
    let ((u0, a), (u1, b)) = (&keys[k - 1], &keys[k]);
    let t = if u1 > u0 { (u - u0) / (u1 - u0) } else { 0.0 };
    a.iter().zip(b).map(|(x, y)| x + (y - x) * t).collect()
}

/// The first component (h) by a Catmull-Rom cubic through the keys (linear for two keys,
/// constant beyond the ends).
fn catmull_rom(keys: &[(f64, Vec<f64>)], u: f64) -> f64 {
    let n = keys.len();
    let k = keys.partition_point(|(ku, _)| *ku <= u);
    if k == 0 {
        return keys[0].1[0];
    }
    if k == n {
        return keys[n - 1].1[0];
    }
    let (i0, i1) = (k - 1, k);
    let (u0, u1) = (keys[i0].0, keys[i1].0);
    let (h0, h1) = (keys[i0].1[0], keys[i1].1[0]);
    if u1 <= u0 {
        return h0;
    }
    // Tangents (dh/du) from the neighbouring keys; zero-curvature ends.
    let slope = |a: usize, b: usize| (keys[b].1[0] - keys[a].1[0]) / (keys[b].0 - keys[a].0).max(1e-12);
    let m0 = if i0 == 0 { slope(i0, i1) } else { slope(i0 - 1, i1) };
    let m1 = if i1 + 1 == n { slope(i0, i1) } else { slope(i0, i1 + 1) };
    let d = u1 - u0;
    let t = (u - u0) / d;
    let (t2, t3) = (t * t, t * t * t);
    (2.0 * t3 - 3.0 * t2 + 1.0) * h0 + (t3 - 2.0 * t2 + t) * d * m0 + (-2.0 * t3 + 3.0 * t2) * h1 + (t3 - t2) * d * m1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deserialization_checks_every_field_with_the_rules_validate_uses() {
        let good = r#"{"points":[[0.0,0.0],[10.0,0.0]],"constraints":[{"u":0.5,"elevation":{"h":3.0,"r":1.0},"slope":{"a":1.0,"b":2.0,"theta":30.0,"phi":-10.0},"noise":{"amplitude":2.0,"roughness":0.5}}]}"#;
        let curve: FeatureCurve = serde_json::from_str(good).unwrap();
        assert_eq!(serde_json::to_string(&curve).unwrap(), good);
        assert_eq!(curve.validate(0), Ok(()));
        let cases = [
            (r#""u":1.5"#, r#""u":0.5"#, "1.5 must lie in [0, 1]", "u"),
            (r#""r":-1.0"#, r#""r":1.0"#, "-1 must be finite and ≥ 0", "r"),
            (r#""a":-1.0"#, r#""a":1.0"#, "≥ 0", "a"),
            (r#""theta":90.0"#, r#""theta":30.0"#, "90 must lie strictly between", "theta"),
            (r#""phi":-95.0"#, r#""phi":-10.0"#, "between", "phi"),
            (r#""amplitude":-2.0"#, r#""amplitude":2.0"#, "≥ 0", "amplitude"),
            (r#""roughness":2.0"#, r#""roughness":0.5"#, "[0, 1]", "roughness"),
        ];
        for (bad, fine, message, field) in cases {
            let text = good.replace(fine, bad);
            let e = serde_json::from_str::<FeatureCurve>(&text).unwrap_err().to_string();
            assert!(e.contains(message), "{bad}: {e}");
            // The same value built in code fails `validate` on the same field.
            let value: serde_json::Value = serde_json::from_str(&text).unwrap();
            let c = &value["constraints"][0];
            let num = |g: &str, f: &str| if g.is_empty() { c[f].as_f64().unwrap() } else { c[g][f].as_f64().unwrap() };
            let mut built = curve.clone();
            let k = &mut built.constraints[0];
            let (e, s, n) = (k.elevation.as_mut().unwrap(), k.slope.as_mut().unwrap(), k.noise.as_mut().unwrap());
            (e.h, e.r) = (num("elevation", "h"), num("elevation", "r"));
            (s.a, s.b, s.theta, s.phi) =
                (num("slope", "a"), num("slope", "b"), num("slope", "theta"), num("slope", "phi"));
            (n.amplitude, n.roughness) = (num("noise", "amplitude"), num("noise", "roughness"));
            k.u = num("", "u");
            let err = built.validate(2).unwrap_err();
            assert!(
                matches!(err, DiffusionError::InvalidConstraint { field: f, curve: 2, constraint: 0, .. } if f == field),
                "{err:?}"
            );
            assert!(
                err.location().ends_with(field) && err.location().starts_with("curves[2].constraints[0]."),
                "{}",
                err.location()
            );
        }
        for (text, message) in [
            (r#"{"points":[[0,0],[1,0],[2,0]],"constraints":[{"u":0}]}"#, "3 control points"),
            (r#"{"points":[[0,0],[1,0]],"constraints":[]}"#, "at least one constraint"),
        ] {
            let e = serde_json::from_str::<FeatureCurve>(text).unwrap_err().to_string();
            assert!(e.contains(message), "{text}: {e}");
        }
    }

    #[test]
    fn stations_follow_the_curve_and_interpolate() {
        let c = FeatureCurve::polyline(
            &[DVec2::ZERO, DVec2::new(100.0, 0.0)],
            vec![
                Constraint { u: 0.0, elevation: Some(Elevation { h: 0.0, r: 2.0 }), ..Constraint::default() },
                Constraint { u: 1.0, elevation: Some(Elevation { h: 100.0, r: 4.0 }), ..Constraint::default() },
            ],
        );
        c.validate(0).unwrap();
        let s = c.stations(1.0);
        assert_eq!(s.len(), 101);
        let mid = s[50];
        assert!((mid.p.x - 50.0).abs() < 1e-9 && (mid.left - DVec2::Y).length() < 1e-12);
        let e = mid.elevation.unwrap();
        assert!((e.h - 50.0).abs() < 1e-9 && (e.r - 3.0).abs() < 1e-9);
        assert!(mid.slope.is_none() && mid.noise.is_none());
    }

    #[test]
    fn catmull_rom_passes_through_its_keys_smoothly() {
        let keys = vec![(0.0, vec![0.0]), (0.5, vec![10.0]), (1.0, vec![0.0])];
        assert_eq!(catmull_rom(&keys, 0.5), 10.0);
        assert_eq!(catmull_rom(&keys, 0.0), 0.0);
        // A smooth peak: higher than the linear ramp just below the key.
        assert!(catmull_rom(&keys, 0.45) > 9.0);
    }

    #[test]
    fn bad_curves_are_named() {
        let one = FeatureCurve { points: vec![DVec2::ZERO], constraints: vec![Constraint::default()] };
        assert_eq!(one.validate(3), Err(DiffusionError::ControlPoints { curve: 3, count: 1 }));
        let five = FeatureCurve { points: vec![DVec2::ZERO; 5], constraints: vec![Constraint::default()] };
        assert!(matches!(five.validate(0), Err(DiffusionError::ControlPoints { count: 5, .. })));
        let mut c =
            FeatureCurve::polyline(&[DVec2::ZERO, DVec2::X], vec![Constraint { u: 1.5, ..Constraint::default() }]);
        assert!(matches!(c.validate(0), Err(DiffusionError::InvalidConstraint { field: "u", .. })));
        c.constraints[0] = Constraint {
            u: 0.5,
            slope: Some(Slope { a: 1.0, b: 1.0, theta: 90.0, phi: 0.0 }),
            ..Constraint::default()
        };
        assert!(matches!(c.validate(0), Err(DiffusionError::InvalidConstraint { field: "theta", .. })));
        c.constraints[0].slope = Some(Slope { a: -1.0, b: 1.0, theta: 10.0, phi: 0.0 });
        assert!(matches!(c.validate(0), Err(DiffusionError::InvalidConstraint { field: "a", .. })));
        c.constraints[0].slope = None;
        c.constraints[0].elevation = Some(Elevation { h: 1.0, r: -2.0 });
        assert!(matches!(c.validate(0), Err(DiffusionError::InvalidConstraint { field: "r", .. })));
        c.constraints.clear();
        assert_eq!(c.validate(1), Err(DiffusionError::NoConstraints { curve: 1 }));
    }
}
