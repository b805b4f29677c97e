//! The engines, their legal heightmap sizes and the file each one imports.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::EngineError;

/// A game engine or DCC tool to export heightmaps for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub enum Engine {
    /// Unity's terrain (`Terrain > Import Raw…`): square 16-bit RAW heightmaps of 2ⁿ + 1 samples,
    /// little-endian ("Windows" byte order), rows from the terrain's back edge (south, z = 0)
    /// forward, heights as fractions of the terrain's height (its size Y).
    Unity,
    /// Unreal Engine's landscape (`Landscape > Import from File`, World Partition's tiled import):
    /// 16-bit grayscale PNGs at the recommended overall sizes (127 … 8129 samples), code 32768 at
    /// the actor's Z, each code 1/128 of the Z scale in centimetres.
    Unreal,
    /// Godot's terrain plugins (`HTerrain`'s and `Terrain3D`'s importers): square 32-bit float
    /// `OpenEXR` heightmaps in metres, of 2ⁿ + 1 samples (`HTerrain`'s sizes).
    Godot,
    /// Blender: a 16-bit grayscale PNG for a Displace modifier on a subdivided plane (any size),
    /// strength = the height range, midlevel 0.
    Blender,
}

/// The file an engine imports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum HeightmapFile {
    /// Headerless little-endian u16, south row first.
    Raw16SouthFirst,
    /// 16-bit grayscale PNG, north row first.
    Png16,
    /// One f32 channel of heights in metres, north row first.
    Exr,
}

/// 2ⁿ + 1 from 33 to 4097: Unity's heightmap resolutions.
const UNITY: [usize; 8] = [33, 65, 129, 257, 513, 1025, 2049, 4097];
/// Unreal's recommended overall landscape sizes (its Landscape Technical Guide's table).
const UNREAL: [usize; 7] = [127, 253, 505, 1009, 2017, 4033, 8129];
/// `HTerrain`'s map resolutions, 2ⁿ + 1 from 65 to 4097.
const GODOT: [usize; 7] = [65, 129, 257, 513, 1025, 2049, 4097];
/// Blender takes any size; beyond this a plane's subdivisions are no longer usable.
const BLENDER_MAX: usize = 8192;

impl Engine {
    /// Every engine, in documentation order.
    pub const ALL: [Engine; 4] = [Engine::Unity, Engine::Unreal, Engine::Godot, Engine::Blender];

    /// The name the command line and scenes use (`unity`, `unreal`, `godot`, `blender`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Unity => "unity",
            Self::Unreal => "unreal",
            Self::Godot => "godot",
            Self::Blender => "blender",
        }
    }

    /// The heightmap sizes (samples per side) the engine accepts; `None` where any size from 2 to
    /// 8192 is fine (Blender).
    pub fn legal_sizes(self) -> Option<&'static [usize]> {
        match self {
            Self::Unity => Some(&UNITY),
            Self::Unreal => Some(&UNREAL),
            Self::Godot => Some(&GODOT),
            Self::Blender => None,
        }
    }

    /// The legal size nearest `n` samples (the larger of two equally near).
    pub fn nearest_size(self, n: usize) -> usize {
        match self.legal_sizes() {
            Some(sizes) => {
                sizes.iter().copied().min_by_key(|&s| (s.abs_diff(n), std::cmp::Reverse(s))).unwrap_or(sizes[0])
            }
            None => n.clamp(2, BLENDER_MAX),
        }
    }

    /// `n` if it is a legal size.
    ///
    /// # Errors
    /// [`EngineError::IllegalSize`] naming the legal sizes.
    pub fn check_size(self, n: usize) -> Result<usize, EngineError> {
        let legal = match self.legal_sizes() {
            Some(sizes) => sizes.contains(&n),
            None => (2..=BLENDER_MAX).contains(&n),
        };
        if legal {
            Ok(n)
        } else {
            let sizes = self.legal_sizes().map_or_else(
                || format!("2 to {BLENDER_MAX}"),
                |s| s.iter().map(ToString::to_string).collect::<Vec<_>>().join(", "),
            );
            Err(EngineError::IllegalSize { engine: self, size: n, legal: sizes })
        }
    }

    /// Whether one heightmap must be square (every engine but Blender).
    pub(crate) fn square(self) -> bool {
        self != Self::Blender
    }

    pub(crate) fn file(self) -> HeightmapFile {
        match self {
            Self::Unity => HeightmapFile::Raw16SouthFirst,
            Self::Unreal | Self::Blender => HeightmapFile::Png16,
            Self::Godot => HeightmapFile::Exr,
        }
    }

    /// The heightmap's file extension.
    pub(crate) fn extension(self) -> &'static str {
        match self.file() {
            HeightmapFile::Raw16SouthFirst => "raw",
            HeightmapFile::Png16 => "png",
            HeightmapFile::Exr => "exr",
        }
    }

    /// A tile's file stem suffix in the engine's tiled-import naming: Unity's Terrain Toolbox
    /// `_X_Z` (Z from the south), Unreal World Partition's `_x{X}_y{Y}` (Y from the north, its +Y
    /// pointing down the image); `_{X}_{Y}` (Y from the north) for the others.
    pub(crate) fn tile_suffix(self, column: usize, row_from_north: usize, rows: usize) -> String {
        match self {
            Self::Unity => format!("_{column}_{}", rows - 1 - row_from_north),
            Self::Unreal => format!("_x{column}_y{row_from_north}"),
            Self::Godot | Self::Blender => format!("_{column}_{row_from_north}"),
        }
    }
}

impl fmt::Display for Engine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Engine {
    type Err = EngineError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|e| e.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| EngineError::UnknownEngine(s.to_owned()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn legal_sizes_are_the_engines_own() {
        for s in UNITY.iter().chain(&GODOT) {
            assert!((s - 1).is_power_of_two(), "{s} is not 2ⁿ + 1");
        }
        // Unreal's are whole numbers of 126- or 252-quad components plus one, up to 32 per side.
        for s in UNREAL {
            assert!((s - 1) % 63 == 0 || (s - 1) % 126 == 0 || (s - 1) % 254 == 0, "{s}");
        }
        assert_eq!(Engine::Unity.nearest_size(1000), 1025);
        assert_eq!(Engine::Unity.nearest_size(769), 1025, "a tie goes to the larger");
        assert_eq!(Engine::Unity.nearest_size(10), 33);
        assert_eq!(Engine::Unreal.nearest_size(1024), 1009);
        assert_eq!(Engine::Unreal.nearest_size(100_000), 8129);
        assert_eq!(Engine::Godot.nearest_size(2000), 2049);
        assert_eq!(Engine::Blender.nearest_size(777), 777);
        assert_eq!(Engine::Blender.nearest_size(1), 2);
    }

    #[test]
    fn illegal_sizes_name_the_legal_ones() {
        let e = Engine::Unity.check_size(1024).unwrap_err().to_string();
        assert!(e.contains("1024") && e.contains("1025") && e.contains("unity"), "{e}");
        assert_eq!(Engine::Unreal.check_size(2017).unwrap(), 2017);
        assert!(Engine::Blender.check_size(1).is_err() && Engine::Blender.check_size(9000).is_err());
        assert_eq!("Unreal".parse::<Engine>().unwrap(), Engine::Unreal);
        assert!("cryengine".parse::<Engine>().unwrap_err().to_string().contains("unity, unreal, godot, blender"));
    }

    #[test]
    fn tiles_are_named_as_each_importer_expects() {
        // Two rows of tiles: the northern row is Unity's Z = 1 and Unreal's y = 0.
        assert_eq!(Engine::Unity.tile_suffix(3, 0, 2), "_3_1");
        assert_eq!(Engine::Unreal.tile_suffix(3, 0, 2), "_x3_y0");
        assert_eq!(Engine::Godot.tile_suffix(3, 1, 2), "_3_1");
    }
}
