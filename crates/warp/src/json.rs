//! The JSON forms of [`PathWarp`] and [`SlopeModulation`]: the parameters they are built from.
//!
//! Each field is checked as it is read, so a deserialization error names the offending field
//! (`edits[1].warp.radius` in a scene), and a value that reads is then built, which checks what
//! needs several fields (the segment bound, a curve's reach).

use glam::DVec2;
use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::error::{check_path_strength, check_radius, finite};
use crate::path::clean_stroke;
use crate::slope::{Center, check_strength};
use crate::{PathOptions, PathWarp, Profile, SlopeModulation, WarpError};

/// The JSON form of a [`PathWarp`].
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema), schemars(rename = "PathWarp"))]
struct PathWarpJson {
    /// The stroke `[[x, y], …]` from start to end (at least two distinct points): content at
    /// its start is dragged along it.
    #[serde(deserialize_with = "stroke")]
    #[cfg_attr(feature = "schemars", schemars(with = "Vec<[f64; 2]>"))]
    stroke: Vec<DVec2>,
    /// Radius r of the discs of influence, world units (> 0).
    #[serde(deserialize_with = "radius")]
    radius: f64,
    /// Strength μ in [0, 1] (default 1: each disc centre moves one segment along the stroke).
    #[serde(default = "full_strength", deserialize_with = "path_strength")]
    strength: f64,
    /// Exponent k ≥ 1 of the displacement profile (4x(1 − x))^k (default 2).
    #[serde(default = "default_exponent", deserialize_with = "exponent")]
    exponent: u32,
    /// A forced segment length ε, at most the bijectivity bound of Appendix B (default: half the
    /// bound at full strength).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    segment: Option<f64>,
}

fn full_strength() -> f64 {
    1.0
}

fn default_exponent() -> u32 {
    2
}

fn stroke<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<DVec2>, D::Error> {
    let points = Vec::<DVec2>::deserialize(d)?;
    clean_stroke(&points).map_err(D::Error::custom)?;
    Ok(points)
}

fn radius<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    check_radius(f64::deserialize(d)?).map_err(D::Error::custom)
}

fn path_strength<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    check_path_strength(f64::deserialize(d)?).map_err(D::Error::custom)
}

fn slope_strength<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    check_strength(f64::deserialize(d)?).map_err(D::Error::custom)
}

fn exponent<'de, D: Deserializer<'de>>(d: D) -> Result<u32, D::Error> {
    let k = u32::deserialize(d)?;
    Profile::power(k).map_err(D::Error::custom)?;
    Ok(k)
}

fn point<'de, D: Deserializer<'de>>(d: D) -> Result<Option<DVec2>, D::Error> {
    let p = DVec2::deserialize(d)?;
    finite("centre x", p.x).and_then(|_| finite("centre y", p.y)).map_err(D::Error::custom)?;
    Ok(Some(p))
}

fn curve<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Vec<DVec2>>, D::Error> {
    stroke(d).map(Some)
}

impl TryFrom<PathWarpJson> for PathWarp {
    type Error = WarpError;
    fn try_from(j: PathWarpJson) -> Result<Self, WarpError> {
        let options = PathOptions {
            radius: j.radius,
            strength: j.strength,
            profile: Profile::power(j.exponent)?,
            segment: j.segment,
        };
        PathWarp::new(&j.stroke, &options)
    }
}

impl<'de> Deserialize<'de> for PathWarp {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        PathWarp::try_from(PathWarpJson::deserialize(d)?).map_err(D::Error::custom)
    }
}

impl Serialize for PathWarp {
    /// # Errors
    /// A warp with a [`Profile::custom`] profile has no JSON form.
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let Some(exponent) = self.profile().exponent() else {
            return Err(serde::ser::Error::custom("a path warp with a custom profile has no JSON form"));
        };
        let json = PathWarpJson {
            stroke: self.stroke.clone(),
            radius: self.radius(),
            strength: self.strength,
            exponent,
            segment: self.forced_segment,
        };
        json.serialize(s)
    }
}

impl PartialEq for PathWarp {
    /// Equal parameters: stroke, radius, strength, forced segment, and the same power profile
    /// (custom profiles never compare equal).
    fn eq(&self, other: &Self) -> bool {
        self.stroke == other.stroke
            && self.radius() == other.radius()
            && self.strength == other.strength
            && self.forced_segment == other.forced_segment
            && self.profile().exponent().is_some()
            && self.profile().exponent() == other.profile().exponent()
    }
}

/// The JSON form of a [`SlopeModulation`].
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema), schemars(rename = "SlopeModulation"))]
struct SlopeJson {
    /// The centre point `[x, y]` (give this or `curve`).
    #[serde(default, skip_serializing_if = "Option::is_none", deserialize_with = "point")]
    #[cfg_attr(feature = "schemars", schemars(with = "Option<[f64; 2]>"))]
    point: Option<DVec2>,
    /// The curve `[[x, y], …]` (give this or `point`): the smooth curve through these points,
    /// whose curvature radius and clearance must exceed the radius.
    #[serde(default, skip_serializing_if = "Option::is_none", deserialize_with = "curve")]
    #[cfg_attr(feature = "schemars", schemars(with = "Option<Vec<[f64; 2]>>"))]
    curve: Option<Vec<DVec2>>,
    /// Radius of influence, world units (> 0).
    #[serde(deserialize_with = "radius")]
    radius: f64,
    /// Strength μ in (−1, 3): positive steepens near the centre, negative flattens.
    #[serde(deserialize_with = "slope_strength")]
    strength: f64,
}

impl TryFrom<SlopeJson> for SlopeModulation {
    type Error = WarpError;
    fn try_from(j: SlopeJson) -> Result<Self, WarpError> {
        match (j.point, j.curve) {
            (Some(p), None) => SlopeModulation::point(p, j.radius, j.strength),
            (None, Some(c)) => SlopeModulation::curve(&c, j.radius, j.strength),
            _ => Err(WarpError::AmbiguousCentre),
        }
    }
}

impl<'de> Deserialize<'de> for SlopeModulation {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        SlopeModulation::try_from(SlopeJson::deserialize(d)?).map_err(D::Error::custom)
    }
}

impl Serialize for SlopeModulation {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let (point, curve) = match &self.center {
            Center::Point(p) => (Some(*p), None),
            Center::Curve(points, _) => (None, Some(points.clone())),
        };
        SlopeJson { point, curve, radius: self.radius, strength: self.mu }.serialize(s)
    }
}

impl PartialEq for SlopeModulation {
    /// Equal parameters: centre point or curve points, radius and strength.
    fn eq(&self, other: &Self) -> bool {
        let same_centre = match (&self.center, &other.center) {
            (Center::Point(a), Center::Point(b)) => a == b,
            (Center::Curve(a, _), Center::Curve(b, _)) => a == b,
            _ => false,
        };
        same_centre && self.radius == other.radius && self.mu == other.mu
    }
}

#[cfg(feature = "schemars")]
impl schemars::JsonSchema for PathWarp {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "PathWarp".into()
    }

    fn json_schema(generator: &mut schemars::SchemaGenerator) -> schemars::Schema {
        PathWarpJson::json_schema(generator)
    }
}

#[cfg(feature = "schemars")]
impl schemars::JsonSchema for SlopeModulation {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "SlopeModulation".into()
    }

    fn json_schema(generator: &mut schemars::SchemaGenerator) -> schemars::Schema {
        SlopeJson::json_schema(generator)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_path_warp_round_trips_and_names_its_bad_fields() {
        let text = r#"{"stroke":[[0.0,0.0],[300.0,0.0]],"radius":150.0,"strength":0.5,"exponent":3}"#;
        let warp: PathWarp = serde_json::from_str(text).unwrap();
        assert_eq!(serde_json::to_string(&warp).unwrap(), text);
        let direct = PathWarp::new(
            &[DVec2::ZERO, DVec2::new(300.0, 0.0)],
            &PathOptions { profile: Profile::power(3).unwrap(), ..PathOptions::new(150.0, 0.5) },
        )
        .unwrap();
        assert_eq!(warp, direct);
        let defaults: PathWarp = serde_json::from_str(r#"{"stroke":[[0,0],[1,0]],"radius":1}"#).unwrap();
        assert_eq!((defaults.strength, defaults.profile().exponent()), (1.0, Some(2)));
        for (text, contains) in [
            (r#"{"stroke":[[0,0]],"radius":1}"#, "distinct"),
            (r#"{"stroke":[[0,0],[1,0]],"radius":-3}"#, "radius -3"),
            (r#"{"stroke":[[0,0],[1,0]],"radius":1,"strength":2}"#, "strength"),
            (r#"{"stroke":[[0,0],[1,0]],"radius":1,"exponent":0}"#, "exponent"),
            (r#"{"stroke":[[0,0],[1,0]],"radius":1,"segment":5}"#, "bijectivity"),
        ] {
            let e = serde_json::from_str::<PathWarp>(text).unwrap_err().to_string();
            assert!(e.contains(contains), "{text}: {e}");
        }
        let custom = PathWarp::new(
            &[DVec2::ZERO, DVec2::X],
            &PathOptions { profile: Profile::custom(|x| x * (1.0 - x)).unwrap(), ..PathOptions::new(1.0, 1.0) },
        )
        .unwrap();
        assert!(serde_json::to_string(&custom).is_err());
        assert_ne!(custom, custom.clone(), "custom profiles are never equal");
    }

    #[test]
    fn slope_modulations_are_equal_when_built_from_equal_parameters() {
        let curve = [DVec2::ZERO, DVec2::new(100.0, 0.0), DVec2::new(200.0, 50.0)];
        let point = SlopeModulation::point(DVec2::new(1.0, 2.0), 50.0, 1.5).unwrap();
        let along = SlopeModulation::curve(&curve, 20.0, -0.5).unwrap();
        assert_eq!(point, point.clone());
        assert_eq!(along, SlopeModulation::curve(&curve, 20.0, -0.5).unwrap());
        for other in [
            SlopeModulation::point(DVec2::new(1.0, 3.0), 50.0, 1.5).unwrap(),
            SlopeModulation::point(DVec2::new(1.0, 2.0), 60.0, 1.5).unwrap(),
            SlopeModulation::point(DVec2::new(1.0, 2.0), 50.0, 1.0).unwrap(),
            along.clone(),
        ] {
            assert_ne!(point, other);
        }
        let bent = [DVec2::ZERO, DVec2::new(100.0, 0.0), DVec2::new(200.0, 60.0)];
        assert_ne!(along, SlopeModulation::curve(&bent, 20.0, -0.5).unwrap());
        assert_ne!(along, point);
    }

    #[cfg(feature = "schemars")]
    #[test]
    fn the_json_schemas_describe_the_json_forms() {
        let path = serde_json::to_value(schemars::schema_for!(PathWarp)).unwrap();
        assert_eq!(path["title"], "PathWarp");
        assert_eq!(path["required"], serde_json::json!(["stroke", "radius"]));
        let slope = serde_json::to_value(schemars::schema_for!(SlopeModulation)).unwrap();
        assert_eq!(slope["title"], "SlopeModulation");
        assert!(slope["properties"]["curve"].is_object() && slope["properties"]["point"].is_object(), "{slope}");
    }

    #[test]
    fn a_slope_modulation_round_trips_and_needs_exactly_one_centre() {
        for text in [
            r#"{"point":[1.0,2.0],"radius":50.0,"strength":1.5}"#,
            r#"{"curve":[[0.0,0.0],[100.0,0.0],[200.0,50.0]],"radius":20.0,"strength":-0.5}"#,
        ] {
            let slope: SlopeModulation = serde_json::from_str(text).unwrap();
            assert_eq!(serde_json::to_string(&slope).unwrap(), text);
        }
        for (text, contains) in [
            (r#"{"point":[1,1],"curve":[[0,0],[1,1]],"radius":50,"strength":1}"#, "exactly one"),
            (r#"{"radius":50,"strength":1}"#, "exactly one"),
            (r#"{"point":[1,1],"radius":50,"strength":3}"#, "strength"),
            (r#"{"curve":[[0,0],[10,0],[10,10],[0,10]],"radius":50,"strength":1}"#, "fold"),
        ] {
            let e = serde_json::from_str::<SlopeModulation>(text).unwrap_err().to_string();
            assert!(e.contains(contains), "{text}: {e}");
        }
    }
}
