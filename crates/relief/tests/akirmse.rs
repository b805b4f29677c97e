//! Orometry of the Jacksboro DEM beside akirmse/mountains' (`fixtures/akirmse/`: its peaks and its
//! pruned divide tree, output only): the same prominent peaks, and the same divide tree — each
//! peak joined to the neighbour whose ridge meets its own at a saddle, through that saddle.

use std::collections::HashMap;
use std::path::Path;

use relief::orometry::{AnalysisOptions, Orometry, analyze};

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

fn akirmse(ny: i64) -> Akirmse {
    let text = std::fs::read_to_string(root().join("fixtures/akirmse/divide_tree.dvt")).unwrap();
    let cell = |col: &str, row: &str| [col.parse::<i64>().unwrap() - COL, ny - 1 - (row.parse::<i64>().unwrap() - ROW)];
    let mut tree = Akirmse { peaks: HashMap::new(), saddles: HashMap::new(), edges: Vec::new() };
    for line in text.lines() {
        let f: Vec<&str> = line.split(',').collect();
        match f[0] {
            "P" => {
                tree.peaks.insert(f[1].parse().unwrap(), (cell(f[2], f[3]), f[4].parse().unwrap()));
            }
            "S" => {
                tree.saddles.insert(f[1].parse().unwrap(), (cell(f[3], f[4]), f[5].parse().unwrap()));
            }
            "N" if f[2] != "-1" => {
                tree.edges.push((f[1].parse().unwrap(), f[2].parse().unwrap(), f[3].parse().unwrap()));
            }
            _ => {}
        }
    }
    tree
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
    /// less prominent peaks stay in the tree): each is merged into the neighbour across its
    /// highest saddle, whose ridge goes, and its other ridges lead to that neighbour.
    fn without(mut self, listed: &[([i64; 2], f64, f64)]) -> Self {
        let extra: Vec<u32> = self
            .peaks
            .iter()
            .filter(|(_, (cell, h))| !listed.iter().any(|(c, e, _)| c == cell && e == h))
            .map(|(&id, _)| id)
            .collect();
        for id in extra {
            let at = |e: &(u32, u32, u32)| e.0 == id || e.1 == id;
            let Some(highest) = self
                .edges
                .iter()
                .filter(|e| at(e))
                .max_by(|a, b| self.saddles[&a.2].1.total_cmp(&self.saddles[&b.2].1))
                .copied()
            else {
                continue;
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

#[test]
fn the_divide_tree_joins_the_peaks_akirmse_joins_through_the_same_saddles() {
    let (oro, ny) = jacksboro();
    let theirs = akirmse(ny).without(&akirmse_peaks(ny));
    let (mut same, mut total) = (0, 0);
    let mut misses = Vec::new();
    for &(p, q, s) in &theirs.edges {
        total += 1;
        let (Some(a), Some(b)) = (matching(&oro, theirs.peaks[&p]), matching(&oro, theirs.peaks[&q])) else {
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
