//! [`InputOptions`]: how a scene's input files are read, for what they do not say themselves.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::heightfield::{Crs, Units};
use crate::io::{Channel, ReadOptions};

/// What a scene's input files (DEMs, heightmap images, control maps, label masks) do not say
/// themselves: the scene's form of the command line's global read flags (`--z-range`,
/// `--cell-size`, `--origin`, `--raw-size`, `--units`, `--crs`, `--band`, `--channel`). Every
/// field is optional and applies to every input the scene reads; the command line's flags apply
/// to the files a command reads directly.
///
/// ```json
/// "inputs": { "z_range": [-50, 1200], "cell_size": [30, 30], "crs": { "epsg": 32617 } }
/// ```
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct InputOptions {
    /// Elevations `[min, max]` a plain 8/16-bit heightmap's lowest and highest codes stand for
    /// (default 0 and 1); refused for files that store elevations.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub z_range: Option<[f64; 2]>,
    /// Distance `[x, y]` between samples, overriding the files'.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cell_size: Option<[f64; 2]>,
    /// Position `[x, y]` of the south-west sample, overriding the files'.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub origin: Option<[f64; 2]>,
    /// `[width, height]` of a .r16/.r32 file without a sidecar (default: square).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub raw_size: Option<[usize; 2]>,
    /// Units of the coordinates, overriding the files' and their CRS's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub units: Option<Units>,
    /// Coordinate reference system to label the inputs with (nothing is reprojected).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crs: Option<Crs>,
    /// Band (1-based) of a multi-band GeoTIFF.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub band: Option<u16>,
    /// Channel of a colour image that holds the values.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub channel: Option<Channel>,
}

impl InputOptions {
    /// These options applied to `read`.
    pub fn apply(&self, mut read: ReadOptions) -> ReadOptions {
        if let Some([min, max]) = self.z_range {
            read = read.with_z_range(min, max);
        }
        if let Some(c) = self.cell_size {
            read = read.with_cell_size(c.into());
        }
        if let Some(o) = self.origin {
            read = read.with_origin(o.into());
        }
        if let Some([w, h]) = self.raw_size {
            read = read.with_raw_dims(w, h);
        }
        if let Some(units) = self.units {
            read = read.with_units(units);
        }
        if let Some(crs) = &self.crs {
            read = read.with_crs(crs.clone());
        }
        if let Some(band) = self.band {
            read = read.with_band(band);
        }
        if let Some(channel) = self.channel {
            read = read.with_channel(channel);
        }
        read
    }

    /// Whether every field is unset.
    pub fn is_empty(&self) -> bool {
        self == &Self::default()
    }
}
