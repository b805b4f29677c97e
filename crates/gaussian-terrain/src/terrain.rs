//! The vector terrain (a list of primitives, serde) and the atlas of saved landforms.

use glam::DVec2;
use relief_heightfield::{Crs, Extent, Heightfield, Units};
use serde::{Deserialize, Serialize};

use crate::{DetailLayer, Gaussian, GaussianError};

/// The most primitives a terrain or atlas landform may hold: 2²² (about 4.2 million, 230 MB).
pub const MAX_PRIMITIVES: usize = 1 << 22;

/// A terrain as a sum of generalized Gaussian primitives: `h(p) = Σ gᵢ(p)` (§3.2). Resolution
/// independent; [`crate::rasterize`] turns it into a grid at any resolution and window.
///
/// Deserializing validates it ([`VectorTerrain::validate`]: NaN, `σ ≤ 0`, too many primitives,
/// a bad domain or detail layer), so a terrain read from JSON is always usable; one built in code
/// is checked by the rasterizer.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, try_from = "VectorTerrainJson")]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct VectorTerrain {
    /// The primitives, summed in this order.
    pub primitives: Vec<Gaussian>,
    /// A constant added everywhere (default 0): vectorization puts the DEM's minimum here so
    /// that the primitives only model relief above it.
    #[serde(default)]
    pub base: f64,
    /// Where the base plus the primitives falls below this, the terrain is this (before the
    /// detail layers): the sea level or flat low ground of a vectorized DEM, kept exactly flat
    /// (none by default; vectorization sets it to the DEM's minimum when at least 1 % of the DEM
    /// lies there). Its slope there is 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub floor: Option<f64>,
    /// The window the terrain was made for, `[min, max]` corners (vectorization records the
    /// DEM's extent); renderers default to it. Not a clip: primitives reach beyond it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub domain: Option<[[f64; 2]; 2]>,
    /// Detail primitives (§3.2), added after the Gaussians in this order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub details: Vec<DetailLayer>,
    /// What the coordinates (centres, σ, domain) measure; none: the CRS's units, else metres.
    /// Vectorization records the DEM's grid units, so that a raster of the terrain is labelled
    /// like the DEM (see [`VectorTerrain::units`]). Given, they win over the CRS's, as a grid's
    /// do (a DEM read with its units overridden keeps its file's CRS label).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub units: Option<Units>,
    /// The coordinate reference system of the coordinates (vectorization records the DEM's):
    /// rasters of the terrain carry it. A label only: nothing is reprojected.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crs: Option<Crs>,
}

/// The unchecked JSON form of a [`VectorTerrain`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema), schemars(rename = "VectorTerrain"))]
struct VectorTerrainJson {
    /// The primitives, summed in this order.
    primitives: Vec<Gaussian>,
    /// A constant added everywhere (default 0).
    #[serde(default)]
    base: f64,
    /// The lowest elevation of the base plus the primitives (none by default).
    #[serde(default)]
    floor: Option<f64>,
    /// The window the terrain was made for, `[min, max]` corners.
    #[serde(default)]
    domain: Option<[[f64; 2]; 2]>,
    /// Detail primitives (§3.2).
    #[serde(default)]
    details: Vec<DetailLayer>,
    /// What the coordinates measure (none: metres, or the CRS's units).
    #[serde(default)]
    units: Option<Units>,
    /// The coordinate reference system of the coordinates.
    #[serde(default)]
    crs: Option<Crs>,
}

impl TryFrom<VectorTerrainJson> for VectorTerrain {
    type Error = GaussianError;
    fn try_from(j: VectorTerrainJson) -> Result<Self, GaussianError> {
        let terrain = Self {
            primitives: j.primitives,
            base: j.base,
            floor: j.floor,
            domain: j.domain,
            details: j.details,
            units: j.units,
            crs: j.crs,
        };
        terrain.validate()?;
        Ok(terrain)
    }
}

impl VectorTerrain {
    /// A terrain of these primitives (not yet validated).
    pub fn new(primitives: Vec<Gaussian>) -> Self {
        Self { primitives, ..Self::default() }
    }

    /// What the coordinates measure: [`VectorTerrain::units`] if given (even where the CRS says
    /// otherwise), else the CRS's units, else metres.
    pub fn units(&self) -> Units {
        self.units.or_else(|| self.crs.as_ref().and_then(Crs::units)).unwrap_or_default()
    }

    /// The units and CRS of `dem`'s coordinates, recorded on this terrain (what vectorization
    /// does).
    #[must_use]
    pub fn in_frame_of(mut self, dem: &Heightfield) -> Self {
        self.units = Some(dem.grid().units());
        self.crs = dem.crs().cloned();
        self
    }

    /// Number of primitives.
    pub fn len(&self) -> usize {
        self.primitives.len()
    }

    /// Whether there is no primitive (a flat terrain at 0).
    pub fn is_empty(&self) -> bool {
        self.primitives.is_empty()
    }

    /// Checks every primitive, detail layer and the count (Gaussians plus detail centres).
    ///
    /// # Errors
    /// [`GaussianError::TooManyPrimitives`] above [`MAX_PRIMITIVES`]; a non-finite base; the
    /// first primitive's [`Gaussian::validate`] or layer's [`DetailLayer::validate`] error.
    pub fn validate(&self) -> Result<(), GaussianError> {
        self.validate_with_limit(MAX_PRIMITIVES)
    }

    /// [`Self::validate`] with a caller's cap on the primitive count (a budget below
    /// [`MAX_PRIMITIVES`]).
    ///
    /// # Errors
    /// As [`Self::validate`], with `limit` in place of [`MAX_PRIMITIVES`].
    pub fn validate_with_limit(&self, limit: usize) -> Result<(), GaussianError> {
        let limit = limit.min(MAX_PRIMITIVES);
        let count = self.primitives.len() + self.details.iter().map(|d| d.centers.len()).sum::<usize>();
        if count > limit {
            return Err(GaussianError::TooManyPrimitives { count, limit });
        }
        let finite = |v: f64| v.is_finite() && v.abs() <= f64::from(f32::MAX);
        if !finite(self.base) {
            return Err(GaussianError::NotFinite { index: 0, what: "base" });
        }
        if self.floor.is_some_and(|f| !finite(f)) {
            return Err(GaussianError::NotFinite { index: 0, what: "floor" });
        }
        if let Some([lo, hi]) = self.domain
            && !(lo.iter().chain(&hi).all(|v| v.is_finite()) && hi[0] > lo[0] && hi[1] > lo[1])
        {
            return Err(GaussianError::NotFinite { index: 0, what: "domain (finite, max > min)" });
        }
        self.primitives.iter().enumerate().try_for_each(|(i, g)| g.validate(i))?;
        self.details.iter().enumerate().try_for_each(|(i, d)| d.validate(i))
    }

    /// The window to render by default: the recorded [`VectorTerrain::domain`], else the union
    /// of the primitives' supports (at [`crate::DEFAULT_TOLERANCE`]), else 1000 × 1000 from the
    /// origin.
    pub fn extent(&self) -> Extent {
        if let Some([lo, hi]) = self.domain {
            return Extent::new(DVec2::from(lo), DVec2::from(hi));
        }
        let bounds = self
            .primitives
            .iter()
            .map(|g| g.bounds(crate::DEFAULT_TOLERANCE))
            .reduce(|(a, b), (lo, hi)| (a.min(lo), b.max(hi)));
        match bounds {
            Some((lo, hi)) if (hi - lo).min_element() > 0.0 => Extent::new(lo, hi),
            _ => Extent::new(DVec2::ZERO, DVec2::splat(1000.0)),
        }
    }

    /// The exact elevation at `p`: the base, every primitive untruncated and every detail
    /// layer, in f64. O(primitives); the reference the rasterizer is tested against.
    pub fn height_at(&self, p: DVec2) -> f64 {
        let ground = self.ground_at(p);
        ground.elevation + self.details.iter().map(|d| d.value(p, ground)).sum::<f64>()
    }

    /// The loop of the paper's Fig. 15: whatever changed `target` away from this terrain
    /// (erosion on its raster, say) becomes a detail layer, `ΔT = target − T̃` read by detail
    /// primitives at Poisson-disc centres `spacing` cells apart over `target`'s extent, so the
    /// terrain reproduces `target` on its grid and carries the change to any other resolution.
    ///
    /// # Errors
    /// The rasterizer's errors; [`GaussianError::InvalidOption`] for a spacing that is not
    /// `> 0` or that would place more centres than [`MAX_PRIMITIVES`].
    pub fn add_error_details(&mut self, target: &Heightfield, spacing: f64, seed: u64) -> Result<(), GaussianError> {
        if !(spacing.is_finite() && spacing > 0.0) {
            return Err(GaussianError::InvalidOption {
                name: "detail spacing",
                value: spacing,
                reason: "must be > 0 cells",
            });
        }
        let current = crate::rasterize(self, target.grid(), &crate::RasterOptions::default())?;
        let error: Vec<f32> = target.samples().iter().zip(current.samples()).map(|(t, c)| t - c).collect();
        let map = Heightfield::from_samples(*target.grid(), error)?;
        let cell = target.grid().cell_size();
        let extent = target.extent();
        let radius = spacing * cell.x.min(cell.y);
        let budget = MAX_PRIMITIVES.saturating_sub(self.len());
        let layer = DetailLayer::poisson(
            (extent.min, extent.max),
            radius,
            seed,
            budget,
            crate::DetailSource::ErrorMap { map },
        )?;
        self.details.push(layer);
        Ok(())
    }

    /// The ground the detail layers see at `p`: the base plus every primitive untruncated, and
    /// its slope from their exact gradients; the floor and a slope of 0 where that is below the
    /// [`VectorTerrain::floor`].
    pub fn ground_at(&self, p: DVec2) -> crate::Ground {
        let elevation = self.base + self.primitives.iter().map(|g| g.value(p)).sum::<f64>();
        if let Some(floor) = self.floor
            && elevation < floor
        {
            return crate::Ground { elevation: floor, slope: 0.0 };
        }
        let gradient: DVec2 = self.primitives.iter().map(|g| g.gradient(p)).sum();
        crate::Ground { elevation, slope: gradient.length() }
    }
}

/// A landform saved for stamping: primitives relative to an anchor at the origin.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Landform {
    /// Name to find it by.
    pub name: String,
    /// Primitives, centres relative to the landform's anchor.
    pub primitives: Vec<Gaussian>,
}

impl Landform {
    /// Saves `primitives` as a landform anchored at `anchor` (their centres become relative).
    pub fn new(name: impl Into<String>, primitives: &[Gaussian], anchor: DVec2) -> Self {
        let primitives =
            primitives.iter().map(|g| Gaussian { center: (DVec2::from(g.center) - anchor).to_array(), ..*g }).collect();
        Self { name: name.into(), primitives }
    }

    /// The landform placed with its anchor at `at`, turned by `rotation` radians and scaled
    /// uniformly by `scale` (σ and centre offsets; amplitudes unchanged).
    pub fn placed(&self, at: DVec2, rotation: f64, scale: f64) -> Vec<Gaussian> {
        let turn = DVec2::from_angle(rotation);
        self.primitives
            .iter()
            .map(|g| Gaussian {
                center: (at + turn.rotate(DVec2::from(g.center) * scale)).to_array(),
                sigma: [g.sigma[0] * scale, g.sigma[1] * scale],
                theta: g.theta + rotation,
                ..*g
            })
            .collect()
    }
}

/// A collection of saved landforms (§5.2, "vector-based atlas"): serde, so it saves as JSON;
/// deserializing validates it ([`Atlas::validate`]).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, try_from = "AtlasJson")]
pub struct Atlas {
    /// The landforms, by name.
    pub landforms: Vec<Landform>,
    /// What their coordinates measure: the units of the terrain they were taken from (none:
    /// not recorded). A landform pasted into a terrain in other units would come out scaled by
    /// their ratio, so users of an atlas compare this with the terrain's
    /// [`VectorTerrain::units`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub units: Option<Units>,
}

/// The unchecked JSON form of an [`Atlas`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AtlasJson {
    landforms: Vec<Landform>,
    #[serde(default)]
    units: Option<Units>,
}

impl TryFrom<AtlasJson> for Atlas {
    type Error = GaussianError;
    fn try_from(j: AtlasJson) -> Result<Self, GaussianError> {
        let atlas = Self { landforms: j.landforms, units: j.units };
        atlas.validate()?;
        Ok(atlas)
    }
}

impl Atlas {
    /// The landform called `name`.
    ///
    /// # Errors
    /// [`GaussianError::NoSuchLandform`].
    pub fn get(&self, name: &str) -> Result<&Landform, GaussianError> {
        self.landforms
            .iter()
            .find(|l| l.name == name)
            .ok_or_else(|| GaussianError::NoSuchLandform { name: name.into() })
    }

    /// Checks every landform's primitives (indices count across the atlas).
    ///
    /// # Errors
    /// As [`VectorTerrain::validate`].
    pub fn validate(&self) -> Result<(), GaussianError> {
        let count: usize = self.landforms.iter().map(|l| l.primitives.len()).sum();
        if count > MAX_PRIMITIVES {
            return Err(GaussianError::TooManyPrimitives { count, limit: MAX_PRIMITIVES });
        }
        self.landforms.iter().flat_map(|l| &l.primitives).enumerate().try_for_each(|(i, g)| g.validate(i))
    }
}
