//! Prominence, key saddles, isolation and the divide tree on hand-built DEMs with known answers,
//! and the invariants of prominence on random DEMs against a brute-force flood from each peak.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use glam::DVec2;
use proptest::prelude::*;
use relief_heightfield::{Extent, GridSpec, Heightfield};
use relief_orometry::{AnalysisOptions, Orometry, OrometryError, ProminenceBase, analyze};

fn grid(nx: usize, ny: usize) -> GridSpec {
    GridSpec::from_extent(nx, ny, Extent::new(DVec2::ZERO, DVec2::new((nx - 1) as f64, (ny - 1) as f64))).unwrap()
}

fn run(dem: &Heightfield) -> Orometry {
    analyze(dem, &AnalysisOptions::default()).unwrap()
}

fn peak_at(o: &Orometry, cell: [usize; 2]) -> &relief_orometry::Peak {
    o.peaks.iter().find(|p| p.cell == cell).unwrap_or_else(|| panic!("no peak at {cell:?}"))
}

#[test]
fn two_cones_joined_by_a_col() {
    let dem = Heightfield::from_fn(grid(61, 21), |p| {
        let a = 100.0 - 6.0 * p.distance(DVec2::new(15.0, 10.0));
        let b = 80.0 - 4.0 * p.distance(DVec2::new(45.0, 10.0));
        a.max(b).max(0.0) as f32
    })
    .unwrap();
    let o = run(&dem);
    assert_eq!(o.peaks.len(), 2);
    let (a, b) = (peak_at(&o, [15, 10]), peak_at(&o, [45, 10]));
    // The col is where the cones meet on the axis: 100 − 6x' = 80 − 4(30 − x') → x' = 4 from... the
    // ground along the axis is the upper envelope; its lowest point between the peaks.
    let col = (0..=60).map(|i| dem.value(i, 10)).skip(15).take(31).fold(f32::INFINITY, f32::min);
    assert!((b.prominence - f64::from(80.0 - col)).abs() < 1e-4, "{} vs {}", b.prominence, 80.0 - col);
    let s = &o.saddles[b.key_saddle.unwrap()];
    assert_eq!(s.elevation, f64::from(col));
    assert!(s.cell[0] > 15 && s.cell[0] < 45 && s.cell[1] == 10, "{:?}", s.cell);
    assert_eq!(s.peaks, [1, 0]);
    assert!((b.dominance - b.prominence / 80.0).abs() < 1e-12);
    // The highest: prominence above the lowest outlet (the map's border at 0).
    assert_eq!(a.prominence, 100.0);
    assert!(a.key_saddle.is_none() && a.isolation.is_none());
    // b's nearest higher ground is on a's flank, due west: 100 − 6d > 80 ⇒ d < 3.33, so x = 18.
    let iso = b.isolation.unwrap();
    assert!((iso.distance - 27.0).abs() < 1e-9 && (iso.azimuth - 270.0).abs() < 1e-9, "{iso:?}");
    assert_eq!((a.relative_prominence, b.relevance), (1.0, (b.prominence / 100.0 * 0.8).sqrt()));
}

#[test]
fn a_flat_topped_plateau_is_one_peak_at_its_first_cell() {
    let dem = Heightfield::from_fn(grid(20, 20), |p| {
        let d = (p - DVec2::new(10.0, 10.0)).abs().max_element();
        if d <= 2.0 { 50.0 } else { (50.0 - 5.0 * (d - 2.0)) as f32 }
    })
    .unwrap();
    let o = run(&dem);
    assert_eq!(o.peaks.len(), 1, "{:?}", o.peaks.iter().map(|p| p.cell).collect::<Vec<_>>());
    assert_eq!(o.peaks[0].cell, [8, 8]);
    // Flats that touch higher ground make no zero-prominence peaks either.
    let step = Heightfield::from_fn(grid(12, 12), |p| if p.x < 6.0 { 10.0 } else { 20.0 }).unwrap();
    let o = run(&step);
    assert_eq!(o.peaks.len(), 1);
    assert_eq!(o.peaks[0].cell, [6, 0]);
}

#[test]
fn nested_peaks_and_the_divide_tree() {
    // A main summit with a shoulder summit on its flank, and a third summit across a deep col.
    let dem = Heightfield::from_fn(grid(80, 30), |p| {
        let main = 300.0 - 8.0 * p.distance(DVec2::new(20.0, 15.0));
        let shoulder = 240.0 - 10.0 * p.distance(DVec2::new(30.0, 15.0));
        let far = 200.0 - 6.0 * p.distance(DVec2::new(62.0, 15.0));
        main.max(shoulder).max(far).max(0.0) as f32
    })
    .unwrap();
    let o = run(&dem);
    assert_eq!(o.peaks.len(), 3);
    let (main, shoulder, far) = (peak_at(&o, [20, 15]), peak_at(&o, [30, 15]), peak_at(&o, [62, 15]));
    assert!(shoulder.prominence < 40.0 && shoulder.prominence > 0.0);
    assert!(far.prominence >= 95.0, "{}", far.prominence);
    assert_eq!(shoulder.parent, Some(0));
    // Pruned above the shoulder's prominence: two peaks left, the far one still linked to the top.
    let pruned = o.pruned(50.0);
    assert_eq!(pruned.peaks.len(), 2);
    assert_eq!(pruned.saddles.len(), 1);
    assert_eq!(pruned.peaks[1].cell, far.cell);
    assert_eq!(pruned.peaks[1].parent, Some(0));
    // The top's prominence is its height above the lowest border cell.
    let border = (0..80)
        .flat_map(|i| [dem.value(i, 0), dem.value(i, 29)])
        .chain((0..30).flat_map(|j| [dem.value(0, j), dem.value(79, j)]));
    assert_eq!(main.prominence, 300.0 - f64::from(border.fold(f32::INFINITY, f32::min)));
}

#[test]
fn the_divide_tree_joins_peaks_along_their_ridges() {
    // Three summits in a row, west to east: 300, 200 (middle, low) and 250. The east summit's key
    // saddle is the col between it and the middle one; its prominence parent is the west summit
    // (the highest on the other side), but its ridge meets the middle summit's there: the divide
    // tree joins east to middle, and middle to west, never east straight to west.
    let dem = Heightfield::from_fn(grid(90, 21), |p| {
        let west = 300.0 - 6.0 * p.distance(DVec2::new(15.0, 10.0));
        let middle = 200.0 - 4.0 * p.distance(DVec2::new(45.0, 10.0));
        let east = 250.0 - 6.0 * p.distance(DVec2::new(75.0, 10.0));
        west.max(middle).max(east).max(0.0) as f32
    })
    .unwrap();
    let o = run(&dem);
    let index = |cell: [usize; 2]| o.peaks.iter().position(|p| p.cell == cell).unwrap();
    let (west, middle, east) = (index([15, 10]), index([45, 10]), index([75, 10]));
    assert_eq!(o.peaks[east].parent, Some(west), "the prominence parent is the higher summit");
    let joins = |a: usize, b: usize| o.saddles.iter().any(|s| s.peaks == [a, b] || s.peaks == [b, a]);
    assert!(joins(east, middle) && joins(middle, west) && !joins(east, west), "{:?}", o.saddles);
    let ks = &o.saddles[o.peaks[east].key_saddle.unwrap()];
    assert_eq!(ks.peaks, [east, middle], "the key saddle's ridge runs from the east summit to the middle one");
    // Pruning the middle summit joins its neighbours through the lower of its saddles.
    let pruned = o.pruned(o.peaks[middle].prominence + 1.0);
    assert_eq!(pruned.peaks.len(), 2);
    assert_eq!(pruned.saddles.len(), 1);
    assert_eq!(pruned.saddles[0].peaks, [1, 0]);
    let lower = o.saddles.iter().map(|s| s.elevation).fold(f64::INFINITY, f64::min);
    assert_eq!(pruned.saddles[0].elevation, lower);
}

#[test]
fn the_sea_and_the_map_edge() {
    // An island rising from a sea at 0 with its top on the map's edge.
    let dem = Heightfield::from_fn(grid(40, 30), |p| {
        let top = 120.0 - 5.0 * p.distance(DVec2::new(0.0, 15.0));
        let inner = 90.0 - 6.0 * p.distance(DVec2::new(20.0, 15.0));
        top.max(inner).max(-10.0) as f32
    })
    .unwrap();
    let options = AnalysisOptions { sea_level: Some(0.0), ..AnalysisOptions::default() };
    let o = analyze(&dem, &options).unwrap();
    let top = peak_at(&o, [0, 15]);
    // Touching the sea, the top's prominence is its height above it.
    assert_eq!(top.prominence, 120.0);
    assert!(top.edge_effect || top.key_saddle.is_none());
    let inner = peak_at(&o, [20, 15]);
    assert!(!inner.edge_effect, "its key saddle is inland");
    // All sea: a typed error.
    let sea = Heightfield::filled(grid(5, 5), -3.0).unwrap();
    assert_eq!(analyze(&sea, &options).unwrap_err(), OrometryError::NoLand { cells: 25 });
    let none = Heightfield::filled(grid(3, 3), f32::NAN).unwrap();
    assert!(matches!(analyze(&none, &AnalysisOptions::default()), Err(OrometryError::NoLand { .. })));
    let bad = AnalysisOptions { min_prominence: -1.0, ..AnalysisOptions::default() };
    assert!(matches!(analyze(&dem, &bad), Err(OrometryError::InvalidOption { .. })));
}

#[test]
fn tiny_and_flat_dems_have_documented_results() {
    let one = Heightfield::filled(grid(2, 2), 7.0).unwrap();
    // A flat map is one land mass: its top at the first cell, with no relief above the outlet.
    let o = run(&one);
    assert_eq!(o.peaks.len(), 1);
    assert_eq!((o.peaks[0].cell, o.peaks[0].prominence), ([0, 0], 0.0));
    let line =
        Heightfield::from_fn(GridSpec::new(1, 9, DVec2::ZERO, DVec2::ONE).unwrap(), |p| (p.y * (8.0 - p.y)) as f32)
            .unwrap();
    let o = run(&line);
    assert_eq!(o.peaks.len(), 1);
    assert_eq!(o.peaks[0].cell, [0, 4]);
    assert_eq!(o.peaks[0].prominence, 16.0);
    // No-data is an outlet, like the border.
    let mut holed = Heightfield::from_fn(grid(9, 9), |p| (20.0 - p.distance(DVec2::splat(4.0))) as f32).unwrap();
    holed.samples_mut()[0] = f32::NAN;
    let o = run(&holed);
    assert_eq!(o.peaks.len(), 1);
}

/// Prominence by brute force: flood from the peak, highest first, until a cell higher in the
/// strict order (elevation, then earlier index) is reached; the lowest elevation flooded on the
/// way is the key saddle. `None` for the highest cell.
fn brute_prominence(z: &[f32], nx: usize, ny: usize, peak: usize) -> Option<f32> {
    let higher = |a: usize, b: usize| z[a] > z[b] || (z[a] == z[b] && a < b);
    let mut seen = vec![false; z.len()];
    let mut heap = BinaryHeap::new();
    let key = |k: usize| (ordered(z[k]), Reverse(k));
    heap.push((key(peak), peak));
    seen[peak] = true;
    let mut low = z[peak];
    while let Some((_, k)) = heap.pop() {
        low = low.min(z[k]);
        if higher(k, peak) {
            return Some(z[peak] - low);
        }
        let (i, j) = ((k % nx) as i64, (k / nx) as i64);
        for dj in -1..=1 {
            for di in -1..=1 {
                let (a, b) = (i + di, j + dj);
                if a >= 0 && b >= 0 && a < nx as i64 && b < ny as i64 {
                    let w = b as usize * nx + a as usize;
                    if !seen[w] {
                        seen[w] = true;
                        heap.push((key(w), w));
                    }
                }
            }
        }
    }
    None
}

fn ordered(v: f32) -> i64 {
    (f64::from(v) * 1e6) as i64
}

fn random_dem() -> impl Strategy<Value = (usize, usize, Vec<f32>)> {
    (3usize..14, 3usize..12).prop_flat_map(|(nx, ny)| {
        // Quantized to 8 levels, so ties and flats are common.
        (Just(nx), Just(ny), proptest::collection::vec((0u8..8).prop_map(|v| f32::from(v) * 10.0), nx * ny))
    })
}

/// The divide tree by its definition, for a DEM without ties: every cell climbs to its highest
/// neighbour, which splits the map into ascent basins; each pair of neighbouring cells in two
/// basins is a pass between them at the lower cell; Kruskal from the highest pass (and, at one
/// cell, from its highest neighbour: a ridge climbs by its steepest way) keeps a maximum spanning
/// tree. Returns `(peak cell, peak cell, saddle cell)` per ridge, peaks sorted.
fn brute_divide_tree(z: &[f32], nx: usize, ny: usize) -> Vec<([usize; 2], [usize; 2], [usize; 2])> {
    let neighbours = |k: usize| {
        let (i, j) = ((k % nx) as i64, (k / nx) as i64);
        (-1..=1)
            .flat_map(move |dj| (-1..=1).map(move |di| (i + di, j + dj)))
            .filter(move |&(a, b)| (a, b) != (i, j) && a >= 0 && b >= 0 && a < nx as i64 && b < ny as i64)
            .map(move |(a, b)| b as usize * nx + a as usize)
    };
    let climb = |mut k: usize| loop {
        let up = neighbours(k).max_by(|&a, &b| z[a].total_cmp(&z[b])).unwrap();
        if z[up] <= z[k] {
            return k;
        }
        k = up;
    };
    let basin: Vec<usize> = (0..z.len()).map(climb).collect();
    let mut passes: Vec<(usize, usize, usize, usize)> = Vec::new();
    for k in 0..z.len() {
        for w in neighbours(k) {
            if basin[w] != basin[k] && z[w] > z[k] {
                passes.push((k, basin[k], basin[w], w));
            }
        }
    }
    passes.sort_by(|a, b| z[b.0].total_cmp(&z[a.0]).then(z[b.3].total_cmp(&z[a.3])));
    let mut set: Vec<usize> = (0..z.len()).collect();
    let root = |set: &mut [usize], mut x: usize| {
        while set[x] != x {
            x = set[x];
        }
        x
    };
    let cell = |k: usize| [k % nx, k / nx];
    let mut tree = Vec::new();
    for (s, a, b, _) in passes {
        let (ra, rb) = (root(&mut set, a), root(&mut set, b));
        if ra != rb {
            set[ra] = rb;
            let (p, q) = if a < b { (a, b) } else { (b, a) };
            tree.push((cell(p), cell(q), cell(s)));
        }
    }
    tree.sort_unstable();
    tree
}

/// A DEM of distinct heights (a shuffled ramp), so every local maximum is a peak of positive
/// prominence and the divide tree is unique.
fn distinct_dem() -> impl Strategy<Value = (usize, usize, Vec<f32>)> {
    (3usize..14, 3usize..12).prop_flat_map(|(nx, ny)| {
        let values: Vec<f32> = (0..nx * ny).map(|v| v as f32).collect();
        (Just(nx), Just(ny), Just(values).prop_shuffle())
    })
}

/// Checks every saddle's ridge line: it runs from its first peak through the saddle to its
/// second, cell to neighbouring cell, never below the saddle (the lowest point of the path between
/// the two peaks).
fn check_ridge_lines(o: &Orometry, dem: &Heightfield) -> Result<(), TestCaseError> {
    let g = dem.grid();
    for (k, s) in o.saddles.iter().enumerate() {
        let line = &s.ridge;
        prop_assert!(line.len() >= 2, "saddle {k} has no line");
        prop_assert_eq!(line[0], o.peaks[s.peaks[0]].position, "saddle {} starts at its first peak", k);
        prop_assert_eq!(line[line.len() - 1], o.peaks[s.peaks[1]].position, "saddle {} ends at its second", k);
        prop_assert!(line.contains(&s.position), "saddle {k}'s line misses the saddle");
        for w in line.windows(2) {
            let d = (DVec2::from(w[1]) - DVec2::from(w[0])).abs();
            prop_assert!(d.max_element() <= 1.0 + 1e-9 && d.max_element() > 0.0, "saddle {k}: a jump {w:?}");
        }
        for p in line {
            let (i, j) = g.nearest_sample(DVec2::from(*p)).unwrap();
            prop_assert!(
                f64::from(dem.get(i, j).unwrap()) >= s.elevation,
                "saddle {k}: the line dips below it at {p:?}"
            );
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Ridge lines follow the DEM, pruned or not, and pruning an analysis traces the same lines
    /// as analysing with the threshold.
    #[test]
    fn ridge_lines_run_peak_to_saddle_to_peak_on_high_ground((nx, ny, z) in random_dem(), min in 0.0f64..40.0) {
        let dem = Heightfield::from_samples(grid(nx, ny), z).unwrap();
        let options = AnalysisOptions { ridge_lines: true, ..AnalysisOptions::default() };
        let full = analyze(&dem, &options).unwrap();
        check_ridge_lines(&full, &dem)?;
        let cut = analyze(&dem, &AnalysisOptions { min_prominence: min, ..options }).unwrap();
        check_ridge_lines(&cut, &dem)?;
        prop_assert_eq!(full.pruned(min), cut);
    }

    /// Unpruned, the analysis's saddles are the divide tree by its definition: each joins the
    /// two peaks whose ascent basins meet at it.
    #[test]
    fn the_divide_tree_matches_a_brute_force_construction((nx, ny, z) in distinct_dem()) {
        let dem = Heightfield::from_samples(grid(nx, ny), z.clone()).unwrap();
        let o = run(&dem);
        let mut ours: Vec<_> = o
            .saddles
            .iter()
            .map(|s| {
                let [a, b] = s.peaks.map(|k| o.peaks[k].cell);
                let (p, q) = if (a[1], a[0]) < (b[1], b[0]) { (a, b) } else { (b, a) };
                (p, q, s.cell)
            })
            .collect();
        ours.sort_unstable();
        prop_assert_eq!(ours, brute_divide_tree(&z, nx, ny));
    }

    #[test]
    fn prominence_matches_a_brute_force_flood((nx, ny, z) in random_dem()) {
        let dem = Heightfield::from_samples(grid(nx, ny), z.clone()).unwrap();
        let o = run(&dem);
        let min = z.iter().copied().fold(f32::INFINITY, f32::min);
        let border_min = (0..nx * ny)
            .filter(|k| k % nx == 0 || k / nx == 0 || k % nx == nx - 1 || k / nx == ny - 1)
            .map(|k| z[k])
            .fold(f32::INFINITY, f32::min);
        let tops: Vec<_> = o.peaks.iter().filter(|p| p.key_saddle.is_none()).collect();
        // One land mass: exactly one peak without a key saddle, above the lowest outlet.
        prop_assert_eq!(tops.len(), 1);
        for p in &o.peaks {
            let k = p.cell[1] * nx + p.cell[0];
            prop_assert!(p.prominence > 0.0 || p.key_saddle.is_none());
            prop_assert!(p.prominence <= p.elevation - f64::from(min));
            if let Some(s) = p.key_saddle {
                let saddle = &o.saddles[s];
                prop_assert!(saddle.elevation < p.elevation);
                let want = brute_prominence(&z, nx, ny, k).unwrap();
                prop_assert_eq!(p.prominence, f64::from(want));
            } else {
                prop_assert_eq!(p.prominence, f64::from(z[k] - border_min));
                prop_assert!(p.isolation.is_none());
            }
        }
        // Isolation: the nearest strictly higher sample, by brute force.
        for p in &o.peaks {
            let nearest = (0..nx * ny)
                .filter(|&w| f64::from(z[w]) > p.elevation)
                .map(|w| DVec2::new((w % nx) as f64, (w / nx) as f64).distance(DVec2::new(p.cell[0] as f64, p.cell[1] as f64)))
                .fold(f64::INFINITY, f64::min);
            match p.isolation {
                Some(iso) => prop_assert!((iso.distance - nearest).abs() < 1e-9, "{} vs {nearest}", iso.distance),
                None => prop_assert!(nearest.is_infinite()),
            }
        }
        // Every cell whose brute-force prominence is positive is a peak.
        for k in 0..nx * ny {
            if brute_prominence(&z, nx, ny, k).is_some_and(|p| p > 0.0) {
                prop_assert!(o.peaks.iter().any(|p| p.cell == [k % nx, k / nx]), "cell {k} missing");
            }
        }
    }

    /// Raising one cell by `d` lowers no other peak's prominence by more than `d`, as long as the
    /// raised cell stays below that peak: saddles on every path rise by at most `d`. (A cell
    /// raised above a peak becomes higher ground itself, which changes what prominence measures.)
    #[test]
    fn raising_a_cell_costs_others_at_most_the_raise((nx, ny, z) in random_dem(), pick in any::<prop::sample::Index>(), d in 1u8..30) {
        let before = run(&Heightfield::from_samples(grid(nx, ny), z.clone()).unwrap());
        let k = pick.index(nx * ny);
        let mut raised = z.clone();
        raised[k] += f32::from(d);
        let after = run(&Heightfield::from_samples(grid(nx, ny), raised).unwrap());
        for p in &before.peaks {
            let pk = p.cell[1] * nx + p.cell[0];
            let raised_above = f64::from(z[k]) + f64::from(d) > p.elevation
                || (f64::from(z[k]) + f64::from(d) == p.elevation && k < pk);
            if pk == k || raised_above {
                continue;
            }
            if let Some(q) = after.peaks.iter().find(|q| q.cell == p.cell) {
                prop_assert!(q.prominence >= p.prominence - f64::from(d), "{:?}: {} → {}", p.cell, p.prominence, q.prominence);
            }
        }
    }

    #[test]
    fn results_do_not_depend_on_the_thread_count((nx, ny, z) in random_dem()) {
        let dem = Heightfield::from_samples(grid(nx, ny), z).unwrap();
        let at = |threads: usize| {
            rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(|| run(&dem))
        };
        prop_assert_eq!(at(1), at(2));
    }
}

/// A ridge along the middle row of a 3-row DEM (the rows beside it at 0).
fn ridge(profile: &[f32]) -> Heightfield {
    Heightfield::from_fn_indexed(grid(profile.len(), 3), |i, j| if j == 1 { profile[i] } else { 0.0 }).unwrap()
}

#[test]
fn the_line_parent_is_the_first_higher_peak_along_the_ridge_the_prominence_parent_its_top() {
    // P 60 — col 40 — Q 70 — col 50 — R 100: P's key saddle is the col at 40; across it the
    // ridge climbs to Q (higher than P) and on to R, the top of that side.
    let dem = ridge(&[0.0, 60.0, 40.0, 70.0, 50.0, 100.0, 0.0]);
    let oro = run(&dem);
    let (p, q, r) = (peak_at(&oro, [1, 1]), peak_at(&oro, [3, 1]), peak_at(&oro, [5, 1]));
    let id = |x: &relief_orometry::Peak| oro.peaks.iter().position(|y| y == x).unwrap();
    let line = oro.line_parents();
    assert_eq!(p.parent, Some(id(r)));
    assert_eq!(line[id(p)], Some(id(q)));
    assert_eq!((q.parent, line[id(q)]), (Some(id(r)), Some(id(r))));
    assert_eq!(line[id(r)], None);
    // Mirrored, the walk goes the other way along the ridge.
    let dem = ridge(&[0.0, 100.0, 50.0, 70.0, 40.0, 60.0, 0.0]);
    let oro = run(&dem);
    let (p, q) = (peak_at(&oro, [5, 1]), peak_at(&oro, [3, 1]));
    let id = |x: &relief_orometry::Peak| oro.peaks.iter().position(|y| y == x).unwrap();
    assert_eq!(oro.line_parents()[id(p)], Some(id(q)));
}

#[test]
fn line_parents_are_higher_and_on_the_far_side_of_the_key_saddle() {
    let dem = Heightfield::from_fn(grid(41, 37), |p| {
        (40.0 + 30.0 * (p.x * 0.37).sin() * (p.y * 0.29).cos() + 0.8 * p.x + 0.3 * (p.x * 1.7 + p.y).sin()) as f32
    })
    .unwrap();
    let oro = run(&dem);
    let line = oro.line_parents();
    assert!(oro.peaks.len() > 5);
    for (k, p) in oro.peaks.iter().enumerate() {
        match (p.key_saddle, line[k]) {
            (None, None) => {}
            (Some(_), Some(l)) => {
                assert!(l < k && oro.peaks[l].elevation >= p.elevation, "peak {k}: line parent {l} is not higher");
                // Never higher in rank than the prominence parent's side allows: the parent itself
                // or a peak no higher than it.
                let parent = p.parent.unwrap();
                assert!(oro.peaks[l].elevation <= oro.peaks[parent].elevation, "peak {k}");
            }
            other => panic!("peak {k}: key saddle and line parent {other:?}"),
        }
    }
}

#[test]
fn the_sea_level_base_makes_a_land_masss_top_as_prominent_as_it_is_high() {
    // A cone on a plateau at 20: the border, its lowest outlet, is at 20.
    let dem = Heightfield::from_fn(grid(21, 21), |p| (100.0 - 8.0 * p.distance(DVec2::splat(10.0))).max(20.0) as f32)
        .unwrap();
    let top = |options: AnalysisOptions| analyze(&dem, &options).unwrap().peaks[0].prominence;
    assert_eq!(top(AnalysisOptions::default()), 80.0);
    let sea = AnalysisOptions { base: ProminenceBase::SeaLevel, ..AnalysisOptions::default() };
    assert_eq!(top(sea), 100.0);
    assert_eq!(top(AnalysisOptions { sea_level: Some(10.0), ..sea }), 90.0);
}

#[test]
fn anti_prominence_finds_the_pits_of_the_dem_upside_down() {
    let cones = |sign: f32| {
        Heightfield::from_fn(grid(61, 21), move |p| {
            let a = 100.0 - 6.0 * p.distance(DVec2::new(15.0, 10.0));
            let b = 80.0 - 4.0 * p.distance(DVec2::new(45.0, 10.0));
            sign * a.max(b).max(0.0) as f32
        })
        .unwrap()
    };
    let summits = run(&cones(1.0));
    let pits = analyze(&cones(-1.0), &AnalysisOptions { depressions: true, ..AnalysisOptions::default() }).unwrap();
    assert_eq!(pits.peaks.len(), summits.peaks.len());
    for (pit, summit) in pits.peaks.iter().zip(&summits.peaks) {
        assert_eq!((pit.cell, pit.elevation, pit.prominence), (summit.cell, -summit.elevation, summit.prominence));
    }
    assert_eq!(pits.saddles[0].elevation, -summits.saddles[0].elevation);
    // Without the flag, the bottoms of the upside-down cones are no peaks.
    let o = run(&cones(-1.0));
    assert!(o.peaks.iter().all(|p| p.cell != [15, 10] && p.cell != [45, 10]));
}

#[test]
fn line_parents_walk_through_trees_rerooted_at_their_saddles() {
    // Q 90 — 30 — K 80 — 70 — M 75 — 40 — R 100. K's key saddle (40) is reached through M, so
    // K's side hangs under R re-rooted at M; Q's walk from K then climbs K → M → R.
    let dem = ridge(&[0.0, 90.0, 30.0, 80.0, 70.0, 75.0, 40.0, 100.0, 0.0]);
    let oro = run(&dem);
    let id = |cell| oro.peaks.iter().position(|p| p.cell == cell).unwrap();
    let (q, k, m, r) = (id([1, 1]), id([3, 1]), id([5, 1]), id([7, 1]));
    let line = oro.line_parents();
    assert_eq!((line[q], line[k], line[m], line[r]), (Some(r), Some(r), Some(k), None));
}

#[test]
fn anti_prominence_with_a_sea_level_keeps_to_the_sea_floor() {
    // Sea floor at −5 with a pit at −30 (west), a shelf at 0 with a dip at −1, land at 50 with a
    // dip at 40 (east); the sea level at −2.
    let dem = Heightfield::from_fn_indexed(grid(12, 5), |i, j| match (i, j) {
        (1, 2) => -30.0,
        (6, 2) => -1.0,
        (10, 2) => 40.0,
        (i, _) if i <= 3 => -5.0,
        (i, _) if i <= 7 => 0.0,
        _ => 50.0,
    })
    .unwrap();
    let pits = |sea_level| {
        let o = analyze(&dem, &AnalysisOptions { depressions: true, sea_level, ..AnalysisOptions::default() }).unwrap();
        o.peaks.iter().map(|p| (p.cell, p.elevation)).collect::<Vec<_>>()
    };
    let all = pits(None);
    assert!(all.contains(&([10, 2], 40.0)) && all.contains(&([6, 2], -1.0)), "{all:?}");
    let sea = pits(Some(-2.0));
    assert!(sea.contains(&([1, 2], -30.0)) && sea.iter().all(|p| p.1 < -2.0), "{sea:?}");
}
