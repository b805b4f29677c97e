//! Orometry of the Jacksboro DEM beside akirmse/mountains' (`fixtures/akirmse/`: its peaks and its
//! pruned divide tree, output only): the same prominent peaks, and the same divide tree — each
//! peak joined to the neighbour whose ridge meets its own at a saddle, through that saddle.

use std::collections::HashMap;
use std::path::Path;

use relief::orometry::{AnalysisOptions, DivideTree, Dvt, DvtGrid, Orometry, analyze};

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

/// The DEM's samples sit on akirmse's canvas at column `i + 704`, row `r + 321` (rows from the top).
const COL: i64 = 704;
const ROW: i64 = 321;

struct Akirmse {
    /// Per peak id: grid cell `[i, j]` (ours, rows from the bottom) and elevation.
    peaks: HashMap<u32, ([i64; 2], f64)>,
    /// Per saddle id: grid cell and elevation.
    saddles: HashMap<u32, ([i64; 2], f64)>,
    /// `(peak, neighbour, saddle)`.
    edges: Vec<(u32, u32, u32)>,
}

/// akirmse's tree, read by our `.dvt` reader.
fn akirmse(ny: i64) -> Akirmse {
    let text = std::fs::read_to_string(root().join("fixtures/akirmse/divide_tree.dvt")).unwrap();
    let dvt = Dvt::parse(&text).unwrap();
    assert_eq!((dvt.unlinked_saddles, dvt.runoffs), (0, 0));
    let cell = |p: glam::DVec2| {
        let [col, row] = dvt.grid.sample(p);
        [col - COL, ny - 1 - (row - ROW)]
    };
    let tree = &dvt.tree;
    let id = |k: usize| k as u32 + 1;
    Akirmse {
        peaks: tree.peaks.iter().enumerate().map(|(k, p)| (id(k), (cell(p.position), p.elevation))).collect(),
        saddles: tree.saddles.iter().enumerate().map(|(k, s)| (id(k), (cell(s.position), s.elevation))).collect(),
        edges: tree.saddles.iter().enumerate().map(|(k, s)| (s.peaks[0] + 1, s.peaks[1] + 1, id(k))).collect(),
    }
}

/// Our peak at akirmse's: the same elevation, on the same flat top (within 2 cells: on a flat
/// summit akirmse and we pick different cells).
fn matching(oro: &Orometry, (cell, elevation): ([i64; 2], f64)) -> Option<usize> {
    let distance = |c: [usize; 2]| (c[0] as i64 - cell[0]).abs().max((c[1] as i64 - cell[1]).abs());
    (0..oro.peaks.len())
        .filter(|&k| oro.peaks[k].elevation == elevation && distance(oro.peaks[k].cell) <= 2)
        .min_by_key(|&k| distance(oro.peaks[k].cell))
}

impl Akirmse {
    /// Its tree without the peaks its own list drops (its pruning at 30 m is best effort: a few
    /// less prominent peaks stay in the tree): each, lowest first, is merged into the neighbour
    /// across its highest saddle, whose ridge goes, and its other ridges lead to that neighbour.
    /// Where a dropped peak's highest saddles are equal (flat cols, whose cells akirmse and we
    /// rank differently), bit `m` of `flips` picks the last of them instead of the first at the
    /// `m`-th such peak.
    fn without(mut self, listed: &[([i64; 2], f64, f64)], flips: u32) -> Self {
        let mut extra: Vec<(f64, u32)> = self
            .peaks
            .iter()
            .filter(|(_, (cell, h))| !listed.iter().any(|(c, e, _)| c == cell && e == h))
            .map(|(&id, &(_, h))| (h, id))
            .collect();
        extra.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut ties = 0;
        for (_, id) in extra {
            let at = |e: &(u32, u32, u32)| e.0 == id || e.1 == id;
            let height = |e: &(u32, u32, u32)| self.saddles[&e.2].1;
            let Some(top) = self.edges.iter().filter(|e| at(e)).map(height).max_by(f64::total_cmp) else {
                continue;
            };
            let tied: Vec<(u32, u32, u32)> = self.edges.iter().filter(|e| at(e) && height(e) == top).copied().collect();
            let highest = if tied.len() > 1 {
                ties += 1;
                if flips >> (ties - 1) & 1 == 1 { tied[tied.len() - 1] } else { tied[0] }
            } else {
                tied[0]
            };
            let other = if highest.0 == id { highest.1 } else { highest.0 };
            self.edges.retain(|e| *e != highest);
            for e in &mut self.edges {
                if e.0 == id {
                    e.0 = other;
                }
                if e.1 == id {
                    e.1 = other;
                }
            }
            self.peaks.remove(&id);
        }
        self
    }
}

fn jacksboro() -> (Orometry, i64) {
    let dem = relief::io::read(root().join("fixtures/dem/jacksboro.asc")).unwrap();
    let oro = analyze(&dem, &AnalysisOptions { min_prominence: 30.0, ..AnalysisOptions::default() }).unwrap();
    (oro, dem.ny() as i64)
}

/// How many of akirmse's ridges (pruned to its listed peaks) join our matching peaks through our
/// saddle at the same cell (± 1), and the misses.
fn same_ridges(oro: &Orometry, theirs: &Akirmse) -> (usize, Vec<String>) {
    let mut same = 0;
    let mut misses = Vec::new();
    for &(p, q, s) in &theirs.edges {
        let (Some(a), Some(b)) = (matching(oro, theirs.peaks[&p]), matching(oro, theirs.peaks[&q])) else {
            misses.push(format!("{p}-{q}: a peak is not ours"));
            continue;
        };
        let cell = theirs.saddles[&s].0;
        let found = oro.saddles.iter().any(|x| {
            (x.peaks == [a, b] || x.peaks == [b, a])
                && (x.cell[0] as i64 - cell[0]).abs() <= 1
                && (x.cell[1] as i64 - cell[1]).abs() <= 1
        });
        if found {
            same += 1;
        } else {
            misses.push(format!("{p}-{q} via {cell:?} at {} m", theirs.saddles[&s].1));
        }
    }
    (same, misses)
}

#[test]
fn the_divide_tree_joins_the_peaks_akirmse_joins_through_the_same_saddles() {
    let (oro, ny) = jacksboro();
    let listed = akirmse_peaks(ny);
    // Either way through each tie of equal saddles (four in this tree); the best of the 16.
    let (total, (same, misses)) = (0..16)
        .map(|flips| {
            let theirs = akirmse(ny).without(&listed, flips);
            (theirs.edges.len(), same_ridges(&oro, &theirs))
        })
        .max_by_key(|(_, (same, _))| *same)
        .unwrap();
    eprintln!("{same} of {total} ridges as akirmse's; misses: {misses:?}");
    assert!(same * 100 >= 95 * total, "{same} of {total} ridges as akirmse's; misses: {misses:?}");
}

/// akirmse's peaks at least 30 m prominent: cell, elevation, prominence.
fn akirmse_peaks(ny: i64) -> Vec<([i64; 2], f64, f64)> {
    let text = std::fs::read_to_string(root().join("fixtures/akirmse/prominence.txt")).unwrap();
    text.lines()
        .map(|line| {
            let f: Vec<f64> = line.split(',').map(|v| v.parse().unwrap()).collect();
            // lat = 37 − row/1200, lon = −85 + col/1200, rounded to the sample.
            let (col, row) = (((f[1] + 85.0) * 1200.0).round() as i64, ((37.0 - f[0]) * 1200.0).round() as i64);
            ([col - COL, ny - 1 - (row - ROW)], f[2], f[5])
        })
        .collect()
}

#[test]
fn prominent_peaks_are_akirmses_within_a_metre() {
    let (oro, ny) = jacksboro();
    let theirs = akirmse_peaks(ny);
    let mut misses = Vec::new();
    for &(cell, elevation, prominence) in &theirs {
        match matching(&oro, (cell, elevation)) {
            // akirmse measures a land mass's top from sea level; we measure it from its lowest outlet.
            Some(k) if oro.peaks[k].key_saddle.is_none() => {}
            Some(k) if (oro.peaks[k].prominence - prominence).abs() <= 1.0 => {}
            Some(k) => {
                misses.push(format!("{cell:?} {elevation}: {prominence} against our {}", oro.peaks[k].prominence));
            }
            None => misses.push(format!("{cell:?} {elevation}: {prominence}, not ours")),
        }
    }
    eprintln!("{} of {} peaks differ: {misses:?}", misses.len(), theirs.len());
    assert!(misses.len() * 100 <= 3 * theirs.len(), "{} of {} peaks differ: {misses:?}", misses.len(), theirs.len());
}

/// The lines of a `.dvt` file that describe the grid, peaks and saddles (not comments, not the
/// edges, whose orientation is free).
fn grid_peaks_saddles(text: &str) -> Vec<&str> {
    text.lines().filter(|l| l.starts_with(['G', 'P', 'S'])).collect()
}

#[test]
fn akirmses_tree_goes_through_our_reader_and_writer_unchanged() {
    let text = std::fs::read_to_string(root().join("fixtures/akirmse/divide_tree.dvt")).unwrap();
    let dvt = Dvt::parse(&text).unwrap();
    let ours = dvt.to_string();
    assert_eq!(grid_peaks_saddles(&ours), grid_peaks_saddles(&text));
    // The same tree back, each edge perhaps the other way round.
    let back = Dvt::parse(&ours).unwrap();
    assert_eq!(back.tree.peaks, dvt.tree.peaks);
    let unordered = |tree: &DivideTree| -> Vec<_> {
        tree.saddles
            .iter()
            .map(|s| (s.position, s.elevation, s.peaks[0].min(s.peaks[1]), s.peaks[0].max(s.peaks[1])))
            .collect()
    };
    assert_eq!(unordered(&back.tree), unordered(&dvt.tree));
}

#[test]
fn our_jacksboro_tree_is_written_on_akirmses_canvas() {
    let dem = relief::io::read(root().join("fixtures/dem/jacksboro.asc")).unwrap();
    let oro = analyze(&dem, &AnalysisOptions { min_prominence: 30.0, ..AnalysisOptions::default() }).unwrap();
    let grid = DvtGrid::for_grid(dem.grid(), dem.crs()).unwrap();
    let theirs = std::fs::read_to_string(root().join("fixtures/akirmse/divide_tree.dvt")).unwrap();
    assert_eq!(Dvt::parse(&theirs).unwrap().grid, grid);
    // Every peak sits at its cell of the canvas: column i + 704, row (from the top) r + 321.
    let text = Dvt { grid, tree: DivideTree::from_orometry(&oro), unlinked_saddles: 0, runoffs: 0 }.to_string();
    let back = Dvt::parse(&text).unwrap();
    for (p, q) in oro.peaks.iter().zip(&back.tree.peaks) {
        let [i, j] = p.cell.map(|c| c as i64);
        assert_eq!(grid.sample(q.position), [i + COL, dem.ny() as i64 - 1 - j + ROW]);
    }
    assert_eq!(back.tree.saddles.len(), oro.saddles.len());
}
