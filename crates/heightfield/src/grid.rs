use glam::DVec2;
use serde::{Deserialize, Serialize};

use crate::HeightfieldError;

/// The largest number of samples a grid may hold: flat indices always fit a `u32`, which downstream
/// crates use for compact per-cell links (flow receivers, union-find parents).
pub const MAX_SAMPLES: u64 = u32::MAX as u64;

/// What the grid's world coordinates measure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub enum Units {
    /// Planar coordinates in metres (x east, y north).
    #[default]
    Metres,
    /// Geographic coordinates in degrees: x is longitude, y is latitude (WGS84), as in SRTM tiles.
    /// Distances, slopes and gradients convert to metres with the ellipsoid's radii of curvature at
    /// each row's latitude ([`metres_per_degree`]).
    Degrees,
    /// Planar coordinates in international feet (0.3048 m), as in many US state-plane systems.
    /// Distances, slopes and gradients convert to metres.
    Feet,
    /// Planar coordinates in US survey feet (1200/3937 m), the unit of most US state-plane CRSs
    /// in their `ftUS` forms.
    #[serde(rename = "us_survey_feet")]
    UsSurveyFeet,
}

impl Units {
    /// Metres per unit of a planar unit, `None` for [`Units::Degrees`] (whose metres depend on the
    /// latitude: [`metres_per_degree`]).
    pub fn metres(self) -> Option<f64> {
        match self {
            Units::Metres => Some(1.0),
            Units::Feet => Some(0.3048),
            Units::UsSurveyFeet => Some(1200.0 / 3937.0),
            Units::Degrees => None,
        }
    }

    /// The short symbol printed after coordinates: `m`, `°`, `ft`, `ftUS`.
    pub fn symbol(self) -> &'static str {
        match self {
            Units::Metres => "m",
            Units::Degrees => "°",
            Units::Feet => "ft",
            Units::UsSurveyFeet => "ftUS",
        }
    }

    /// The name used in JSON and on the command line: `metres`, `degrees`, `feet`, `us_survey_feet`.
    pub fn name(self) -> &'static str {
        match self {
            Units::Metres => "metres",
            Units::Degrees => "degrees",
            Units::Feet => "feet",
            Units::UsSurveyFeet => "us_survey_feet",
        }
    }
}

impl std::str::FromStr for Units {
    type Err = HeightfieldError;

    /// Parses [`Units::name`], plus `m`, `metre(s)`, `meter(s)`, `deg`, `degree`, `ft`, `foot`,
    /// `ftUS` and `us-ft`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "m" | "metre" | "metres" | "meter" | "meters" => Ok(Units::Metres),
            "deg" | "degree" | "degrees" | "°" => Ok(Units::Degrees),
            "ft" | "foot" | "feet" => Ok(Units::Feet),
            "ftus" | "us-ft" | "us_survey_feet" | "us-survey-feet" | "us_survey_foot" => Ok(Units::UsSurveyFeet),
            _ => Err(HeightfieldError::UnknownUnits { name: s.to_owned() }),
        }
    }
}

/// An axis-aligned rectangle in world coordinates. In JSON, `{ "min": [x, y], "max": [x, y] }`;
/// deserialization checks that both corners are finite and `min < max` along both axes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, try_from = "ExtentRepr")]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct Extent {
    /// Minimum corner (west, south).
    #[cfg_attr(feature = "schemars", schemars(with = "[f64; 2]"))]
    pub min: DVec2,
    /// Maximum corner (east, north).
    #[cfg_attr(feature = "schemars", schemars(with = "[f64; 2]"))]
    pub max: DVec2,
}

/// The unchecked JSON form of an [`Extent`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema), schemars(rename = "Extent"))]
struct ExtentRepr {
    /// Minimum corner `[x, y]` (west, south).
    #[cfg_attr(feature = "schemars", schemars(with = "[f64; 2]"))]
    min: DVec2,
    /// Maximum corner `[x, y]` (east, north), above `min` along both axes.
    #[cfg_attr(feature = "schemars", schemars(with = "[f64; 2]"))]
    max: DVec2,
}

impl TryFrom<ExtentRepr> for Extent {
    type Error = HeightfieldError;
    fn try_from(r: ExtentRepr) -> Result<Self, HeightfieldError> {
        Self::checked(r.min, r.max)
    }
}

impl Extent {
    /// The rectangle spanned by two corners.
    pub fn new(min: DVec2, max: DVec2) -> Self {
        Self { min, max }
    }

    /// The rectangle spanned by two corners, checked: both finite, `min < max` along both axes.
    ///
    /// # Errors
    /// [`HeightfieldError::InvalidExtent`] otherwise.
    pub fn checked(min: DVec2, max: DVec2) -> Result<Self, HeightfieldError> {
        if min.is_finite() && max.is_finite() && min.cmplt(max).all() {
            Ok(Self { min, max })
        } else {
            Err(HeightfieldError::InvalidExtent { min_x: min.x, min_y: min.y, max_x: max.x, max_y: max.y })
        }
    }

    /// `max - min`.
    pub fn size(&self) -> DVec2 {
        self.max - self.min
    }

    /// Midpoint of the rectangle.
    pub fn center(&self) -> DVec2 {
        0.5 * (self.min + self.max)
    }

    /// Whether `p` lies inside or on the border.
    pub fn contains(&self, p: DVec2) -> bool {
        p.x >= self.min.x && p.x <= self.max.x && p.y >= self.min.y && p.y <= self.max.y
    }
}

/// Metres per degree of longitude (`x`) and of latitude (`y`) at geodetic latitude `lat_deg` on the
/// WGS84 ellipsoid.
///
/// Uses the exact radii of curvature: the meridional radius `M = a(1−e²)/(1−e²sin²φ)^{3/2}` for
/// latitude and the prime-vertical radius `N = a/√(1−e²sin²φ)` times `cos φ` for longitude,
/// each multiplied by π/180. At the equator this gives 111 319.5 m (lon) and 110 574.3 m (lat).
pub fn metres_per_degree(lat_deg: f64) -> DVec2 {
    const A: f64 = 6_378_137.0;
    const F: f64 = 1.0 / 298.257_223_563;
    let e2 = F * (2.0 - F);
    let phi = lat_deg.to_radians();
    let s = phi.sin();
    let w = (1.0 - e2 * s * s).sqrt();
    let n = A / w;
    let m = A * (1.0 - e2) / (w * w * w);
    let k = std::f64::consts::PI / 180.0;
    // cos(±90°) evaluates to ~6e-17, not 0: the pole rows get exactly zero width.
    let cos = if lat_deg.abs() >= 90.0 { 0.0 } else { phi.cos() };
    DVec2::new(k * n * cos, k * m)
}

/// Geometry of a node-registered grid: `nx × ny` samples, sample `(i, j)` at
/// `origin + (i·cell_size.x, j·cell_size.y)`.
///
/// Row `j = 0` is the southern (minimum-y) edge and `i = 0` the western edge; samples are stored
/// row-major (`index = j·nx + i`). File formats that store north-up rasters flip rows on read/write.
/// The grid is validated at construction: dimensions non-zero and at most [`MAX_SAMPLES`] samples,
/// cell sizes finite and positive, extent finite, latitudes within ±90° for geographic grids.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "GridSpecRepr", into = "GridSpecRepr")]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct GridSpec {
    nx: usize,
    ny: usize,
    origin: DVec2,
    cell_size: DVec2,
    units: Units,
}

/// The JSON form of a [`GridSpec`].
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema), schemars(rename = "GridSpec"))]
struct GridSpecRepr {
    /// Samples along x.
    nx: usize,
    /// Samples along y.
    ny: usize,
    /// Position `[x, y]` of sample (0, 0), the south-west corner.
    #[cfg_attr(feature = "schemars", schemars(with = "[f64; 2]"))]
    origin: DVec2,
    /// Spacing `[dx, dy]` of the samples.
    #[cfg_attr(feature = "schemars", schemars(with = "[f64; 2]"))]
    cell_size: DVec2,
    /// Units of the coordinates (default metres).
    #[serde(default)]
    units: Units,
}

impl TryFrom<GridSpecRepr> for GridSpec {
    type Error = HeightfieldError;
    fn try_from(r: GridSpecRepr) -> Result<Self, Self::Error> {
        GridSpec::new(r.nx, r.ny, r.origin, r.cell_size)?.with_units(r.units)
    }
}

impl From<GridSpec> for GridSpecRepr {
    fn from(g: GridSpec) -> Self {
        Self { nx: g.nx, ny: g.ny, origin: g.origin, cell_size: g.cell_size, units: g.units }
    }
}

impl GridSpec {
    /// A planar grid (metres) of `nx × ny` samples with sample `(0, 0)` at `origin` and spacing `cell_size`.
    ///
    /// # Errors
    /// [`HeightfieldError::EmptyGrid`], [`HeightfieldError::TooManySamples`],
    /// [`HeightfieldError::InvalidCellSize`] or [`HeightfieldError::InvalidOrigin`].
    pub fn new(nx: usize, ny: usize, origin: DVec2, cell_size: DVec2) -> Result<Self, HeightfieldError> {
        if nx == 0 || ny == 0 {
            return Err(HeightfieldError::EmptyGrid { nx, ny });
        }
        let too_many = HeightfieldError::TooManySamples { nx, ny, max: MAX_SAMPLES };
        let n = nx.checked_mul(ny).ok_or(too_many.clone())?;
        if n as u64 > MAX_SAMPLES {
            return Err(too_many);
        }
        // Normal, not merely positive: a subnormal spacing (an ASCII grid's `cellsize 1e-320`)
        // loses its precision and its reciprocal is infinite.
        if !(cell_size.x.is_normal() && cell_size.y.is_normal() && cell_size.x > 0.0 && cell_size.y > 0.0) {
            return Err(HeightfieldError::InvalidCellSize { x: cell_size.x, y: cell_size.y });
        }
        let far = origin + DVec2::new((nx - 1) as f64, (ny - 1) as f64) * cell_size;
        if !(origin.is_finite() && far.is_finite()) {
            return Err(HeightfieldError::InvalidOrigin { x: origin.x, y: origin.y });
        }
        // Every sample its own coordinates: a spacing below the origin's rounding step would put
        // neighbours at one point.
        let apart = |o: f64, f: f64, c: f64, n: usize| n == 1 || (o + c > o && f - c < f);
        if !(apart(origin.x, far.x, cell_size.x, nx) && apart(origin.y, far.y, cell_size.y, ny)) {
            return Err(HeightfieldError::InvalidCellSize { x: cell_size.x, y: cell_size.y });
        }
        Ok(Self { nx, ny, origin, cell_size, units: Units::Metres })
    }

    /// A geographic grid: `origin` is (longitude, latitude) of sample `(0, 0)` in degrees and
    /// `cell_size` the spacing in degrees.
    ///
    /// # Errors
    /// As [`GridSpec::new`], plus [`HeightfieldError::LatitudeOutOfRange`].
    pub fn geographic(nx: usize, ny: usize, origin: DVec2, cell_size_deg: DVec2) -> Result<Self, HeightfieldError> {
        Self::new(nx, ny, origin, cell_size_deg)?.with_units(Units::Degrees)
    }

    /// A grid whose first and last samples sit exactly on the corners of `extent`.
    ///
    /// An axis with a single sample must have zero width in `extent`; its cell size is then taken
    /// from the other axis (or 1 if both axes hold one sample).
    ///
    /// # Errors
    /// [`HeightfieldError::InvalidExtent`] when the extent is inverted, not finite, or has non-zero
    /// width along a single-sample axis; otherwise as [`GridSpec::new`].
    pub fn from_extent(nx: usize, ny: usize, extent: Extent) -> Result<Self, HeightfieldError> {
        if nx == 0 || ny == 0 {
            return Err(HeightfieldError::EmptyGrid { nx, ny });
        }
        let size = extent.size();
        let bad = || HeightfieldError::InvalidExtent {
            min_x: extent.min.x,
            min_y: extent.min.y,
            max_x: extent.max.x,
            max_y: extent.max.y,
        };
        let axis = |n: usize, w: f64| -> Result<Option<f64>, HeightfieldError> {
            if !w.is_finite() {
                return Err(bad());
            }
            match n {
                1 if w == 0.0 => Ok(None),
                1 => Err(bad()),
                _ if w > 0.0 => Ok(Some(w / (n - 1) as f64)),
                _ => Err(bad()),
            }
        };
        let (cx, cy) = (axis(nx, size.x)?, axis(ny, size.y)?);
        let cell = match (cx, cy) {
            (Some(x), Some(y)) => DVec2::new(x, y),
            (Some(x), None) => DVec2::splat(x),
            (None, Some(y)) => DVec2::splat(y),
            (None, None) => DVec2::ONE,
        };
        Self::new(nx, ny, extent.min, cell)
    }

    /// The same grid with its coordinates reinterpreted in `units`.
    ///
    /// # Errors
    /// [`HeightfieldError::LatitudeOutOfRange`] for a geographic grid reaching past a pole.
    pub fn with_units(mut self, units: Units) -> Result<Self, HeightfieldError> {
        if units == Units::Degrees {
            let (lo, hi) = (self.origin.y, self.extent().max.y);
            // A tiny tolerance lets tiles whose last row is computed as 90.000000000001 through.
            if lo < -90.0 - 1e-9 || hi > 90.0 + 1e-9 {
                return Err(HeightfieldError::LatitudeOutOfRange { min_lat: lo, max_lat: hi });
            }
        }
        self.units = units;
        Ok(self)
    }

    /// The same extent sampled with `nx × ny` samples.
    ///
    /// # Errors
    /// As [`GridSpec::from_extent`].
    pub fn resized(&self, nx: usize, ny: usize) -> Result<Self, HeightfieldError> {
        let ext = self.extent();
        let ext = Extent::new(
            ext.min,
            DVec2::new(if nx == 1 { ext.min.x } else { ext.max.x }, if ny == 1 { ext.min.y } else { ext.max.y }),
        );
        Self::from_extent(nx, ny, ext)?.with_units(self.units)
    }

    /// Samples along x (columns).
    pub fn nx(&self) -> usize {
        self.nx
    }

    /// Samples along y (rows).
    pub fn ny(&self) -> usize {
        self.ny
    }

    /// Total number of samples, `nx · ny`.
    pub fn len(&self) -> usize {
        self.nx * self.ny
    }

    /// Always `false`: a grid holds at least one sample. Present for API symmetry with `len`.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// World position of sample `(0, 0)`.
    pub fn origin(&self) -> DVec2 {
        self.origin
    }

    /// Spacing between samples in world units (metres or degrees, see [`GridSpec::units`]).
    pub fn cell_size(&self) -> DVec2 {
        self.cell_size
    }

    /// What the world coordinates measure.
    pub fn units(&self) -> Units {
        self.units
    }

    /// Rectangle spanned by the sample positions (first to last sample on each axis).
    pub fn extent(&self) -> Extent {
        Extent::new(self.origin, self.position(self.nx - 1, self.ny - 1))
    }

    /// Flat index of sample `(i, j)`: `j·nx + i`.
    #[inline]
    pub fn index(&self, i: usize, j: usize) -> usize {
        debug_assert!(i < self.nx && j < self.ny, "sample ({i}, {j}) outside {}x{}", self.nx, self.ny);
        j * self.nx + i
    }

    /// Column and row of a flat index.
    #[inline]
    pub fn coords(&self, index: usize) -> (usize, usize) {
        (index % self.nx, index / self.nx)
    }

    /// World position of sample `(i, j)`.
    #[inline]
    pub fn position(&self, i: usize, j: usize) -> DVec2 {
        self.origin + DVec2::new(i as f64, j as f64) * self.cell_size
    }

    /// Continuous grid coordinates of world point `p`: sample `(i, j)` maps to `(i, j)`.
    #[inline]
    pub fn grid_coords(&self, p: DVec2) -> DVec2 {
        (p - self.origin) / self.cell_size
    }

    /// The sample nearest to `p`, or `None` when `p` lies farther than half a cell outside the grid.
    pub fn nearest_sample(&self, p: DVec2) -> Option<(usize, usize)> {
        let g = self.grid_coords(p).round();
        let inside = g.x >= 0.0 && g.y >= 0.0 && g.x <= (self.nx - 1) as f64 && g.y <= (self.ny - 1) as f64;
        inside.then_some((g.x as usize, g.y as usize))
    }

    /// Metres per world unit along x and y on row `j`: the unit's length for planar grids
    /// (`(1, 1)` in metres, 0.3048 in feet), the WGS84 [`metres_per_degree`] at the row's latitude
    /// for geographic grids.
    pub fn metres_per_unit(&self, j: usize) -> DVec2 {
        match self.units.metres() {
            Some(m) => DVec2::splat(m),
            None => metres_per_degree(self.origin.y + j as f64 * self.cell_size.y),
        }
    }

    /// Sample spacing in metres on row `j` (rows differ only for geographic grids).
    pub fn cell_size_m(&self, j: usize) -> DVec2 {
        self.cell_size * self.metres_per_unit(j)
    }

    /// Approximate ground area of one cell on row `j`, in square metres.
    pub fn cell_area_m2(&self, j: usize) -> f64 {
        let c = self.cell_size_m(j);
        c.x * c.y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extents_are_checked_and_measured() {
        let d = |x: f64, y: f64| DVec2::new(x, y);
        assert!(Extent::checked(d(0.0, 0.0), d(2.0, 1.0)).is_ok());
        for (min, max) in [
            (d(0.0, 0.0), d(0.0, 1.0)),
            (d(0.0, 0.0), d(1.0, 0.0)),
            (d(2.0, 0.0), d(1.0, 1.0)),
            (d(0.0, 2.0), d(1.0, 1.0)),
            (d(f64::NAN, 0.0), d(1.0, 1.0)),
            (d(0.0, 0.0), d(1.0, f64::INFINITY)),
        ] {
            assert!(matches!(Extent::checked(min, max), Err(HeightfieldError::InvalidExtent { .. })), "{min} {max}");
        }
        let e = Extent::new(d(1.0, 2.0), d(5.0, 10.0));
        assert_eq!((e.size(), e.center()), (d(4.0, 8.0), d(3.0, 6.0)));
        for p in [d(1.0, 2.0), d(5.0, 10.0), d(3.0, 6.0), d(1.0, 10.0)] {
            assert!(e.contains(p), "{p}");
        }
        for p in [d(0.9, 6.0), d(5.1, 6.0), d(3.0, 1.9), d(3.0, 10.1)] {
            assert!(!e.contains(p), "{p}");
        }
    }

    #[test]
    fn grids_from_extents_units_and_cells() {
        let d = |x: f64, y: f64| DVec2::new(x, y);
        // A single-sample axis takes the other axis's spacing (1 when both are single).
        let column = GridSpec::from_extent(1, 5, Extent::new(d(3.0, 0.0), d(3.0, 8.0))).unwrap();
        assert_eq!(column.cell_size(), d(2.0, 2.0));
        let row = GridSpec::from_extent(5, 1, Extent::new(d(0.0, 3.0), d(8.0, 3.0))).unwrap();
        assert_eq!(row.cell_size(), d(2.0, 2.0));
        let point = GridSpec::from_extent(1, 1, Extent::new(d(3.0, 4.0), d(3.0, 4.0))).unwrap();
        assert_eq!((point.cell_size(), point.origin()), (DVec2::ONE, d(3.0, 4.0)));
        assert!(!point.is_empty());
        for (nx, ny, max) in [(1, 5, d(4.0, 8.0)), (5, 5, d(0.0, 8.0)), (5, 5, d(-1.0, 8.0))] {
            assert!(GridSpec::from_extent(nx, ny, Extent::new(d(0.0, 0.0), max)).is_err(), "{nx}x{ny} {max}");
        }
        // Geographic grids stop at the poles (within a rounding tolerance).
        let band = |y0: f64, y1: f64| GridSpec::from_extent(3, 3, Extent::new(d(0.0, y0), d(2.0, y1))).unwrap();
        assert!(band(-90.0, 90.0).with_units(Units::Degrees).is_ok());
        assert!(band(-90.1, 0.0).with_units(Units::Degrees).is_err());
        assert!(band(0.0, 90.1).with_units(Units::Degrees).is_err());
        assert!(band(0.0, 90.1).with_units(Units::Metres).is_ok());
        // Nearest samples within half a cell of the grid; ground measures per row.
        let g = GridSpec::new(4, 3, d(10.0, 20.0), d(2.0, 5.0)).unwrap();
        assert_eq!(g.nearest_sample(d(12.9, 27.4)), Some((1, 1)));
        assert_eq!(g.nearest_sample(d(9.1, 17.6)), Some((0, 0)));
        assert_eq!(g.nearest_sample(d(8.9, 20.0)), None);
        assert_eq!(g.nearest_sample(d(16.0, 32.6)), None);
        assert_eq!(g.nearest_sample(d(17.1, 30.0)), None);
        assert_eq!((g.metres_per_unit(2), g.cell_area_m2(2)), (DVec2::ONE, 10.0));
        let geo = GridSpec::new(4, 3, d(10.0, 40.0), d(0.5, 0.25)).unwrap().with_units(Units::Degrees).unwrap();
        let m = metres_per_degree(40.5);
        assert_eq!(geo.metres_per_unit(2), m);
        assert_eq!(geo.cell_area_m2(2), (0.5 * m.x) * (0.25 * m.y));
    }

    #[test]
    fn metres_per_degree_matches_known_values() {
        let eq = metres_per_degree(0.0);
        assert!((eq.x - 111_319.49).abs() < 0.01, "{eq}");
        assert!((eq.y - 110_574.27).abs() < 0.01, "{eq}");
        let mid = metres_per_degree(45.0);
        assert!((mid.x - 78_846.8).abs() < 0.1, "{mid}");
        assert!((mid.y - 111_132.0).abs() < 1.0, "{mid}");
        assert_eq!(metres_per_degree(90.0).x, 0.0);
    }

    #[test]
    fn rejects_bad_geometry() {
        assert!(matches!(GridSpec::new(0, 3, DVec2::ZERO, DVec2::ONE), Err(HeightfieldError::EmptyGrid { .. })));
        assert!(matches!(
            GridSpec::new(3, 3, DVec2::ZERO, DVec2::new(1.0, -1.0)),
            Err(HeightfieldError::InvalidCellSize { .. })
        ));
        assert!(matches!(
            GridSpec::new(3, 3, DVec2::new(f64::NAN, 0.0), DVec2::ONE),
            Err(HeightfieldError::InvalidOrigin { .. })
        ));
        // A subnormal spacing, and one below the origin's rounding step (neighbours at one point).
        for (origin, cell) in [(0.0, 1e-320), (1e6, 1e-12), (0.0, f64::MIN_POSITIVE / 2.0)] {
            assert!(
                matches!(
                    GridSpec::new(3, 3, DVec2::splat(origin), DVec2::new(1.0, cell)),
                    Err(HeightfieldError::InvalidCellSize { .. })
                ),
                "{origin} {cell}"
            );
        }
        assert!(GridSpec::new(3, 3, DVec2::ZERO, DVec2::splat(f64::MIN_POSITIVE)).is_ok(), "the smallest normal");
        assert!(GridSpec::new(1, 1, DVec2::splat(1e6), DVec2::splat(1e-12)).is_ok(), "one sample has no neighbour");
        assert!(GridSpec::new(3, 3, DVec2::splat(1e6), DVec2::splat(1e-9)).is_ok(), "apart at 1e6");
        assert!(matches!(
            GridSpec::new(3, 3, DVec2::ZERO, DVec2::splat(f64::MAX)),
            Err(HeightfieldError::InvalidOrigin { .. })
        ));
        assert!(matches!(
            GridSpec::new(usize::MAX, 2, DVec2::ZERO, DVec2::ONE),
            Err(HeightfieldError::TooManySamples { .. })
        ));
        assert!(matches!(
            GridSpec::new(70_000, 70_000, DVec2::ZERO, DVec2::ONE),
            Err(HeightfieldError::TooManySamples { .. })
        ));
        assert!(matches!(
            GridSpec::geographic(10, 10, DVec2::new(0.0, 85.0), DVec2::ONE),
            Err(HeightfieldError::LatitudeOutOfRange { .. })
        ));
        let inverted = Extent::new(DVec2::ONE, DVec2::ZERO);
        assert!(matches!(GridSpec::from_extent(4, 4, inverted), Err(HeightfieldError::InvalidExtent { .. })));
    }

    #[test]
    fn extent_round_trips_through_from_extent() {
        let ext = Extent::new(DVec2::new(-3.0, 2.0), DVec2::new(5.0, 10.0));
        let g = GridSpec::from_extent(5, 9, ext).unwrap();
        assert_eq!(g.cell_size(), DVec2::new(2.0, 1.0));
        assert_eq!(g.extent(), ext);
        assert_eq!(g.position(4, 8), ext.max);
        assert_eq!(g.grid_coords(DVec2::new(1.0, 4.0)), DVec2::new(2.0, 2.0));
        assert_eq!(g.nearest_sample(DVec2::new(1.9, 4.4)), Some((2, 2)));
        assert_eq!(g.nearest_sample(DVec2::new(-4.1, 4.0)), None);
        let single = GridSpec::from_extent(1, 3, Extent::new(DVec2::ZERO, DVec2::new(0.0, 4.0))).unwrap();
        assert_eq!(single.cell_size(), DVec2::splat(2.0));
        let r = g.resized(9, 17).unwrap();
        assert_eq!(r.extent(), ext);
    }

    #[test]
    fn geographic_cells_shrink_toward_the_poles() {
        let g = GridSpec::geographic(3601, 3601, DVec2::new(-85.0, 36.0), DVec2::splat(1.0 / 3600.0)).unwrap();
        let south = g.cell_size_m(0);
        let north = g.cell_size_m(3600);
        assert!(north.x < south.x);
        assert!((south.x - 25.0).abs() < 0.1, "{south}");
        assert!((south.y - 30.8).abs() < 0.1, "{south}");
    }

    #[test]
    fn serde_validates() {
        let g = GridSpec::new(4, 3, DVec2::new(1.0, 2.0), DVec2::new(0.5, 0.25)).unwrap();
        let json = serde_json::to_string(&g).unwrap();
        let back: GridSpec = serde_json::from_str(&json).unwrap();
        assert_eq!(back, g);
        let bad = json.replace("0.5", "-0.5");
        assert!(serde_json::from_str::<GridSpec>(&bad).unwrap_err().to_string().contains("cell size"));
        let unknown = json.replace("\"nx\"", "\"nz\"");
        assert!(serde_json::from_str::<GridSpec>(&unknown).is_err());
    }
}
