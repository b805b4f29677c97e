//! Label masks as paint programs save them: speckle, anti-aliased edges, palette variants,
//! colours with transparency, colour tables with heights and depressions.

use glam::DVec2;
use relief_eden_growth::{
    EdenError, Graph, GraphOptions, LabelLevel, LabelMap, MaskOptions, Sampling, Uniform, grow, hex,
};
use relief_tin::heightfield::GridSpec;

const N: usize = 200;

fn grid() -> GridSpec {
    GridSpec::new(N, N, DVec2::ZERO, DVec2::splat(10.0)).unwrap()
}

fn gray(v: f32) -> [f32; 4] {
    [v, v, v, 1.0]
}

/// An island (gray 0.5, radius 80 px) with a range inside it (white, radius 30 px), on black.
fn island(at: impl Fn(f64) -> f32) -> Vec<[f32; 4]> {
    (0..N * N)
        .map(|k| {
            let d = DVec2::new((k % N) as f64, (k / N) as f64).distance(DVec2::splat(100.0));
            gray(at(d))
        })
        .collect()
}

fn hard_island() -> Vec<[f32; 4]> {
    island(|d| {
        if d < 30.0 {
            1.0
        } else if d < 80.0 {
            0.5
        } else {
            0.0
        }
    })
}

fn options(levels: Option<Vec<LabelLevel>>) -> MaskOptions {
    MaskOptions { levels, sampling: Sampling::Particles(1_000) }
}

#[test]
fn speckle_is_snapped_or_merged_and_listed() {
    let mut pixels = hard_island();
    // A single stray pixel of gray 49 and an 11-pixel clump of gray 102 inside the island: as
    // separate levels they hold no node and stop generation.
    pixels[60 * N + 60] = gray(49.0 / 255.0);
    for k in [0, 1, 2, 3, N, N + 1, N + 2, N + 3, 2 * N, 2 * N + 1, 2 * N + 2] {
        pixels[150 * N + 100 + k] = gray(102.0 / 255.0);
    }
    let labels = LabelMap::from_mask(grid(), &pixels, &options(None)).unwrap();
    assert_eq!(labels.max_level(), 2, "outside, island, range");
    let cleaning = labels.cleaning().unwrap();
    assert_eq!(cleaning.colors.iter().map(|&c| hex(c)).collect::<Vec<_>>(), ["#000000", "#808080", "#ffffff"]);
    assert_eq!(cleaning.snapped_pixels, 1, "the lone pixel has no 3 × 3 block: an edge blend or a speck");
    assert_eq!(cleaning.merged_count, 1);
    let merged = &cleaning.merged[0];
    assert_eq!((merged.pixels, hex(merged.color), hex(merged.into)), (11, "#666666".into(), "#808080".into()));
    assert!(merged.at.distance(DVec2::new(1015.0, 1505.0)) < 10.0, "{:?}", merged.at);
    assert!(cleaning.min_patch_pixels > 11);
    // Both speck places now belong to the island, and the map grows.
    assert_eq!(labels_depth(&labels, 60, 60), 1);
    assert_eq!(labels_depth(&labels, 101, 151), 1);
    let graph = Graph::from_labels(&labels, &GraphOptions::particles(5_000)).unwrap();
    grow(&graph, &Uniform, 1).unwrap().check_invariants(&graph).unwrap();
}

#[test]
fn a_clump_the_sampling_holds_stays_a_level() {
    // The same 11-pixel clump at a radius of a tenth of a pixel is a region the graph can hold.
    let mut pixels = hard_island();
    for k in [0, 1, 2, N, N + 1, N + 2, 2 * N, 2 * N + 1, 2 * N + 2, 3 * N, 3 * N + 1] {
        pixels[150 * N + 100 + k] = gray(102.0 / 255.0);
    }
    let fine = MaskOptions { levels: None, sampling: Sampling::Radius(1.0) };
    let labels = LabelMap::from_mask(grid(), &pixels, &fine).unwrap();
    assert_eq!(labels.cleaning().unwrap().merged_count, 0);
    assert_eq!(labels.max_level(), 3, "outside, clump (darker than the island), island, range");
    assert_eq!(labels.cleaning().unwrap().colors.len(), 4);
    assert_eq!(labels_depth(&labels, 101, 151), 1);
}

#[test]
fn anti_aliased_edges_split_between_their_two_sides() {
    // Coverage-blended edges, two pixels wide, as a paint program's anti-aliased brush leaves them.
    let blend = |d: f64, r: f64| ((r + 1.0 - d) / 2.0).clamp(0.0, 1.0);
    let pixels = island(|d| (0.5 * blend(d, 80.0) + 0.5 * blend(d, 30.0)) as f32);
    let labels = LabelMap::from_mask(grid(), &pixels, &options(None)).unwrap();
    let cleaning = labels.cleaning().unwrap();
    assert_eq!(cleaning.colors.len(), 3, "{:?}", cleaning.colors);
    assert!(cleaning.snapped_pixels > 500, "{}", cleaning.snapped_pixels);
    assert_eq!(cleaning.merged_count, 0);
    // A blend pixel joins the side whose colour it is closer to.
    for (k, p) in pixels.iter().enumerate() {
        let (i, j) = (k % N, k / N);
        let v = p[0];
        let expected = match v {
            v if v < 0.23 => 0,
            v if v > 0.27 && v < 0.73 => 1,
            v if v > 0.77 => 2,
            _ => continue,
        };
        let d = labels_depth(&labels, i, j);
        assert_eq!(d, expected, "pixel ({i}, {j}) of value {v}");
    }
}

/// A pixel's depth, read through the map's own classification of a point at its centre.
fn labels_depth(labels: &LabelMap, i: usize, j: usize) -> u16 {
    labels.depth_at(labels.grid().position(i, j))
}

#[test]
fn palette_variants_of_one_gray_join_its_table_row() {
    // The island painted half in gray 128 and half in 127 (two palette entries), with a table.
    let mut pixels = hard_island();
    for (k, p) in pixels.iter_mut().enumerate() {
        if k % N < 100 && p[0] == 0.5 {
            *p = gray(127.0 / 255.0);
        }
    }
    let table = vec![
        LabelLevel { height: Some(0.0), ..LabelLevel::new([0.0; 3]) },
        LabelLevel { height: Some(10.0), ..LabelLevel::new([0.5; 3]) },
        LabelLevel { height: Some(400.0), ..LabelLevel::new([1.0; 3]) },
    ];
    let labels = LabelMap::from_mask(grid(), &pixels, &options(Some(table))).unwrap();
    assert_eq!(labels.max_level(), 2);
    assert_eq!(labels_depth(&labels, 40, 100), 1);
    assert_eq!(labels_depth(&labels, 160, 100), 1);
    assert_eq!(labels.level_heights(), &[Some(0.0), Some(10.0), Some(400.0)]);
    // Without a table both grays form regions, so both are levels.
    let untabled = LabelMap::from_mask(grid(), &pixels, &options(None)).unwrap();
    assert_eq!(untabled.max_level(), 3);
}

#[test]
fn colours_on_transparency_with_heights_and_a_crater() {
    let (red, green, blue) = ([1.0, 0.0, 0.0], [0.0, 0.6, 0.0], [0.0, 0.0, 1.0]);
    let rgba = |c: [f32; 3], a: f32| [c[0], c[1], c[2], a];
    // Transparent sea, a green island, a red range in it, a blue crater in the range; the edges
    // fade out in alpha as an anti-aliased layer does.
    let pixels: Vec<[f32; 4]> = (0..N * N)
        .map(|k| {
            let d = DVec2::new((k % N) as f64, (k / N) as f64).distance(DVec2::splat(100.0));
            match d {
                d if d < 10.0 => rgba(blue, 1.0),
                d if d < 40.0 => rgba(red, 1.0),
                d if d < 80.0 => rgba(green, 1.0),
                d if d < 81.0 => rgba(green, 0.3),
                _ => [0.0; 4],
            }
        })
        .collect();
    let table = vec![
        LabelLevel::new([0.0; 3]),
        LabelLevel { height: Some(0.0), ..LabelLevel::new(green) },
        LabelLevel { height: Some(300.0), ..LabelLevel::new(red) },
        LabelLevel { depression: true, ..LabelLevel::new(blue) },
    ];
    let labels = LabelMap::from_mask(grid(), &pixels, &options(Some(table.clone()))).unwrap();
    assert_eq!(labels.max_level(), 2);
    assert_eq!(labels.level_heights(), &[None, Some(0.0), Some(300.0)]);
    assert_eq!(labels_depth(&labels, 100, 100), 1, "the crater's floor lies one level below its rim");
    assert_eq!(labels_depth(&labels, 100, 130), 2);
    assert_eq!(labels_depth(&labels, 100, 150), 1);
    assert_eq!(labels_depth(&labels, 100, 180), 0, "alpha 0.3 is outside");
    let graph = Graph::from_labels(&labels, &GraphOptions::particles(5_000).with_seed(2)).unwrap();
    let crater = graph.tin().points().iter().position(|p| p.distance(DVec2::splat(1000.0)) < 30.0).unwrap();
    assert!(graph.depressions()[crater], "crater nodes are marked depressions");
    assert_eq!(graph.filled_nodes(), 0, "a marked crater is kept, not filled");
    let growth = grow(&graph, &Uniform, 3).unwrap();
    growth.check_invariants(&graph).unwrap();

    // Without the crater row the blue is a colour no row lists.
    let err = LabelMap::from_mask(grid(), &pixels, &options(Some(table[..3].to_vec()))).unwrap_err();
    assert!(err.to_string().contains("#0000ff") && err.to_string().contains("no row"), "{err}");
    // A crater directly in the coast's level has no level for its floor.
    let mut shallow = table.clone();
    shallow.swap(2, 3);
    shallow[2].height = None;
    let in_coast: Vec<[f32; 4]> =
        pixels.iter().map(|p| if p[0] == 1.0 && p[1] == 0.0 { rgba(green, 1.0) } else { *p }).collect();
    let err = LabelMap::from_mask(grid(), &in_coast, &options(Some(shallow))).unwrap_err();
    assert!(err.to_string().contains("directly inside the coastline"), "{err}");
    // A depression's height would be ignored: refused, naming the row.
    let mut high = table.clone();
    high[3].height = Some(100.0);
    let err = LabelMap::from_mask(grid(), &pixels, &options(Some(high))).unwrap_err();
    assert!(err.to_string().contains("row 3 is a depression"), "{err}");
    // Heights go upward with the rows.
    let mut down = table;
    down[2].height = Some(-5.0);
    let err = LabelMap::from_mask(grid(), &pixels, &options(Some(down))).unwrap_err();
    assert!(err.to_string().contains("row 2: height -5 is not above row 1"), "{err}");
}

#[test]
fn strokes_alone_are_no_region() {
    // One-pixel lines in several grays on black: sketches, not filled regions.
    let pixels: Vec<[f32; 4]> = (0..N * N)
        .map(|k| {
            let (i, j) = (k % N, k / N);
            if i == j || i == 50 { gray(0.3 + (i % 3) as f32 * 0.2) } else { gray(0.0) }
        })
        .collect();
    let err = LabelMap::from_mask(grid(), &pixels, &options(None)).unwrap_err();
    assert!(matches!(err, EdenError::InvalidLabelMap { .. }));
    assert!(err.to_string().contains("thin lines"), "{err}");
}

#[test]
fn a_level_too_thin_for_the_sampling_names_a_count_that_holds_it() {
    // A 4 × 4 pixel summit: big enough to keep, too small for most samplings of 300 nodes.
    let pixels: Vec<[f32; 4]> = hard_island()
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let (i, j) = (k % N, k / N);
            if (98..102).contains(&i) && (98..102).contains(&j) {
                gray(1.0)
            } else if p[0] == 1.0 {
                gray(0.5)
            } else {
                *p
            }
        })
        .collect();
    let coarse = MaskOptions { levels: None, sampling: Sampling::Radius(1.0) };
    let labels = LabelMap::from_mask(grid(), &pixels, &coarse).unwrap();
    let refused: Vec<(u64, EdenError)> = (0..20)
        .filter_map(|seed| {
            Graph::from_labels(&labels, &GraphOptions::particles(300).with_seed(seed)).err().map(|e| (seed, e))
        })
        .collect();
    assert!(refused.len() >= 10, "{} of 20 seeds refused", refused.len());
    let (seed, err) = &refused[0];
    let EdenError::LevelTooSmall { level: 2, particles, needed_radius, .. } = *err else { panic!("{err}") };
    assert!(err.to_string().contains(&format!("about {particles} particles")), "{err}");
    assert!(needed_radius > 10.0 && needed_radius < 25.0, "{needed_radius}");
    Graph::from_labels(&labels, &GraphOptions::particles(particles as usize).with_seed(*seed)).unwrap();
    let at_radius = GraphOptions { sampling: Sampling::Radius(needed_radius), ..GraphOptions::particles(1) };
    for seed in 0..5 {
        Graph::from_labels(&labels, &at_radius.with_seed(seed)).unwrap();
    }
}

mod properties {
    use proptest::prelude::*;

    use super::*;

    /// Depth patches (8-connected) of a map and their sizes.
    fn patch_sizes(labels: &LabelMap) -> Vec<usize> {
        let g = labels.grid();
        let (nx, ny) = (g.nx(), g.ny());
        let depth: Vec<u16> = (0..nx * ny).map(|k| labels.depth_at(g.position(k % nx, k / nx))).collect();
        let mut seen = vec![false; depth.len()];
        let mut sizes = Vec::new();
        for start in 0..depth.len() {
            if seen[start] {
                continue;
            }
            let (mut stack, mut size) = (vec![start], 0);
            seen[start] = true;
            while let Some(k) = stack.pop() {
                size += 1;
                let (i, j) = ((k % nx) as isize, (k / nx) as isize);
                for (di, dj) in [(-1, -1), (0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (0, 1), (1, 1)] {
                    let (a, b) = (i + di, j + dj);
                    if a < 0 || b < 0 || a >= nx as isize || b >= ny as isize {
                        continue;
                    }
                    let q = b as usize * nx + a as usize;
                    if !seen[q] && depth[q] == depth[k] {
                        seen[q] = true;
                        stack.push(q);
                    }
                }
            }
            sizes.push(size);
        }
        sizes
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]

        /// Any small image of a few colours, blocks and noise is a label map or a typed refusal;
        /// a map keeps no patch smaller than the sampling holds, and names one colour per level.
        #[test]
        fn masks_clean_to_patches_the_sampling_holds(
            nx in 3usize..40, ny in 3usize..40,
            blocks in proptest::collection::vec((0usize..40, 0usize..40, 1usize..20, 1usize..20, 0u8..4), 1..6),
            noise in proptest::collection::vec((0usize..1600, 0u8..=255, 0u8..=255), 0..60),
            particles in 20usize..400,
        ) {
            let palette = [0.0, 0.3, 0.6, 1.0];
            let mut pixels = vec![gray(0.0); nx * ny];
            for &(x, y, w, h, c) in &blocks {
                for j in y.min(ny)..(y + h).min(ny) {
                    for i in x.min(nx)..(x + w).min(nx) {
                        pixels[j * nx + i] = gray(palette[c as usize]);
                    }
                }
            }
            for &(k, v, a) in &noise {
                if k < pixels.len() {
                    pixels[k] = [f32::from(v) / 255.0, 0.5, 0.2, f32::from(a) / 255.0];
                }
            }
            let grid = GridSpec::new(nx, ny, DVec2::ZERO, DVec2::ONE).unwrap();
            let options = MaskOptions { levels: None, sampling: Sampling::Particles(particles) };
            match LabelMap::from_mask(grid, &pixels, &options) {
                Err(e) => prop_assert!(matches!(e, EdenError::InvalidLabelMap { .. }), "{e}"),
                Ok(labels) => {
                    let cleaning = labels.cleaning().unwrap();
                    prop_assert_eq!(cleaning.colors.len(), usize::from(labels.max_level()) + 1);
                    prop_assert!(cleaning.merged.iter().all(|m| m.pixels < cleaning.min_patch_pixels));
                    let sizes = patch_sizes(&labels);
                    if sizes.len() > 1 {
                        prop_assert!(sizes.iter().all(|&s| s >= cleaning.min_patch_pixels), "{sizes:?} < {}", cleaning.min_patch_pixels);
                    }
                }
            }
        }
    }
}

#[test]
fn specks_far_apart_name_a_particle_count_that_samples_them() {
    // A 16 × 12 island and a 4 × 4 islet 900 pixels away on a 1024² map: at 50 000 particles the
    // radius over their tiny area would need a hundred million samples over the box they span.
    let grid = GridSpec::new(1024, 1024, DVec2::ZERO, DVec2::ONE).unwrap();
    let depth: Vec<u16> = (0..grid.len())
        .map(|k| {
            let (i, j) = (k % 1024, k / 1024);
            u16::from(
                ((900..916).contains(&i) && (900..912).contains(&j))
                    || ((10..14).contains(&i) && (10..14).contains(&j)),
            )
        })
        .collect();
    let labels = LabelMap::new(grid, depth).unwrap();
    let err = Graph::from_labels(&labels, &GraphOptions::particles(50_000)).unwrap_err();
    let EdenError::SparseDomain { particles, .. } = err else { panic!("{err}") };
    assert!(particles > 10 && particles < 50_000, "{particles}");
    assert!(err.to_string().contains(&format!("use at most {particles} particles")), "{err}");
    let graph = Graph::from_labels(&labels, &GraphOptions::particles(particles as usize)).unwrap();
    assert!(graph.inside_count() > 0);
}

/// A 60 × 40 map: black ground, a big gray (0.5) block and a big white block making both colours
/// labels, and whatever `paint` adds.
fn blocks(paint: impl Fn(usize, usize) -> Option<f32>) -> (GridSpec, Vec<[f32; 4]>) {
    let grid = GridSpec::new(60, 40, DVec2::ZERO, DVec2::ONE).unwrap();
    let pixels = (0..60 * 40)
        .map(|k| {
            let (i, j) = (k % 60, k / 60);
            let v = paint(i, j).unwrap_or(if i >= 50 && j >= 30 {
                0.5
            } else if i >= 50 && j < 8 {
                1.0
            } else {
                0.0
            });
            gray(v)
        })
        .collect();
    (grid, pixels)
}

/// The finest sampling: the smallest patch kept is the 3 × 3 block.
fn fine() -> MaskOptions {
    MaskOptions { levels: None, sampling: Sampling::Radius(0.01) }
}

#[test]
fn merging_keeps_patches_of_the_minimum_size_and_grows_what_it_merges_into() {
    // A 3 × 3 gray block stays; a 2 × 2 one merges.
    let (grid, pixels) = blocks(|i, j| {
        ((5..8).contains(&i) && (5..8).contains(&j) || (20..22).contains(&i) && (5..7).contains(&j)).then_some(0.5)
    });
    let labels = LabelMap::from_mask(grid, &pixels, &fine()).unwrap();
    let cleaning = labels.cleaning().unwrap();
    assert_eq!(cleaning.min_patch_pixels, 9);
    assert_eq!(labels_depth(&labels, 6, 6), 1, "a patch of exactly the minimum size is kept");
    assert_eq!(labels_depth(&labels, 20, 5), 0);
    assert_eq!(cleaning.merged_count, 1);
    // A white pixel inside a ring of eight gray ones: the pixel joins the ring first, which then
    // holds nine pixels and stays.
    let (grid, pixels) = blocks(|i, j| match (i, j) {
        (11, 11) => Some(1.0),
        (10..=12, 10..=12) => Some(0.5),
        _ => None,
    });
    let labels = LabelMap::from_mask(grid, &pixels, &fine()).unwrap();
    assert_eq!(labels_depth(&labels, 11, 11), 1);
    assert_eq!(labels_depth(&labels, 10, 10), 1);
}

#[test]
fn a_speck_joins_the_level_it_shares_most_border_with_and_the_list_stops_at_a_hundred() {
    // A 2 × 2 white speck on the edge of the gray block: six of its eight edges in gray.
    let (grid, pixels) = blocks(|i, j| ((50..52).contains(&i) && (34..36).contains(&j)).then_some(1.0));
    let labels = LabelMap::from_mask(grid, &pixels, &fine()).unwrap();
    assert_eq!(labels_depth(&labels, 50, 34), 1, "into the gray around most of it, not the black");
    assert_eq!(hex(labels.cleaning().unwrap().merged[0].into), "#808080");
    // 130 gray specks of 2 × 2: all merged, the first hundred listed.
    let (grid, pixels) =
        blocks(|i, j| (i < 39 && j < 39 && i % 3 < 2 && j % 3 < 2 && i / 3 + 13 * (j / 3) < 130).then_some(0.5));
    let labels = LabelMap::from_mask(grid, &pixels, &fine()).unwrap();
    let cleaning = labels.cleaning().unwrap();
    assert_eq!((cleaning.merged_count, cleaning.merged.len()), (130, 100));
}

#[test]
fn a_crater_on_two_levels_sinks_below_the_one_around_most_of_it() {
    // Transparent sea, green island, red range; a blue crater straddling the red range's edge,
    // mostly inside it.
    let (red, green, blue) = ([1.0, 0.0, 0.0], [0.0, 0.6, 0.0], [0.0, 0.0, 1.0]);
    let rgba = |c: [f32; 3]| [c[0], c[1], c[2], 1.0];
    let pixels: Vec<[f32; 4]> = (0..N * N)
        .map(|k| {
            let p = DVec2::new((k % N) as f64, (k / N) as f64);
            let d = p.distance(DVec2::splat(100.0));
            if p.distance(DVec2::new(100.0, 135.0)) < 10.0 {
                rgba(blue)
            } else if d < 40.0 {
                rgba(red)
            } else if d < 80.0 {
                rgba(green)
            } else {
                [0.0; 4]
            }
        })
        .collect();
    let table = vec![
        LabelLevel::new([0.0; 3]),
        LabelLevel::new(green),
        LabelLevel::new(red),
        LabelLevel { depression: true, ..LabelLevel::new(blue) },
    ];
    let labels = LabelMap::from_mask(grid(), &pixels, &options(Some(table.clone()))).unwrap();
    // Every crater pixel, the first one met included, sits one level below the red range.
    for (i, j) in [(96, 126), (100, 126), (100, 135), (95, 140), (104, 143)] {
        assert_eq!(labels_depth(&labels, i, j), 1, "({i}, {j})");
    }
    // A crater all in the coast's level is refused, and the message says where it is.
    let coastal: Vec<[f32; 4]> =
        pixels.iter().enumerate().map(|(k, p)| if k % N < 60 && p[0] == 1.0 { rgba(green) } else { *p }).collect();
    let moved: Vec<[f32; 4]> = (0..N * N)
        .map(|k| {
            let p = DVec2::new((k % N) as f64, (k / N) as f64);
            if p.distance(DVec2::new(40.0, 100.0)) < 6.0 {
                rgba(blue)
            } else if p.distance(DVec2::new(40.0, 100.0)) < 30.0 {
                rgba(green)
            } else {
                coastal[k]
            }
        })
        .collect();
    let err = LabelMap::from_mask(grid(), &moved, &options(Some(table))).unwrap_err().to_string();
    assert!(err.contains("directly inside the coastline") && err.contains("near (370, 950)"), "{err}");
}

#[test]
fn a_blend_equally_far_from_two_levels_takes_the_lower() {
    // One pixel of 0.25 between black (left) and gray (right): black, met first, is also lower.
    let (grid, pixels) = blocks(|i, j| ((i, j) == (49, 32)).then_some(0.25));
    let labels = LabelMap::from_mask(grid, &pixels, &fine()).unwrap();
    assert_eq!(labels_depth(&labels, 49, 32), 0);
    // A row of 0.75 between white (below, met first) and gray (above): gray, the lower.
    let (grid, pixels) = blocks(|_, j| match j {
        0..20 => Some(1.0),
        20 => Some(0.75),
        _ => Some(0.5),
    });
    let labels = LabelMap::from_mask(grid, &pixels, &fine()).unwrap();
    let cleaning = labels.cleaning().unwrap();
    assert_eq!(cleaning.colors.len(), 2, "{:?}", cleaning.colors);
    assert_eq!(labels_depth(&labels, 30, 20), 0, "the gray level, the lower of the two");
}
