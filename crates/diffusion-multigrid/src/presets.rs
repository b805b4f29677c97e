//! The paper's landforms (§3.2) as ready-made curves: ridge, multiple ridges sharing a peak,
//! riverbed, cliff, hill and crack.

use glam::DVec2;

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
