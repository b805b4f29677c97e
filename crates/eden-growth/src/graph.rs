use glam::DVec2;
use rayon::prelude::*;
use relief_tin::Tin;
use relief_tin::poisson_sampling::{DENSITY, FnDomain, PoissonDisc, SamplingError, TaggedSamples, radius_for_count};
use serde::{Deserialize, Serialize};

use crate::regions::Class;
use crate::{EdenError, LabelMap, RegionTree};

/// How densely to sample the domain.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Sampling {
    /// About this many nodes inside Ω (the paper's #G); the radius follows from Ω's area.
    Particles(usize),
    /// This Poisson-disc radius, in world units.
    Radius(f64),
}

/// Parameters of graph creation (§4.3).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GraphOptions {
    /// Node density.
    pub sampling: Sampling,
    /// Seed of the Poisson sampling.
    pub seed: u64,
    /// Width of the sampled band outside Ω, in radii (the paper's 4).
    pub margin: f64,
    /// Cap on the nodes inside Ω; requests above it fail before anything is allocated.
    pub max_particles: u64,
}

impl GraphOptions {
    /// About `particles` nodes inside Ω, seed 0, margin 4r, cap 50 million.
    pub fn particles(particles: usize) -> Self {
        Self { sampling: Sampling::Particles(particles), seed: 0, margin: 4.0, max_particles: 50_000_000 }
    }

    /// The same options with `seed`.
    #[must_use]
    pub fn with_seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }
}

/// The graph G of the contours paper (§4.3): a Delaunay TIN over a Poisson sampling of Ω ⊕ B(mr),
/// each node tagged with its level (0 outside Ω) and whether it lies in a depression, and ∂G, the
/// inside nodes adjacent to an outside node.
///
/// Enclosed basins the user did not ask for — lower ground walled in by higher levels, e.g. where
/// two ranges nearly touch at this sampling radius — are filled: their nodes are raised to the
/// lowest surrounding level (counted by [`Graph::filled_nodes`]), exactly as a priority-flood fill
/// would, so only marked depressions may hold an endorheic basin.
#[derive(Debug, Clone)]
pub struct Graph {
    tin: Tin,
    level: Vec<u16>,
    depression: Vec<bool>,
    boundary: Vec<u32>,
    radius: f64,
    max_level: u16,
    level_heights: Vec<Option<f64>>,
    filled: usize,
}

impl Graph {
    /// The graph over user regions (polygons).
    ///
    /// # Errors
    /// [`EdenError::InvalidParticleCount`], [`EdenError::TooManyParticles`],
    /// [`EdenError::InvalidMargin`], [`EdenError::RegionTooSmall`], or a sampling/TIN error.
    pub fn from_regions(tree: &RegionTree, options: &GraphOptions) -> Result<Self, EdenError> {
        let omega = tree.omega();
        let (r, requested) = radius(omega.area(), options)?;
        let samples = PoissonDisc::new(r)?
            .with_seed(options.seed)
            .with_max_points(max_points(requested))
            .sample_extended(omega, options.margin * r)
            .map_err(|e| sparse(e, omega.area(), r, requested))?;
        let tin = Tin::new(samples.points)?;
        let classes: Vec<Class> = tin.points().par_iter().map(|&p| tree.classify(p)).collect();
        let mut counts = vec![0usize; tree.regions().len()];
        for c in &classes {
            if let Some(k) = c.region {
                counts[k as usize] += 1;
            }
        }
        if let Some(region) = counts.iter().position(|&c| c == 0) {
            return Err(EdenError::RegionTooSmall { region, radius: r });
        }
        let level = classes.iter().map(|c| c.level).collect();
        let depression = classes.iter().map(|c| c.depression).collect();
        Ok(Self::assemble(tin, level, depression, r, tree.level_heights().to_vec(), false))
    }

    /// The graph over a label map (the paper's input images).
    ///
    /// Land that reaches the image's edge is taken to go on beyond it: the edge pixels' levels
    /// continue over the inner half of the sampled margin (2r at the default margin), and the sea
    /// begins after that. The frame then cuts the terrain; the growth does not start from it,
    /// which would drop every level to the sea within the last sample (a trench along the
    /// border). Sea inside the image seeds its coast as before.
    ///
    /// # Errors
    /// As [`Graph::from_regions`], with [`EdenError::LevelTooSmall`] for a label level that holds
    /// no node.
    pub fn from_labels(labels: &LabelMap, options: &GraphOptions) -> Result<Self, EdenError> {
        let (r, requested) = radius(labels.omega_area(), options)?;
        let margin = options.margin * r;
        // Half a pixel diagonal of slack: the distance transform is measured between pixel centres.
        let slack = 0.5 * labels.grid().cell_size().length();
        let domain = FnDomain::new(labels.omega_bounds().grow(margin), |p: DVec2| labels.near_omega(p, margin + slack));
        let TaggedSamples { points, .. } = PoissonDisc::new(r)?
            .with_seed(options.seed)
            .with_max_points(max_points(requested))
            .sample_tagged(&domain, |_| false)
            .map_err(|e| sparse(e, labels.omega_area(), r, requested))?;
        let tin = Tin::new(points)?;
        // Land reaching the image's edge goes on beyond it, its coast in the outer half of the
        // margin: the frame cuts the terrain instead of the growth starting from it, which would
        // drop every level to the sea within the last sample (a trench along the border).
        let open = 0.5 * margin;
        let level: Vec<u16> = tin.points().par_iter().map(|&p| labels.depth_beyond(p, open)).collect();
        let depression: Vec<bool> = tin.points().par_iter().map(|&p| labels.depression_at(p, open)).collect();
        let heights = labels.level_heights().to_vec();
        let graph = Self::assemble(tin, level, depression, r, heights, labels.allows_depressions());
        // Every level the image has must keep a node, as every region must in `from_regions`: a
        // level thinner than the sampling radius (a one-pixel line, say) may catch none.
        let mut nodes = vec![0usize; graph.max_level.max(labels.max_level()) as usize + 1];
        for &l in &graph.level {
            nodes[l as usize] += 1;
        }
        let mut present = vec![false; nodes.len()];
        for &d in labels.depths() {
            present[d as usize] = true;
        }
        if let Some(level) = (1..nodes.len()).find(|&l| present[l] && nodes[l] == 0) {
            // A disc of the sampling radius inside the level surely holds a node.
            let widest = labels.inscribed_radius(level as u16);
            let needed = 0.8 * widest;
            let particles = (DENSITY * labels.omega_area() / (needed * needed)).ceil().min(u64::MAX as f64) as u64;
            return Err(EdenError::LevelTooSmall { level: level as u16, radius: r, needed_radius: needed, particles });
        }
        Ok(graph)
    }

    fn assemble(
        tin: Tin,
        mut level: Vec<u16>,
        mut depression: Vec<bool>,
        radius: f64,
        mut level_heights: Vec<Option<f64>>,
        basins_are_depressions: bool,
    ) -> Self {
        let filled = settle_basins(&tin, &mut level, &mut depression, basins_are_depressions);
        let boundary: Vec<u32> = (0..tin.num_points() as u32)
            .filter(|&v| level[v as usize] >= 1 && tin.neighbors(v).iter().any(|&w| level[w as usize] == 0))
            .collect();
        let max_level = level.iter().copied().max().unwrap_or(0);
        level_heights.resize(max_level as usize + 1, None);
        Self { tin, level, depression, boundary, radius, max_level, level_heights, filled }
    }

    /// The triangulation (inside and outside nodes).
    pub fn tin(&self) -> &Tin {
        &self.tin
    }

    /// Level of every node: 0 outside Ω, else the depth of its innermost region.
    pub fn levels(&self) -> &[u16] {
        &self.level
    }

    /// Whether each node lies in a depression (allowed to form an endorheic basin).
    pub fn depressions(&self) -> &[bool] {
        &self.depression
    }

    /// Whether node `v` lies inside Ω.
    pub fn is_inside(&self, v: u32) -> bool {
        self.level[v as usize] >= 1
    }

    /// ∂G: inside nodes adjacent to an outside node, by increasing node id.
    pub fn boundary(&self) -> &[u32] {
        &self.boundary
    }

    /// The Poisson-disc radius the graph was sampled with.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The deepest level.
    pub fn max_level(&self) -> u16 {
        self.max_level
    }

    /// Explicit contour height per level, from the regions (index 0 unused).
    pub fn level_heights(&self) -> &[Option<f64>] {
        &self.level_heights
    }

    /// Number of inside nodes.
    pub fn inside_count(&self) -> usize {
        self.level.iter().filter(|&&l| l >= 1).count()
    }

    /// Nodes raised to fill enclosed basins nobody asked for.
    pub fn filled_nodes(&self) -> usize {
        self.filled
    }
}

/// The sampler's point budget for `requested` particles in Ω: room for the margin ring and a
/// slack of 2^20, but proportional to what was asked, so that a sliver of Ω whose bounding box
/// is vast at its sampling radius fails fast instead of allocating a background grid for it.
fn max_points(requested: u64) -> u64 {
    requested.saturating_mul(8).saturating_add(1 << 20)
}

/// A sampler's point-budget error as [`EdenError::SparseDomain`], with the largest particle count
/// whose sampling of the same box fits the budget (the estimate grows with the count, the budget
/// by eight points per particle); other errors pass through.
fn sparse(e: SamplingError, area: f64, radius: f64, requested: u64) -> EdenError {
    let SamplingError::TooManyPoints { width, height, estimated, .. } = e else { return e.into() };
    let per_particle = estimated as f64 / requested.max(1) as f64;
    let particles = if per_particle > 8.0 {
        (0.9 * f64::from(1u32 << 20) / (per_particle - 8.0)).floor() as u64
    } else {
        requested
    };
    let particles = particles.max(1);
    let suggested_radius = (DENSITY * area / particles as f64).sqrt();
    EdenError::SparseDomain { area, width, height, radius, requested, estimated, particles, suggested_radius }
}

/// The Poisson radius a sampling of `area` uses.
pub(crate) fn sampling_radius(area: f64, sampling: Sampling) -> Result<f64, EdenError> {
    Ok(match sampling {
        Sampling::Particles(0) => return Err(EdenError::InvalidParticleCount { count: 0 }),
        Sampling::Particles(n) => radius_for_count(area, n)?,
        Sampling::Radius(r) => r,
    })
}

/// The Poisson radius for the requested density and the particle count it implies in Ω (area
/// `area`), refusing counts over the cap before sampling.
fn radius(area: f64, options: &GraphOptions) -> Result<(f64, u64), EdenError> {
    if !(options.margin.is_finite() && options.margin >= 1.0) {
        return Err(EdenError::InvalidMargin { margin: options.margin });
    }
    let (r, requested) = match options.sampling {
        Sampling::Particles(0) => return Err(EdenError::InvalidParticleCount { count: 0 }),
        Sampling::Particles(n) => (radius_for_count(area, n)?, n as u64),
        Sampling::Radius(r) => (r, (DENSITY * area / (r * r)).ceil().min(u64::MAX as f64) as u64),
    };
    if requested > options.max_particles {
        return Err(EdenError::TooManyParticles { requested, limit: options.max_particles });
    }
    Ok((r, requested))
}

/// Finds, level by level from the bottom, the connected groups of same-level nodes with no
/// neighbour of a lower level (no outlet). A group holding a depression node stays as it is (its
/// nodes all become depression nodes), or every group when `basins_are_depressions`; any other
/// group is raised to its lowest neighbouring level. Returns the number of raised nodes.
fn settle_basins(tin: &Tin, level: &mut [u16], depression: &mut [bool], basins_are_depressions: bool) -> usize {
    let n = level.len();
    let max = level.iter().copied().max().unwrap_or(0);
    let mut seen = vec![false; n];
    let mut group = Vec::new();
    let mut stack = Vec::new();
    let mut filled = 0;
    for l in 1..=max {
        seen.fill(false);
        for start in 0..n as u32 {
            if level[start as usize] != l || seen[start as usize] {
                continue;
            }
            group.clear();
            stack.push(start);
            seen[start as usize] = true;
            let (mut outlet, mut marked, mut lowest_above) = (false, false, u16::MAX);
            while let Some(v) = stack.pop() {
                group.push(v);
                marked |= depression[v as usize];
                for &w in tin.neighbors(v) {
                    let lw = level[w as usize];
                    if lw < l {
                        outlet = true;
                    } else if lw > l {
                        lowest_above = lowest_above.min(lw);
                    } else if !seen[w as usize] {
                        seen[w as usize] = true;
                        stack.push(w);
                    }
                }
            }
            if outlet || lowest_above == u16::MAX {
                continue;
            }
            if marked || basins_are_depressions {
                for &v in &group {
                    depression[v as usize] = true;
                }
            } else {
                for &v in &group {
                    level[v as usize] = lowest_above;
                }
                filled += group.len();
            }
        }
    }
    filled
}
