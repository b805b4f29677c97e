//! Label masks as people draw them (the contours paper's input images, §4.5): one colour per
//! nested region, saved from a paint program with whatever else that brings — anti-aliased edges,
//! stray pixels of other colours, palette entries of near-identical grays, transparency.
//!
//! [`LabelMap::from_mask`](crate::LabelMap::from_mask) cleans them; [`MaskOptions`] lists its steps.

use std::collections::HashMap;

use glam::DVec2;
use rayon::prelude::*;
use relief_tin::heightfield::GridSpec;

use crate::graph::sampling_radius;
use crate::{EdenError, MAX_LABEL_LEVELS, Sampling};

/// Largest per-channel difference (in [0, 1]) at which an image colour matches a table row: four
/// 8-bit steps, so palette variants of one gray match while distinct drawn colours do not.
pub const COLOR_TOLERANCE: f32 = 4.5 / 255.0;

/// Fewest pixels a kept patch has: the 3 × 3 block that makes a colour a label.
const MIN_PATCH_PIXELS: usize = 9;

/// Merged patches listed one by one; the rest are only counted.
const LISTED_MERGES: usize = 100;

/// One row of a label table: the colour that marks a level, and what the level is.
#[derive(Debug, Clone, PartialEq)]
pub struct LabelLevel {
    /// The colour, RGB in [0, 1] (a gray as three equal values).
    pub color: [f32; 3],
    /// Height of the level's contour (rows in table order must increase).
    pub height: Option<f64>,
    /// Pixels of this colour are a depression (a crater) inside the region around them, which must
    /// lie at depth 2 or more.
    pub depression: bool,
}

impl LabelLevel {
    /// A raised level of this colour, with no height given.
    pub fn new(color: [f32; 3]) -> Self {
        Self { color, height: None, depression: false }
    }
}

/// How [`LabelMap::from_mask`](crate::LabelMap::from_mask) reads a mask. It turns the image into a
/// raster of depths in four steps:
/// 1. **Label colours.** A colour is a label when at least one of its pixels is surrounded by its
///    own colour on all eight sides (a region is at least 3 × 3 pixels). Edge blends and specks
///    never are. Transparent pixels (alpha under ½) belong to the outside.
/// 2. **Levels.** Without a table the label colours, darkest first, are depths 0 (outside Ω), 1, 2…
///    — or 1, 2… when transparency forms a region, which is then the outside; with a
///    [`LabelLevel`] table each label colour joins the row of nearest colour (within
///    [`COLOR_TOLERANCE`]), rows in order being depths, and a colour no row lists is refused. A
///    depression row's patches sink one depth below the level around them.
/// 3. **Snapping.** Every other pixel takes, layer by layer from the labelled ones, the level of
///    the neighbouring label pixel closest to it in colour: an anti-aliased edge splits between its
///    two sides.
/// 4. **Merging.** A connected patch (8-neighbour) smaller than the sampling can hold — a disc of
///    the Poisson radius, and at least 3 × 3 pixels — joins the patch it shares most border with,
///    and is listed in [`MaskCleaning::merged`].
#[derive(Debug, Clone, PartialEq)]
pub struct MaskOptions {
    /// The colour table; `None`: every label colour is a level, darkest outside.
    pub levels: Option<Vec<LabelLevel>>,
    /// The sampling the graph will use, which sets the smallest patch kept.
    pub sampling: Sampling,
}

/// A patch merged into its surroundings because the sampling could not hold it.
#[derive(Debug, Clone, PartialEq)]
pub struct MergedPatch {
    /// Its centroid, in world units.
    pub at: DVec2,
    /// Its size in pixels.
    pub pixels: usize,
    /// Its level's colour.
    pub color: [f32; 3],
    /// The colour of the level it joined.
    pub into: [f32; 3],
}

/// What [`LabelMap::from_mask`](crate::LabelMap::from_mask) changed in a mask.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MaskCleaning {
    /// The colour of each level by depth (index 0: outside Ω).
    pub colors: Vec<[f32; 3]>,
    /// Whether the outside is the image's transparent part (its colour then reads black).
    pub transparent_outside: bool,
    /// Pixels of no label colour that took a neighbour's level (edge blends, specks).
    pub snapped_pixels: usize,
    /// The smallest patch kept, in pixels.
    pub min_patch_pixels: usize,
    /// The first 100 merged patches, by size then position.
    pub merged: Vec<MergedPatch>,
    /// How many patches were merged in all.
    pub merged_count: usize,
}

/// A cleaned mask: depth and depression flag per pixel, and the levels' heights.
#[derive(Debug, Clone)]
pub(crate) struct CleanMask {
    pub(crate) depth: Vec<u16>,
    pub(crate) depression: Vec<bool>,
    pub(crate) level_heights: Vec<Option<f64>>,
    pub(crate) cleaning: MaskCleaning,
}

/// One level of the mask, before depths are laid out.
struct Class {
    color: [f32; 3],
    height: Option<f64>,
    depression: bool,
}

const TRANSPARENT: u64 = u64::MAX;
const UNSET: u16 = u16::MAX;

/// Cleans an RGBA mask (row-major, row 0 south, values in [0, 1]) over `grid`.
///
/// # Errors
/// [`EdenError::InvalidLabelMap`] when the sizes disagree, the image has no region (nothing but
/// the outside colour forms a 3 × 3 block), more label colours than [`MAX_LABEL_LEVELS`] + 1, a
/// label colour no table row lists, a depression not inside a raised level, or table heights
/// that are not finite and increasing.
pub(crate) fn clean_mask(grid: &GridSpec, rgba: &[[f32; 4]], options: &MaskOptions) -> Result<CleanMask, EdenError> {
    let invalid = |reason: String| EdenError::InvalidLabelMap { reason };
    if rgba.len() != grid.len() {
        return Err(invalid(format!("{} pixels for a {}x{} grid", rgba.len(), grid.nx(), grid.ny())));
    }
    let keys: Vec<u64> = rgba.par_iter().map(|&p| key(p)).collect();
    let stats = key_stats(grid, &keys);
    let classes = match &options.levels {
        Some(table) => table_classes(table)?,
        None => luma_classes(&stats)?,
    };
    let class_of_key = assign_keys(grid, &stats, &classes, options.levels.is_some())?;
    let mut last = (TRANSPARENT - 1, UNSET);
    let mut class: Vec<u16> = keys
        .iter()
        .map(|&k| {
            if k != last.0 {
                last = (k, class_of_key.get(&k).copied().unwrap_or(UNSET));
            }
            last.1
        })
        .collect();
    let snapped_pixels = snap(grid, rgba, &classes, &mut class);
    let inside = class.iter().filter(|&&c| c != 0).count();
    if inside == 0 {
        return Err(invalid("no region: every colour but the outside's is an edge blend or a speck".into()));
    }
    let cell = grid.cell_size();
    let r = sampling_radius(inside as f64 * cell.x * cell.y, options.sampling)?;
    let min_patch_pixels = ((std::f64::consts::PI * r * r / (cell.x * cell.y)).ceil() as usize).max(MIN_PATCH_PIXELS);
    let (merged, merged_count) = merge_small(grid, &mut class, &classes, min_patch_pixels);
    let Layout { depth, depression, heights: level_heights, colors } = layout(grid, &class, &classes)?;
    let transparent_outside = options.levels.is_none() && stats.get(&TRANSPARENT).is_some_and(|s| s.interior > 0);
    let cleaning = MaskCleaning { colors, transparent_outside, snapped_pixels, min_patch_pixels, merged, merged_count };
    Ok(CleanMask { depth, depression, level_heights, cleaning })
}

/// A pixel's colour at 16 bits a channel, or [`TRANSPARENT`].
fn key(p: [f32; 4]) -> u64 {
    if p[3].is_nan() || p[3] < 0.5 || p[..3].iter().any(|v| v.is_nan()) {
        return TRANSPARENT;
    }
    let q = |v: f32| (f64::from(v.clamp(0.0, 1.0)) * 65535.0).round() as u64;
    (q(p[0]) << 32) | (q(p[1]) << 16) | q(p[2])
}

fn key_color(k: u64) -> [f32; 3] {
    if k == TRANSPARENT {
        return [0.0; 3];
    }
    let c = |shift: u32| ((k >> shift) & 0xFFFF) as f32 / 65535.0;
    [c(32), c(16), c(0)]
}

/// How often a colour occurs, how many of its pixels are surrounded by it, and its first pixel.
#[derive(Clone, Copy)]
struct KeyStat {
    pixels: usize,
    interior: usize,
    first: usize,
}

/// Counts of every colour.
fn key_stats(grid: &GridSpec, keys: &[u64]) -> HashMap<u64, KeyStat> {
    let (nx, ny) = (grid.nx(), grid.ny());
    let interior: Vec<bool> = (0..keys.len())
        .into_par_iter()
        .map(|k| {
            let (i, j) = (k % nx, k / nx);
            let key = keys[k];
            if i > 0 && j > 0 && i + 1 < nx && j + 1 < ny {
                let rows = [k - nx, k, k + nx];
                rows.iter().all(|&r| keys[r - 1] == key && keys[r] == key && keys[r + 1] == key)
            } else {
                neighbours8(i, j, nx, ny).all(|q| keys[q] == key)
            }
        })
        .collect();
    let mut stats: HashMap<u64, KeyStat> = HashMap::new();
    let mut run_start = 0;
    // Runs of one colour are counted at once: masks are mostly long runs.
    for k in 1..=keys.len() {
        if k < keys.len() && keys[k] == keys[run_start] {
            continue;
        }
        let s = stats.entry(keys[run_start]).or_insert(KeyStat { pixels: 0, interior: 0, first: run_start });
        s.pixels += k - run_start;
        s.interior += interior[run_start..k].iter().filter(|&&b| b).count();
        run_start = k;
    }
    stats
}

/// The in-bounds 8-neighbours of pixel `(i, j)`.
fn neighbours8(i: usize, j: usize, nx: usize, ny: usize) -> impl Iterator<Item = usize> {
    let (i, j) = (i as isize, j as isize);
    (-1..=1isize)
        .flat_map(move |dj| (-1..=1isize).map(move |di| (i + di, j + dj)))
        .filter(move |&(a, b)| (a, b) != (i, j) && a >= 0 && b >= 0 && a < nx as isize && b < ny as isize)
        .map(move |(a, b)| b as usize * nx + a as usize)
}

/// The in-bounds 4-neighbours of pixel `k`.
fn neighbours4(k: usize, nx: usize, ny: usize) -> impl Iterator<Item = usize> {
    let (i, j) = (k % nx, k / nx);
    [(i > 0).then(|| k - 1), (i + 1 < nx).then(|| k + 1), (j > 0).then(|| k - nx), (j + 1 < ny).then(|| k + nx)]
        .into_iter()
        .flatten()
}

fn luma(c: [f32; 3]) -> f32 {
    0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2]
}

/// Largest per-channel difference.
fn color_distance(a: [f32; 3], b: [f32; 3]) -> f32 {
    (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f32::max)
}

/// The levels of a mask without a table: its label colours by increasing luma.
fn luma_classes(stats: &HashMap<u64, KeyStat>) -> Result<Vec<Class>, EdenError> {
    let mut labels: Vec<u64> =
        stats.iter().filter(|(k, s)| **k != TRANSPARENT && s.interior > 0).map(|(&k, _)| k).collect();
    labels.sort_by(|&a, &b| luma(key_color(a)).total_cmp(&luma(key_color(b))).then(a.cmp(&b)));
    if labels.len() > MAX_LABEL_LEVELS + 1 {
        return Err(EdenError::InvalidLabelMap {
            reason: format!(
                "{} colours form regions; a label map has at most {} (is this a continuous image?)",
                labels.len(),
                MAX_LABEL_LEVELS + 1
            ),
        });
    }
    // Transparency that forms a region is the outside: nothing was drawn there.
    let transparent = stats.get(&TRANSPARENT).is_some_and(|s| s.interior > 0);
    if labels.len() + usize::from(transparent) < 2 {
        let (others, pixels) =
            stats.values().filter(|s| s.interior == 0).fold((0, 0), |(n, p), s| (n + 1, p + s.pixels));
        return Err(EdenError::InvalidLabelMap {
            reason: format!(
                "fewer than two colours form regions (3 × 3 pixels or more): no region to grow; the image's {others} \
                 other colours ({pixels} pixels) are thin lines, edge blends or specks: fill the regions"
            ),
        });
    }
    let mut classes: Vec<Class> =
        labels.into_iter().map(|k| Class { color: key_color(k), height: None, depression: false }).collect();
    if transparent {
        classes.insert(0, Class { color: [0.0; 3], height: None, depression: false });
    }
    Ok(classes)
}

/// The levels of a table, checked.
fn table_classes(table: &[LabelLevel]) -> Result<Vec<Class>, EdenError> {
    let invalid = |reason: String| Err(EdenError::InvalidLabelMap { reason });
    if table.len() < 2 {
        return invalid(format!("a label table needs the outside and at least one level, got {} rows", table.len()));
    }
    if table.len() > MAX_LABEL_LEVELS + 1 {
        return invalid(format!("{} table rows; at most {}", table.len(), MAX_LABEL_LEVELS + 1));
    }
    if table[0].depression {
        return invalid("table row 0 is the outside of Ω and cannot be a depression".into());
    }
    for (k, row) in table.iter().enumerate() {
        if row.color.iter().any(|v| !(0.0..=1.0).contains(v)) {
            return invalid(format!("table row {k}: colour {:?} outside [0, 1]", row.color));
        }
        if let Some((other, _)) =
            table[..k].iter().enumerate().find(|(_, o)| color_distance(o.color, row.color) <= COLOR_TOLERANCE)
        {
            return invalid(format!("table rows {other} and {k} have the same colour {}", hex(row.color)));
        }
    }
    Ok(table.iter().map(|r| Class { color: r.color, height: r.height, depression: r.depression }).collect())
}

/// The level of each label colour (and of transparency: the outside).
fn assign_keys(
    grid: &GridSpec,
    stats: &HashMap<u64, KeyStat>,
    classes: &[Class],
    table: bool,
) -> Result<HashMap<u64, u16>, EdenError> {
    let mut out = HashMap::new();
    let mut labels: Vec<(&u64, &KeyStat)> = stats.iter().filter(|(_, s)| s.interior > 0).collect();
    labels.sort_by_key(|(k, _)| **k);
    for (&k, s) in labels {
        if k == TRANSPARENT {
            out.insert(k, 0);
            continue;
        }
        let color = key_color(k);
        let nearest = (0..classes.len())
            .min_by(|&a, &b| {
                color_distance(classes[a].color, color).total_cmp(&color_distance(classes[b].color, color))
            })
            .unwrap_or(0);
        if table && color_distance(classes[nearest].color, color) > COLOR_TOLERANCE {
            let p = grid.position(s.first % grid.nx(), s.first / grid.nx());
            return Err(EdenError::InvalidLabelMap {
                reason: format!(
                    "colour {} covers {} pixels (one at ({}, {})) but no row of the label table lists it \
                     (nearest: {}); add a row for it",
                    hex(color),
                    s.pixels,
                    p.x,
                    p.y,
                    hex(classes[nearest].color)
                ),
            });
        }
        out.insert(k, nearest as u16);
    }
    if stats.contains_key(&TRANSPARENT) {
        out.insert(TRANSPARENT, 0);
    }
    Ok(out)
}

/// `#rrggbb`, 8 bits a channel.
pub fn hex(c: [f32; 3]) -> String {
    let b = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    format!("#{:02x}{:02x}{:02x}", b(c[0]), b(c[1]), b(c[2]))
}

/// Gives every unlabelled pixel, layer by layer outward from the labelled ones, the level of the
/// neighbouring labelled pixel nearest in colour (ties: the lower level). Returns how many.
fn snap(grid: &GridSpec, rgba: &[[f32; 4]], classes: &[Class], class: &mut [u16]) -> usize {
    let (nx, ny) = (grid.nx(), grid.ny());
    let coords = |k: usize| (k % nx, k / nx);
    let mut queued = vec![false; class.len()];
    let mut layer: Vec<usize> = (0..class.len())
        .filter(|&k| {
            let (i, j) = coords(k);
            class[k] == UNSET && neighbours8(i, j, nx, ny).any(|q| class[q] != UNSET)
        })
        .collect();
    for &k in &layer {
        queued[k] = true;
    }
    let mut snapped = 0;
    while !layer.is_empty() {
        let picks: Vec<u16> = layer
            .iter()
            .map(|&k| {
                let (i, j) = coords(k);
                let own = [rgba[k][0], rgba[k][1], rgba[k][2]];
                let mut best = (f32::INFINITY, UNSET);
                for q in neighbours8(i, j, nx, ny).filter(|&q| class[q] != UNSET) {
                    let d = color_distance(classes[class[q] as usize].color, own);
                    if d < best.0 || (d == best.0 && class[q] < best.1) {
                        best = (d, class[q]);
                    }
                }
                best.1
            })
            .collect();
        for (&k, &c) in layer.iter().zip(&picks) {
            class[k] = c;
        }
        snapped += layer.len();
        let mut next = Vec::new();
        for &k in &layer {
            let (i, j) = coords(k);
            for q in neighbours8(i, j, nx, ny) {
                if class[q] == UNSET && !queued[q] {
                    queued[q] = true;
                    next.push(q);
                }
            }
        }
        next.sort_unstable();
        layer = next;
    }
    snapped
}

/// 8-connected patches of one level: a patch id per pixel, each patch's size and level.
fn patches(grid: &GridSpec, class: &[u16]) -> (Vec<u32>, Vec<usize>, Vec<u16>) {
    let (nx, ny) = (grid.nx(), grid.ny());
    let mut id = vec![u32::MAX; class.len()];
    let (mut sizes, mut levels) = (Vec::new(), Vec::new());
    let mut stack = Vec::new();
    for start in 0..class.len() {
        if id[start] != u32::MAX {
            continue;
        }
        let p = sizes.len() as u32;
        let mut size = 0;
        id[start] = p;
        stack.push(start);
        let c = class[start];
        while let Some(k) = stack.pop() {
            size += 1;
            let (i, j) = (k % nx, k / nx);
            let mut visit = |q: usize| {
                if id[q] == u32::MAX && class[q] == c {
                    id[q] = p;
                    stack.push(q);
                }
            };
            if i > 0 && j > 0 && i + 1 < nx && j + 1 < ny {
                for q in [k - nx - 1, k - nx, k - nx + 1, k - 1, k + 1, k + nx - 1, k + nx, k + nx + 1] {
                    visit(q);
                }
            } else {
                neighbours8(i, j, nx, ny).for_each(visit);
            }
        }
        sizes.push(size);
        levels.push(class[start]);
    }
    (id, sizes, levels)
}

/// Root of patch `p` among merged patches (with path halving).
fn find(parent: &mut [u32], mut p: u32) -> u32 {
    while parent[p as usize] != p {
        let up = parent[parent[p as usize] as usize];
        parent[p as usize] = up;
        p = up;
    }
    p
}

/// Merges patches under `min` pixels, smallest first, into the patch they share most border with
/// (4-neighbour edges; ties: the lower patch id). Returns the first merges and their count.
fn merge_small(grid: &GridSpec, class: &mut [u16], classes: &[Class], min: usize) -> (Vec<MergedPatch>, usize) {
    let (nx, ny) = (grid.nx(), grid.ny());
    let (id, mut sizes, levels) = patches(grid, class);
    let mut small: Vec<u32> = (0..sizes.len() as u32).filter(|&p| sizes[p as usize] < min).collect();
    if small.is_empty() {
        return (Vec::new(), 0);
    }
    small.sort_by_key(|&p| (sizes[p as usize], p));
    let mut members: HashMap<u32, Vec<usize>> = small.iter().map(|&p| (p, Vec::new())).collect();
    for (k, &p) in id.iter().enumerate() {
        if let Some(m) = members.get_mut(&p) {
            m.push(k);
        }
    }
    let mut parent: Vec<u32> = (0..sizes.len() as u32).collect();
    let (mut merged, mut count) = (Vec::new(), 0);
    for p in small {
        if sizes[p as usize] >= min {
            continue;
        }
        let pixels = members.remove(&p).unwrap_or_default();
        let mut shared: HashMap<u32, usize> = HashMap::new();
        for &k in &pixels {
            for q in neighbours4(k, nx, ny) {
                let other = find(&mut parent, id[q]);
                if other != p {
                    *shared.entry(other).or_default() += 1;
                }
            }
        }
        let Some((&into, _)) = shared.iter().max_by(|a, b| a.1.cmp(b.1).then(b.0.cmp(a.0))) else { continue };
        let to = levels[into as usize];
        for &k in &pixels {
            class[k] = to;
        }
        parent[p as usize] = into;
        sizes[into as usize] += pixels.len();
        count += 1;
        if merged.len() < LISTED_MERGES {
            merged.push(MergedPatch {
                at: centroid(grid, &pixels),
                pixels: pixels.len(),
                color: classes[levels[p as usize] as usize].color,
                into: classes[to as usize].color,
            });
        }
        if let Some(m) = members.get_mut(&into) {
            m.extend(pixels);
        }
    }
    (merged, count)
}

/// Mean position of some pixels, in world units.
fn centroid(grid: &GridSpec, pixels: &[usize]) -> DVec2 {
    let sum: DVec2 = pixels.iter().map(|&k| grid.position(k % grid.nx(), k / grid.nx())).sum();
    sum / pixels.len().max(1) as f64
}

/// What [`layout`] makes of the cleaned levels.
struct Layout {
    depth: Vec<u16>,
    depression: Vec<bool>,
    heights: Vec<Option<f64>>,
    colors: Vec<[f32; 3]>,
}

/// Depth and depression flag per pixel, heights and colours per depth: raised levels in order take depths
/// 0, 1, 2…; a depression patch sits one below the level it shares most border with.
fn layout(grid: &GridSpec, class: &[u16], classes: &[Class]) -> Result<Layout, EdenError> {
    let invalid = |reason: String| Err(EdenError::InvalidLabelMap { reason });
    let mut present = vec![false; classes.len()];
    for &c in class {
        present[c as usize] = true;
    }
    present[0] = true;
    let mut depth_of = vec![0u16; classes.len()];
    let mut heights: Vec<Option<f64>> = Vec::new();
    let mut colors = Vec::new();
    let mut last: Option<(usize, f64)> = None;
    for (c, level) in classes.iter().enumerate() {
        if !present[c] {
            // A level merged away (or a table row the image does not use) takes no depth.
            continue;
        }
        if level.depression {
            if let Some(h) = level.height {
                return invalid(format!(
                    "table row {c} is a depression: its rim is the contour of the level around it and its floor \
                     follows the histogram, so its height {h} would be ignored; remove it"
                ));
            }
            continue;
        }
        depth_of[c] = heights.len() as u16;
        colors.push(level.color);
        if let Some(h) = level.height {
            if !h.is_finite() {
                return invalid(format!("table row {c}: height {h} is not finite"));
            }
            if let Some((lc, lh)) = last
                && h <= lh
            {
                return invalid(format!("table row {c}: height {h} is not above row {lc}'s {lh}; rows go upward"));
            }
            last = Some((c, h));
        }
        heights.push(level.height);
    }
    let mut depth: Vec<u16> = class.iter().map(|&c| depth_of[c as usize]).collect();
    let mut depression = vec![false; class.len()];
    if classes.iter().any(|c| c.depression) {
        sink_depressions(grid, class, classes, &depth_of, &mut depth, &mut depression)?;
    }
    Ok(Layout { depth, depression, heights, colors })
}

/// Gives each depression patch the depth one below the raised level around it.
fn sink_depressions(
    grid: &GridSpec,
    class: &[u16],
    classes: &[Class],
    depth_of: &[u16],
    depth: &mut [u16],
    depression: &mut [bool],
) -> Result<(), EdenError> {
    let (nx, ny) = (grid.nx(), grid.ny());
    let (id, _, _) = patches(grid, class);
    let mut around: HashMap<u32, HashMap<u16, usize>> = HashMap::new();
    for k in (0..class.len()).filter(|&k| classes[class[k] as usize].depression) {
        for q in neighbours4(k, nx, ny).filter(|&q| !classes[class[q] as usize].depression) {
            *around.entry(id[k]).or_default().entry(class[q]).or_default() += 1;
        }
    }
    let is_depression = |k: usize| classes[class[k] as usize].depression;
    let mut sunk: HashMap<u32, u16> = HashMap::new();
    for k in (0..class.len()).filter(|&k| is_depression(k)) {
        if let Some(&d) = sunk.get(&id[k]) {
            depth[k] = d;
            depression[k] = true;
            continue;
        }
        let rim = around.get(&id[k]).and_then(|m| m.iter().max_by(|a, b| a.1.cmp(b.1).then(b.0.cmp(a.0))));
        let rim_depth = rim.map_or(0, |(&c, _)| depth_of[c as usize]);
        if rim_depth < 2 {
            let at = grid.position(k % nx, k / nx);
            let place = if rim_depth == 0 { "outside every region" } else { "directly inside the coastline" };
            return Err(EdenError::InvalidLabelMap {
                reason: format!(
                    "the depression colour {} near ({}, {}) lies {place}: a depression's rim is the contour of the \
                     level around it, so it must lie inside a raised level above the coast's",
                    hex(classes[class[k] as usize].color),
                    at.x,
                    at.y,
                ),
            });
        }
        sunk.insert(id[k], rim_depth - 1);
        depth[k] = rim_depth - 1;
        depression[k] = true;
    }
    Ok(())
}
