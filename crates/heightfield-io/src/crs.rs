//! Coordinate reference systems across formats: EPSG codes completed with their WKT (from the
//! `crs-definitions` tables, generated from the EPSG registry, rather than tables of our own),
//! `.prj` files read and written, and the units a file's CRS implies.

use relief_heightfield::{Crs, GridSpec, Units};

use crate::{IoError, IoErrorKind};

/// `crs` with its WKT filled in from the EPSG tables when it was a bare code the tables know, or
/// its EPSG code when it was a common geographic CRS written without one ([`Crs::identified`]:
/// ESRI's `GCS_WGS_1984` is EPSG:4326, as GDAL reads it).
pub(crate) fn complete(crs: Crs) -> Crs {
    match (crs.wkt(), crs.epsg()) {
        (None, Some(code)) => match epsg_wkt(code) {
            Some(wkt) => crs.with_wkt(wkt),
            None => crs,
        },
        (Some(_), None) => crs.identified(),
        _ => crs,
    }
}

/// The EPSG registry's WKT 1 for `code`, if the tables hold it.
pub(crate) fn epsg_wkt(code: u32) -> Option<&'static str> {
    u16::try_from(code).ok().and_then(crs_definitions::from_code).map(|d| d.wkt)
}

/// The CRS with EPSG code `code`, its WKT filled in when known.
///
/// # Errors
/// As [`Crs::from_epsg`].
pub(crate) fn from_epsg(code: u32) -> Result<Crs, relief_heightfield::HeightfieldError> {
    Crs::from_epsg(code).map(complete)
}

/// What a `.prj` says: the CRS (none for a local `LOCAL_CS`, which places nothing on Earth, or
/// for the old ESRI keyword format) and the units of its coordinates.
pub(crate) fn read_prj(prj: &str) -> (Option<Crs>, Units) {
    match Crs::from_wkt(prj) {
        Ok(crs) => {
            let units = crs.units().unwrap_or_else(|| keyword_units(prj));
            ((!crs.is_local()).then(|| complete(crs)), units)
        }
        Err(_) => (None, keyword_units(prj)),
    }
}

/// Units from keywords alone: degrees for a geographic CRS (WKT `GEOGCS`/`GEOGCRS` without a
/// projection, or the old ESRI `Projection GEOGRAPHIC`), metres otherwise.
fn keyword_units(prj: &str) -> Units {
    let up = prj.to_ascii_uppercase();
    let projected = up.contains("PROJCS") || up.contains("PROJCRS") || up.contains("LOCAL_CS");
    let geographic = up.contains("GEOGCS") || up.contains("GEOGCRS") || up.contains("GEOGRAPHIC");
    if geographic && !projected { Units::Degrees } else { Units::Metres }
}

/// The `.prj` text for a grid in `units` labelled `crs`: the CRS's WKT; without one, WGS 84 for
/// degrees and a local CRS in the grid's unit otherwise (GDAL reads both).
pub(crate) fn prj_text(crs: Option<&Crs>, units: Units) -> String {
    if let Some(wkt) =
        crs.and_then(|c| c.wkt().map(str::to_owned).or_else(|| complete(c.clone()).wkt().map(str::to_owned)))
    {
        return format!("{wkt}\n");
    }
    match units {
        Units::Degrees => epsg_wkt(4326).map_or_else(String::new, |w| format!("{w}\n")),
        planar => {
            let (name, metres) = match planar {
                Units::Feet => ("foot", "0.3048"),
                Units::UsSurveyFeet => ("US survey foot", "0.304800609601219"),
                _ => ("metre", "1"),
            };
            format!("LOCAL_CS[\"relief planar {}\",LOCAL_DATUM[\"none\",0],UNIT[\"{name}\",{metres}]]\n", planar.name())
        }
    }
}

/// Whether a grid read without any CRS (an ASCII grid with no `.prj`) looks geographic: its
/// extent lies within ±180° × ±90° and its cells are finer than one arc-minute, which no metric
/// DEM has (1/60 of a metre cells would not fit a ±180 m extent with any useful size).
pub(crate) fn looks_geographic(grid: &GridSpec) -> bool {
    let e = grid.extent();
    let c = grid.cell_size();
    let inside =
        e.min.x >= -180.0 - 1e-9 && e.max.x <= 180.0 + 1e-9 && e.min.y >= -90.0 - 1e-9 && e.max.y <= 90.0 + 1e-9;
    let fine = c.x < 1.0 / 60.0 + 1e-12 && c.y < 1.0 / 60.0 + 1e-12;
    inside && fine
}

/// The CRS a user names: `EPSG:n` (any case; `urn:ogc:def:crs:EPSG::n` too), a WKT text, or the
/// path of a `.prj`/`.wkt` file holding one. A code the EPSG tables know gets its WKT.
///
/// ```
/// let utm = relief_heightfield_io::parse_crs("EPSG:32617")?;
/// assert_eq!(utm.name(), "WGS 84 / UTM zone 17N");
/// assert_eq!(utm.units(), Some(relief_heightfield::Units::Metres));
/// assert!(relief_heightfield_io::parse_crs("UTM 17").is_err());
/// # Ok::<(), relief_heightfield_io::IoError>(())
/// ```
///
/// # Errors
/// [`IoErrorKind::InvalidMetadata`] when `spec` is none of these (the error's path is the spec),
/// or the file's error when it cannot be read.
pub fn parse_crs(spec: &str) -> Result<Crs, IoError> {
    let spec = spec.trim();
    let invalid = |reason: String| IoError::new(spec, IoErrorKind::InvalidMetadata(reason));
    let lower = spec.to_ascii_lowercase();
    let code = lower.strip_prefix("epsg:").or_else(|| lower.strip_prefix("urn:ogc:def:crs:epsg::"));
    if let Some(code) = code {
        let code: u32 = code.trim().parse().map_err(|_| invalid(format!("{spec:?}: give EPSG:n with a number n")))?;
        return from_epsg(code).map_err(|e| invalid(e.to_string()));
    }
    let looks_wkt = spec.contains('[');
    let text = if looks_wkt {
        spec.to_owned()
    } else {
        let path = std::path::Path::new(spec);
        if !path.is_file() {
            return Err(invalid(format!("{spec:?} is neither EPSG:n, WKT nor a .prj file")));
        }
        let bytes = crate::read_capped(path, 1 << 16).map_err(|e| invalid(e.to_string()))?;
        String::from_utf8(bytes).map_err(|_| invalid("the CRS file is not UTF-8 text".to_owned()))?
    };
    Crs::from_wkt(&text).map(complete).map_err(|e| invalid(e.to_string()))
}
