use glam::DVec2;
use relief_tin::TinError;
use relief_tin::poisson_sampling::SamplingError;
use thiserror::Error;

/// Why a graph could not be built or grown. Regions are numbered in input order.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum EdenError {
    /// No region was given.
    #[error("no regions given: at least one outer region (the coastline) is needed")]
    NoRegions,
    /// Two region boundaries touch or cross: regions must nest or be apart.
    #[error("regions {a} and {b} overlap without nesting (their boundaries meet near ({}, {}))", at.x, at.y)]
    RegionsOverlap {
        /// First region.
        a: usize,
        /// Second region.
        b: usize,
        /// A point near the contact.
        at: DVec2,
    },
    /// A raised region (depth ≥ 2) has a hole, which would enclose lower ground with no outlet.
    #[error(
        "region {region} (depth {depth}) has a hole; its inside would be an enclosed basin: draw a separate region with `depression: true` instead"
    )]
    HoleInRaisedRegion {
        /// The region.
        region: usize,
        /// Its nesting depth.
        depth: u16,
    },
    /// A depression region must lie inside a raised region (depth ≥ 2) so its floor has a level.
    #[error("{}", depression_not_nested(*region, *parent_depth))]
    DepressionNotNested {
        /// The depression.
        region: usize,
        /// Depth of its parent (0 when it has none).
        parent_depth: u16,
    },
    /// Depressions may not contain other regions.
    #[error("depression region {region} contains region {child}; depressions may not contain regions")]
    DepressionWithChildren {
        /// The depression.
        region: usize,
        /// A region inside it.
        child: usize,
    },
    /// A depression was given a height, which would be ignored: its contour is its rim, at the
    /// level around it, and its floor follows the histogram.
    #[error(
        "region {region} is a depression: its contour is its rim, at the height of the level around it, and its floor \
         follows the histogram, so its height {height} would be ignored; remove it (or drop `depression` to raise it)"
    )]
    DepressionHeight {
        /// The depression.
        region: usize,
        /// The height given.
        height: f64,
    },
    /// A region's explicit height is not finite.
    #[error("region {region} has height {value}; heights must be finite")]
    InvalidHeight {
        /// The region.
        region: usize,
        /// The height given.
        value: f64,
    },
    /// Two regions at the same depth give different heights (heights apply per depth level).
    #[error(
        "regions {a} and {b} are both at depth {depth} but give heights {height_a} and {height_b}; heights apply to a whole \
         depth level (the growth shares one front per level): give both {} and draw a region at {} inside region {}",
        height_a.min(*height_b),
        height_a.max(*height_b),
        if height_a > height_b { a } else { b }
    )]
    ConflictingHeights {
        /// The depth level.
        depth: u16,
        /// First region.
        a: usize,
        /// Its height.
        height_a: f64,
        /// Second region.
        b: usize,
        /// Its height.
        height_b: f64,
    },
    /// Explicit heights must increase with depth.
    #[error("depth {depth} has height {height}, not above depth {lower_depth}'s height {lower_height}")]
    HeightsNotIncreasing {
        /// The deeper level.
        depth: u16,
        /// Its height.
        height: f64,
        /// The shallower level.
        lower_depth: u16,
        /// Its height.
        lower_height: f64,
    },
    /// A region's `depth` is invalid.
    #[error("region {region}: depth {value} {reason}")]
    InvalidDepth {
        /// The region.
        region: usize,
        /// The depth given.
        value: f64,
        /// What is wrong.
        reason: &'static str,
    },
    /// A region holds no graph node at this sampling radius.
    #[error("region {region} holds no graph node at sampling radius {radius}: enlarge it or raise the particle count")]
    RegionTooSmall {
        /// The region.
        region: usize,
        /// The sampling radius.
        radius: f64,
    },
    /// A level of a label map holds no graph node at this sampling radius.
    #[error(
        "label level {level} holds no graph node at sampling radius {radius}: its widest part is {:.3} across, so use \
         `radius` ≤ {needed_radius:.4} (about {particles} particles) or thicken it in the image",
        2.0 * needed_radius / 0.8
    )]
    LevelTooSmall {
        /// The level (depth) in the label map.
        level: u16,
        /// The sampling radius.
        radius: f64,
        /// A radius at which the level surely holds a node (0.8 × its widest inscribed disc).
        needed_radius: f64,
        /// The particle count that gives that radius over the whole map.
        particles: u64,
    },
    /// A label map is malformed.
    #[error("invalid label map: {reason}")]
    InvalidLabelMap {
        /// What is wrong.
        reason: String,
    },
    /// The particle count is zero.
    #[error("particle count must be at least 1, got {count}")]
    InvalidParticleCount {
        /// The count given.
        count: usize,
    },
    /// The requested graph would exceed the particle cap.
    #[error("about {requested} particles requested, over the cap of {limit}; lower the count or raise the cap")]
    TooManyParticles {
        /// Particles the request implies.
        requested: u64,
        /// The cap.
        limit: u64,
    },
    /// The margin of the extended domain (in radii) is not a finite number ≥ 1.
    #[error("extended-domain margin of {margin} radii must be finite and >= 1")]
    InvalidMargin {
        /// The margin given.
        margin: f64,
    },
    /// A probability value is negative or not finite.
    #[error("probability map gives {value} at ({x}, {y}); probabilities must be finite and >= 0")]
    InvalidProbability {
        /// Where.
        x: f64,
        /// Where.
        y: f64,
        /// What it gave.
        value: f64,
    },
    /// The probability map is zero on every node, so no growth order is preferred anywhere.
    #[error("probability map is zero on every node of the region")]
    ZeroProbability,
    /// The parameters of a built-in probability map are invalid.
    #[error("invalid probability map parameters: {reason}")]
    InvalidProbabilityParameters {
        /// What is wrong.
        reason: String,
    },
    /// Ω is small and spread out (specks far apart): at the requested density, sampling its
    /// bounding box would exceed the point budget.
    #[error(
        "the regions cover {area:.0} square units spread over a {width:.0} x {height:.0} box: the radius {radius:.4} \
         that {requested} particles need there would take about {estimated} samples over that box; use at most \
         {particles} particles (`radius` ≥ {suggested_radius:.4}), or remove the far-off specks"
    )]
    SparseDomain {
        /// Area of Ω.
        area: f64,
        /// Width of Ω's bounding box (with the sampling margin).
        width: f64,
        /// Its height.
        height: f64,
        /// The radius the request gives.
        radius: f64,
        /// Particles requested.
        requested: u64,
        /// Samples the bounding box would take.
        estimated: u64,
        /// A particle count within the budget.
        particles: u64,
        /// The radius that count gives.
        suggested_radius: f64,
    },
    /// Sampling the extended domain failed.
    #[error("sampling the domain failed: {0}")]
    Sampling(#[from] SamplingError),
    /// Triangulating the samples failed.
    #[error("triangulating the samples failed: {0}")]
    Tin(#[from] TinError),
    /// A growth breaks one of its invariants at a node ([`crate::Growth::check_invariants`]): a
    /// bug, never the user's input.
    #[error("growth invariant broken at node {node}: {reason}")]
    BrokenGrowth {
        /// The offending node.
        node: u32,
        /// What is wrong there.
        reason: String,
    },
    /// A growth does not fit the graph it is checked against (node count, level count or a
    /// level's extent in the order).
    #[error("growth does not fit its graph: {reason}")]
    GrowthMismatch {
        /// What differs.
        reason: String,
    },
}

impl EdenError {
    /// Where the offending value is, as a JSON path relative to the inputs laid out as a scene's
    /// `contours` generator lays them out: `regions[2].polygon`, `regions[1].height`,
    /// `probability`, `particles`…; empty when the error concerns the inputs as a whole (a label
    /// map's level, a particle budget, sampling). The `relief` facade prefixes it with the
    /// generator's path.
    pub fn location(&self) -> String {
        let region = |i: usize, field: &str| format!("regions[{i}]{field}");
        match *self {
            Self::NoRegions | Self::HeightsNotIncreasing { .. } => "regions".to_owned(),
            Self::RegionsOverlap { b, .. } => region(b, ".polygon"),
            Self::HoleInRaisedRegion { region: i, .. } => region(i, ".polygon.holes"),
            Self::DepressionNotNested { region: i, .. } | Self::DepressionWithChildren { region: i, .. } => {
                region(i, ".depression")
            }
            Self::DepressionHeight { region: i, .. }
            | Self::InvalidHeight { region: i, .. }
            | Self::ConflictingHeights { b: i, .. } => region(i, ".height"),
            Self::RegionTooSmall { region: i, .. } => region(i, ".polygon"),
            Self::InvalidDepth { region: i, .. } => region(i, ".depth"),
            Self::InvalidProbability { .. } | Self::ZeroProbability | Self::InvalidProbabilityParameters { .. } => {
                "probability".to_owned()
            }
            Self::InvalidParticleCount { .. } | Self::SparseDomain { .. } => "particles".to_owned(),
            _ => String::new(),
        }
    }
}

/// Why a depression cannot sit where it is, and what to draw instead.
fn depression_not_nested(region: usize, parent_depth: u16) -> String {
    if parent_depth == 0 {
        return format!("depression region {region} lies outside every region: draw it inside a raised region");
    }
    format!(
        "depression region {region} lies directly inside the coastline: a depression's rim is the contour of the level \
         around it, here the coast's, so its floor would sink below the sea; draw a region around it (a lowland with \
         its own height) and put the depression inside that, or make it a hole of the coastline for an inland sea"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_error_is_located_at_the_value_it_is_about() {
        let cases = [
            (EdenError::NoRegions, "regions"),
            (EdenError::HeightsNotIncreasing { depth: 2, height: 1.0, lower_depth: 1, lower_height: 5.0 }, "regions"),
            (EdenError::RegionsOverlap { a: 0, b: 3, at: DVec2::ZERO }, "regions[3].polygon"),
            (EdenError::HoleInRaisedRegion { region: 2, depth: 2 }, "regions[2].polygon.holes"),
            (EdenError::DepressionNotNested { region: 4, parent_depth: 0 }, "regions[4].depression"),
            (EdenError::DepressionWithChildren { region: 5, child: 6 }, "regions[5].depression"),
            (EdenError::InvalidHeight { region: 1, value: f64::NAN }, "regions[1].height"),
            (EdenError::DepressionHeight { region: 9, height: 3.0 }, "regions[9].height"),
            (EdenError::ConflictingHeights { depth: 2, a: 1, height_a: 3.0, b: 7, height_b: 4.0 }, "regions[7].height"),
            (EdenError::RegionTooSmall { region: 8, radius: 2.0 }, "regions[8].polygon"),
            (EdenError::InvalidProbability { x: 0.0, y: 0.0, value: -1.0 }, "probability"),
            (EdenError::ZeroProbability, "probability"),
            (EdenError::InvalidProbabilityParameters { reason: String::new() }, "probability"),
            (EdenError::InvalidParticleCount { count: 0 }, "particles"),
            (EdenError::TooManyParticles { requested: 9, limit: 1 }, ""),
            (EdenError::LevelTooSmall { level: 2, radius: 1.0, needed_radius: 0.5, particles: 9 }, ""),
        ];
        for (e, path) in cases {
            assert_eq!(e.location(), path, "{e:?}");
        }
    }
}
