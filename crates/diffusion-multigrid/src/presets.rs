//! The paper's landforms (§3.2) as ready-made curves: ridge, multiple ridges sharing a peak,
//! riverbed, cliff, hill and crack; [`Preset`] names them in scene files.

use glam::DVec2;
use serde::{Deserialize, Serialize};

use crate::curve::{Constraint, Elevation, FeatureCurve, Noise, Slope};

fn at(u: f64, elevation: Option<Elevation>, slope: Option<Slope>) -> Constraint {
    Constraint { u, elevation, slope, noise: None }
}

/// A ridge line through `points`, from `start_h` through a smooth crest of `peak_h` halfway to
/// `end_h`, with flanks falling at `angle` degrees over `extent` on both sides.
pub fn ridge(points: &[DVec2], start_h: f64, peak_h: f64, end_h: f64, angle: f64, extent: f64) -> FeatureCurve {
    let slope = Some(Slope { a: extent, b: extent, theta: angle, phi: angle });
    FeatureCurve::polyline(
        points,
        vec![
            at(0.0, Some(Elevation { h: start_h, r: 0.0 }), slope),
            at(0.5, Some(Elevation { h: peak_h, r: 0.0 }), slope),
            at(1.0, Some(Elevation { h: end_h, r: 0.0 }), slope),
        ],
    )
}

/// Several ridges leaving a common `peak` of height `peak_h` towards `ends` (where they drop to
/// `foot_h`), each with its own flank `angles` (degrees; reused cyclically) over `extent`.
pub fn multiple_ridges(
    peak: DVec2,
    peak_h: f64,
    ends: &[DVec2],
    foot_h: f64,
    angles: &[f64],
    extent: f64,
) -> Vec<FeatureCurve> {
    ends.iter()
        .enumerate()
        .map(|(k, &end)| {
            let angle = if angles.is_empty() { 30.0 } else { angles[k % angles.len()] };
            let slope = Some(Slope { a: extent, b: extent, theta: angle, phi: angle });
            FeatureCurve::polyline(
                &[peak, end],
                vec![
                    at(0.0, Some(Elevation { h: peak_h, r: 0.0 }), slope),
                    at(1.0, Some(Elevation { h: foot_h, r: 0.0 }), slope),
                ],
            )
        })
        .collect()
}

/// A riverbed: a bed of half-width `width / 2` falling from `start_h` to `end_h`, banks rising
/// gently (`bank_angle` degrees) over `bank`.
pub fn riverbed(points: &[DVec2], start_h: f64, end_h: f64, width: f64, bank_angle: f64, bank: f64) -> FeatureCurve {
    let slope = Some(Slope { a: bank, b: bank, theta: -bank_angle.abs(), phi: -bank_angle.abs() });
    FeatureCurve::polyline(
        points,
        vec![
            at(0.0, Some(Elevation { h: start_h, r: width / 2.0 }), slope),
            at(1.0, Some(Elevation { h: end_h, r: width / 2.0 }), slope),
        ],
    )
}

/// A cliff along `points` at height `h`: the left side drops at `drop_angle` over `extent`, the
/// right side stays level.
pub fn cliff(points: &[DVec2], h: f64, drop_angle: f64, extent: f64) -> FeatureCurve {
    let slope = Some(Slope { a: extent, b: extent, theta: drop_angle, phi: 0.0 });
    FeatureCurve::polyline(points, vec![at(0.0, Some(Elevation { h, r: 0.0 }), slope), at(1.0, None, slope)])
}

/// A hill: a short curve at height `h` with horizontal slope constraints over `extent` on both
/// sides, so the ground next to it stays level before falling away.
pub fn hill(points: &[DVec2], h: f64, extent: f64) -> FeatureCurve {
    let slope = Some(Slope { a: extent, b: extent, theta: 0.0, phi: 0.0 });
    FeatureCurve::polyline(points, vec![at(0.0, Some(Elevation { h, r: 0.0 }), slope), at(1.0, None, slope)])
}

/// A crack: no elevation of its own, the ground rising at `angle` degrees on both sides over
/// `extent`.
pub fn crack(points: &[DVec2], angle: f64, extent: f64) -> FeatureCurve {
    let slope = Some(Slope { a: extent, b: extent, theta: -angle.abs(), phi: -angle.abs() });
    FeatureCurve::polyline(points, vec![at(0.0, None, slope), at(1.0, None, slope)])
}

/// Adds a noise constraint (amplitude, roughness) at both ends of `curve`.
#[must_use]
pub fn with_noise(mut curve: FeatureCurve, amplitude: f64, roughness: f64) -> FeatureCurve {
    let noise = Some(Noise { amplitude, roughness });
    curve.constraints.push(Constraint { u: 0.0, noise, ..Constraint::default() });
    curve.constraints.push(Constraint { u: 1.0, noise, ..Constraint::default() });
    curve
}

/// A landform by name, as scene files write it (`{"ridge": {"points": [[0, 0], [4000, 0]],
/// "start_h": 300, "peak_h": 1200, "end_h": 400, "angle": 30, "extent": 800}}`): each variant is
/// the function of the same name with its arguments as fields, plus an optional detail `noise`
/// along the curves ([`with_noise`]). [`Preset::curves`] expands it; the curves it gives are
/// validated like any other ([`FeatureCurve::validate`]).
///
/// ```
/// use relief_diffusion_multigrid::presets::Preset;
///
/// let json = r#"{"hill": {"points": [[0, 0], [200, 0]], "h": 150, "extent": 100}}"#;
/// let hill: Preset = serde_json::from_str(json)?;
/// let curves = hill.curves();
/// assert_eq!(curves.len(), 1);
/// assert!(curves[0].validate(0).is_ok());
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub enum Preset {
    /// [`ridge`]: a crest from `start_h` through `peak_h` (halfway) to `end_h`, flanks at `angle`
    /// degrees over `extent` on both sides.
    Ridge {
        /// The ridge line, `[x, y]` points.
        #[cfg_attr(feature = "schemars", schemars(with = "Vec<[f64; 2]>"))]
        points: Vec<DVec2>,
        /// Height at the first point.
        start_h: f64,
        /// Height halfway along.
        peak_h: f64,
        /// Height at the last point.
        end_h: f64,
        /// Flank angle, degrees.
        angle: f64,
        /// Flank width, world units.
        extent: f64,
        /// Detail noise along the ridge.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        noise: Option<Noise>,
    },
    /// [`multiple_ridges`]: ridges from a common `peak` down to each of `ends`.
    MultipleRidges {
        /// The shared summit `[x, y]`.
        #[cfg_attr(feature = "schemars", schemars(with = "[f64; 2]"))]
        peak: DVec2,
        /// Height of the summit.
        peak_h: f64,
        /// Where each ridge ends, `[x, y]`.
        #[cfg_attr(feature = "schemars", schemars(with = "Vec<[f64; 2]>"))]
        ends: Vec<DVec2>,
        /// Height at the ends.
        foot_h: f64,
        /// Flank angle of each ridge, degrees (reused cyclically; empty: 30°).
        angles: Vec<f64>,
        /// Flank width, world units.
        extent: f64,
        /// Detail noise along every ridge.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        noise: Option<Noise>,
    },
    /// [`riverbed`]: a bed `width` wide falling from `start_h` to `end_h`, banks rising at
    /// `bank_angle` degrees over `bank`.
    Riverbed {
        /// The river's course, `[x, y]` points.
        #[cfg_attr(feature = "schemars", schemars(with = "Vec<[f64; 2]>"))]
        points: Vec<DVec2>,
        /// Bed height at the first point.
        start_h: f64,
        /// Bed height at the last point.
        end_h: f64,
        /// Width of the bed, world units.
        width: f64,
        /// Bank angle, degrees.
        bank_angle: f64,
        /// Bank width, world units.
        bank: f64,
        /// Detail noise along the river.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        noise: Option<Noise>,
    },
    /// [`cliff`]: at height `h`, its left side dropping at `drop_angle` degrees over `extent`.
    Cliff {
        /// The cliff's edge, `[x, y]` points.
        #[cfg_attr(feature = "schemars", schemars(with = "Vec<[f64; 2]>"))]
        points: Vec<DVec2>,
        /// Height of the edge.
        h: f64,
        /// Drop angle, degrees.
        drop_angle: f64,
        /// Width of the drop, world units.
        extent: f64,
        /// Detail noise along the edge.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        noise: Option<Noise>,
    },
    /// [`hill`]: at height `h`, level ground over `extent` on both sides.
    Hill {
        /// The hill's crest, `[x, y]` points.
        #[cfg_attr(feature = "schemars", schemars(with = "Vec<[f64; 2]>"))]
        points: Vec<DVec2>,
        /// Height of the crest.
        h: f64,
        /// Width of the level ground, world units.
        extent: f64,
        /// Detail noise along the crest.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        noise: Option<Noise>,
    },
    /// [`crack`]: no height of its own, the ground rising at `angle` degrees on both sides over
    /// `extent`.
    Crack {
        /// The crack's course, `[x, y]` points.
        #[cfg_attr(feature = "schemars", schemars(with = "Vec<[f64; 2]>"))]
        points: Vec<DVec2>,
        /// Wall angle, degrees.
        angle: f64,
        /// Wall width, world units.
        extent: f64,
        /// Detail noise along the crack.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        noise: Option<Noise>,
    },
}

impl Preset {
    /// The curves of this landform.
    pub fn curves(&self) -> Vec<FeatureCurve> {
        let (curves, noise) = match self {
            Self::Ridge { points, start_h, peak_h, end_h, angle, extent, noise } => {
                (vec![ridge(points, *start_h, *peak_h, *end_h, *angle, *extent)], noise)
            }
            Self::MultipleRidges { peak, peak_h, ends, foot_h, angles, extent, noise } => {
                (multiple_ridges(*peak, *peak_h, ends, *foot_h, angles, *extent), noise)
            }
            Self::Riverbed { points, start_h, end_h, width, bank_angle, bank, noise } => {
                (vec![riverbed(points, *start_h, *end_h, *width, *bank_angle, *bank)], noise)
            }
            Self::Cliff { points, h, drop_angle, extent, noise } => {
                (vec![cliff(points, *h, *drop_angle, *extent)], noise)
            }
            Self::Hill { points, h, extent, noise } => (vec![hill(points, *h, *extent)], noise),
            Self::Crack { points, angle, extent, noise } => (vec![crack(points, *angle, *extent)], noise),
        };
        match noise {
            Some(n) => curves.into_iter().map(|c| with_noise(c, n.amplitude, n.roughness)).collect(),
            None => curves,
        }
    }
}
