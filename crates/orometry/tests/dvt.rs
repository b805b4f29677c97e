//! akirmse/mountains' `.dvt` divide-tree files: parsing hand-written files with known answers,
//! writing trees of analysed DEMs and reading them back, and the errors of malformed files and
//! of grids the format cannot hold.

use glam::DVec2;
use proptest::prelude::*;
use relief_heightfield::{Crs, GridSpec, Heightfield};
use relief_orometry::{AnalysisOptions, DivideTree, Dvt, DvtGrid, OrometryError, analyze};

const SMALL: &str = "# a comment\n\
G,36.000000,-85.000000,1200,1200,37.000000,-84.000000\n\
P,1,704,321,500.00\n\
P,2,710,330,450.50\n\
P,3,700,340,420.00\n\
S,1,p,707,325,400.00\n\
S,2,b,705,335,300.00\n\
S,3,p,702,338,390.25\n\
N,0,-1,-1\n\
N,1,-1,-1\n\
N,2,1,1\n\
N,3,2,3\n";

#[test]
fn a_hand_written_file_gives_its_peaks_saddles_and_edges() {
    let dvt = Dvt::parse(SMALL).unwrap();
    let tree = &dvt.tree;
    assert_eq!(tree.peaks.len(), 3);
    // Sample (704, 321) lies at lon −85 + 704/1200, lat 37 − 321/1200.
    let p = tree.peaks[0].position;
    assert!((p.x - (-85.0 + 704.0 / 1200.0)).abs() < 1e-12 && (p.y - (37.0 - 321.0 / 1200.0)).abs() < 1e-12);
    assert_eq!(tree.peaks[1].elevation, 450.5);
    // Two edges, saddle 2 (a basin saddle on no edge) dropped.
    assert_eq!(tree.saddles.len(), 2);
    assert_eq!(tree.saddles[0].peaks, [1, 0]);
    assert_eq!(tree.saddles[0].elevation, 400.0);
    assert_eq!(tree.saddles[1].peaks, [2, 1]);
    assert_eq!(tree.saddles[1].elevation, 390.25);
    let s = tree.saddles[1].position;
    assert!((s.x - (-85.0 + 702.0 / 1200.0)).abs() < 1e-12 && (s.y - (37.0 - 338.0 / 1200.0)).abs() < 1e-12);
    assert_eq!((dvt.unlinked_saddles, dvt.runoffs), (1, 0));
    // Prominences on the tree: 3 drops to the col at 390.25, 2 to the col at 400.
    let oro = tree.orometry(0.0);
    assert_eq!(oro.prominence[2], 420.0 - 390.25);
    assert_eq!(oro.prominence[1], 50.5);
}

#[test]
fn written_files_root_each_tree_at_its_highest_peak_on_the_same_lattice() {
    let dvt = Dvt::parse(SMALL).unwrap();
    let text = dvt.to_string();
    let lines: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(lines[0], "G,36.000000,-85.000000,1200,1200,37.000000,-84.000000");
    assert_eq!(&lines[1..4], ["P,1,704,321,500.00", "P,2,710,330,450.50", "P,3,700,340,420.00"]);
    assert_eq!(&lines[4..6], ["S,1,p,707,325,400.00", "S,2,p,702,338,390.25"]);
    assert_eq!(&lines[6..], ["N,0,-1,-1", "N,1,-1,-1", "N,2,1,1", "N,3,2,2"]);
    assert_eq!(Dvt::parse(&text).unwrap(), Dvt { unlinked_saddles: 0, ..dvt });
}

/// A geographic grid of 3″ samples on akirmse's canvas, and its analysed tree.
fn geographic(nx: usize, ny: usize, z: &[f32]) -> (Heightfield, DivideTree) {
    let cell = 1.0 / 1200.0;
    let grid =
        GridSpec::geographic(nx, ny, DVec2::new(-84.5 + 3.0 * cell, 36.25 + 7.0 * cell), DVec2::splat(cell)).unwrap();
    let dem = Heightfield::from_samples(grid, z.to_vec()).unwrap();
    let tree = DivideTree::from_orometry(&analyze(&dem, &AnalysisOptions::default()).unwrap());
    (dem, tree)
}

/// The tree's edges as sets: `(lower peak, higher peak, saddle cell, elevation)`.
fn edges(tree: &DivideTree, grid: &DvtGrid) -> Vec<([u32; 2], [i64; 2], f64)> {
    let mut e: Vec<_> = tree
        .saddles
        .iter()
        .map(|s| {
            let mut p = s.peaks;
            p.sort_unstable();
            (p, grid.sample(s.position), s.elevation)
        })
        .collect();
    e.sort_by(|a, b| a.partial_cmp(b).unwrap());
    e
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Writing an analysed tree and reading it back gives the same peaks (at the same samples,
    /// elevations to the file's centimetres) and the same ridges through the same saddles.
    #[test]
    fn analysed_trees_survive_a_round_trip(
        (nx, ny, z) in (3usize..14, 3usize..14).prop_flat_map(|(nx, ny)| {
            (Just(nx), Just(ny), proptest::collection::vec(0u16..200, nx * ny))
        })
    ) {
        let z: Vec<f32> = z.into_iter().map(|v| f32::from(v) * 0.25).collect();
        let (dem, tree) = geographic(nx, ny, &z);
        let grid = DvtGrid::for_grid(dem.grid(), None).unwrap();
        let back = Dvt::parse(&Dvt { grid, tree: tree.clone(), unlinked_saddles: 0, runoffs: 0 }.to_string()).unwrap();
        prop_assert_eq!(back.grid, grid);
        prop_assert_eq!(back.tree.peaks.len(), tree.peaks.len());
        for (a, b) in tree.peaks.iter().zip(&back.tree.peaks) {
            prop_assert_eq!(grid.sample(a.position), grid.sample(b.position));
            prop_assert!((a.position - b.position).length() < 1e-9);
            prop_assert!((a.elevation - b.elevation).abs() < 0.005);
        }
        prop_assert_eq!(edges(&tree, &grid), edges(&back.tree, &grid));
    }
}

#[test]
fn a_geographic_grid_sits_on_the_whole_degree_canvas() {
    let (dem, _) = geographic(4, 3, &[0.0; 12]);
    let grid = DvtGrid::for_grid(dem.grid(), None).unwrap();
    assert_eq!(
        grid,
        DvtGrid::Degrees {
            min_lat: 36.0,
            min_lng: -85.0,
            max_lat: 37.0,
            max_lng: -84.0,
            samples_per_degree: [1200, 1200]
        }
    );
    // Sample (0, 0) of the grid, its south-west corner at lon −84.5 + 3/1200, lat 36.25 + 7/1200,
    // is column 0.5·1200 + 3 and row 0.75·1200 − 7 of the canvas.
    assert_eq!(grid.sample(dem.grid().position(0, 0)), [603, 893]);
}

#[test]
fn utm_grids_keep_their_zone_and_metres() {
    let grid = GridSpec::new(5, 4, DVec2::new(500_015.0, 4_000_015.0), DVec2::splat(30.0)).unwrap();
    let crs = Crs::from_epsg(32617).unwrap();
    let dvt = DvtGrid::for_grid(&grid, Some(&crs)).unwrap();
    assert_eq!(
        dvt,
        DvtGrid::Utm { zone: 17, min: [500_015, 4_000_015], max: [500_135, 4_000_105], metres_per_sample: 30.0 }
    );
    assert_eq!(dvt.sample(grid.position(1, 0)), [1, 3]);
    assert_eq!(dvt.position(1, 3), grid.position(1, 0));
    let text = "U,17,500015,4000015,500135,4000105,30.000000\nP,1,1,3,10.00\nN,0,-1,-1\nN,1,-1,-1\n";
    assert_eq!(Dvt::parse(text).unwrap().tree.peaks[0].position, DVec2::new(500_045.0, 4_000_015.0));
}

#[test]
fn grids_the_format_cannot_hold_are_refused_with_the_reason() {
    let local = GridSpec::new(5, 4, DVec2::ZERO, DVec2::splat(30.0)).unwrap();
    let err = DvtGrid::for_grid(&local, None).unwrap_err().to_string();
    assert!(err.contains("local units") && err.contains("GeoJSON"), "{err}");
    let lambert = Crs::from_epsg(2154).unwrap();
    assert!(matches!(DvtGrid::for_grid(&local, Some(&lambert)), Err(OrometryError::Dvt(_))));
    let odd = GridSpec::geographic(50, 50, DVec2::new(10.0, 40.0), DVec2::splat(0.0007)).unwrap();
    let err = DvtGrid::for_grid(&odd, None).unwrap_err().to_string();
    assert!(err.contains("whole number of samples per degree"), "{err}");
    let off = GridSpec::new(5, 4, DVec2::new(500_015.5, 4_000_015.0), DVec2::splat(30.0)).unwrap();
    let err = DvtGrid::for_grid(&off, Some(&Crs::from_epsg(32617).unwrap())).unwrap_err().to_string();
    assert!(err.contains("whole metres"), "{err}");
}

#[test]
fn malformed_files_name_the_line_and_the_problem() {
    let cases = [
        ("", "no grid line"),
        ("P,1,2,3,4\n", "first line must describe the grid"),
        ("G,36,-85,0,1200,37,-84\n", "samples per degree must be positive"),
        ("G,36,-85,1200\n", "first line must describe the grid"),
        ("U,17,1,2\n", "first line must describe the grid"),
        ("U,0,500000,4000000,500100,4000100,30\n", "zone must be 1–60"),
        ("U,17,500000,4000000,500100,4000100,0\n", "spacing positive"),
        ("G,36,-85,1200,1200,37,-84\nP,1,x,3,4.0\n", "line 2: column `x`"),
        ("G,36,-85,1200,1200,37,-84\nP,1,2,3\n", "line 2: `P,1,2,3` has 4 fields, not 5"),
        ("G,36,-85,1200,1200,37,-84\nP,1,2,3,NaN\n", "not finite"),
        ("G,36,-85,1200,1200,37,-84\nQ,1\n", "unknown line kind `Q`"),
        ("G,36,-85,1200,1200,37,-84\nP,1,2,3,4\nN,0,-1,-1\nN,1,-1,-1\nN,2,-1,-1\n", "3 N lines for 1 peaks"),
        ("G,36,-85,1200,1200,37,-84\nP,1,2,3,4\nP,2,2,4,5\nN,0,-1,-1\nN,1,2,1\nN,2,-1,-1\n", "2 peaks and 0 saddles"),
        (
            "G,36,-85,1200,1200,37,-84\nP,1,2,3,4\nP,2,2,4,5\nP,3,2,5,6\nS,1,p,2,6,1\nN,0,-1,-1\nN,1,2,1\nN,2,3,1\nN,3,-1,-1\n",
            "saddle 1 joins more than one pair",
        ),
        ("G,36,-85,1200,1200,37,-84\nP,1,2,3,4\nP,2,2,4,5\nS,1,p,2,6,9\nN,0,-1,-1\nN,1,2,1\nN,2,-1,-1\n", "above peak"),
        ("G,36,-85,1200,1200,37,-84\nP,1,2,3,4\nN,0,-1,-1\nN,1,2,-1\n", "needs a saddle"),
    ];
    for (text, expected) in cases {
        let err = Dvt::parse(text).unwrap_err();
        assert!(matches!(err, OrometryError::Dvt(_)), "{text:?}: {err:?}");
        assert!(err.to_string().contains(expected), "{text:?}: {err} does not say {expected:?}");
    }
}

#[test]
fn runoffs_and_old_one_degree_headers_are_accepted() {
    let text = "G,36,-85,1200,1200\nP,1,2,3,4\nR,0,0,3,2.0,1,0\nN,0,-1,-1\nN,1,-1,-1\nE,0,1\n";
    let dvt = Dvt::parse(text).unwrap();
    assert_eq!(dvt.runoffs, 1);
    assert!(matches!(dvt.grid, DvtGrid::Degrees { max_lat: 37.0, max_lng: -84.0, .. }));
}

#[test]
fn every_utm_family_names_its_zone() {
    let grid = GridSpec::new(5, 4, DVec2::new(500_010.0, 4_000_020.0), DVec2::splat(10.0)).unwrap();
    for (epsg, zone) in [(32617, 17), (32733, 33), (26910, 10), (25832, 32)] {
        let dvt = DvtGrid::for_grid(&grid, Some(&Crs::from_epsg(epsg).unwrap())).unwrap();
        assert!(matches!(dvt, DvtGrid::Utm { zone: z, .. } if z == zone), "EPSG:{epsg}: {dvt:?}");
    }
    // Corners a hundredth of a cell off whole metres are rounded; square cells only.
    let near = GridSpec::new(5, 4, DVec2::new(500_010.05, 4_000_020.0), DVec2::splat(10.0)).unwrap();
    let crs = Crs::from_epsg(32617).unwrap();
    assert!(matches!(DvtGrid::for_grid(&near, Some(&crs)).unwrap(), DvtGrid::Utm { min: [500_010, 4_000_020], .. }));
    let oblong = GridSpec::new(5, 4, DVec2::new(500_010.0, 4_000_020.0), DVec2::new(10.0, 20.0)).unwrap();
    let err = DvtGrid::for_grid(&oblong, Some(&crs)).unwrap_err().to_string();
    assert!(err.contains("square cells"), "{err}");
}

#[test]
fn a_canvas_edge_a_rounding_error_past_a_whole_degree_stays_on_it() {
    // The top row a hair above 37° N: the canvas still ends at 37°, and that row is row 0.
    let cell = 1.0 / 1200.0;
    let (nx, ny) = (4, 30);
    let origin = DVec2::new(-84.5, 37.0 + 1e-12 - (ny - 1) as f64 * cell);
    let grid = GridSpec::geographic(nx, ny, origin, DVec2::splat(cell)).unwrap();
    let dvt = DvtGrid::for_grid(&grid, None).unwrap();
    assert!(matches!(dvt, DvtGrid::Degrees { max_lat: 37.0, min_lat: 36.0, .. }), "{dvt:?}");
    assert_eq!(dvt.sample(grid.position(0, ny - 1)), [600, 0]);
    // Columns on the lattice but rows half a sample off it: the grid's own corners, not the canvas.
    let off = GridSpec::geographic(nx, ny, origin + DVec2::new(0.0, 0.5 * cell), DVec2::splat(cell)).unwrap();
    let dvt = DvtGrid::for_grid(&off, None).unwrap();
    assert!(matches!(dvt, DvtGrid::Degrees { min_lng, .. } if min_lng == -84.5), "{dvt:?}");
    assert_eq!(dvt.sample(off.position(0, ny - 1)), [0, 0]);
}
