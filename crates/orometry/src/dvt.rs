//! akirmse/mountains' divide-tree text format (`.dvt`), read and written, so trees go through its
//! tools (`merge_divide_trees`, `compute_parents`, …) and back.
//!
//! The format, as that program writes it: `#` comments; a first line describing the sample grid
//! (`G,minLat,minLng,samplesPerDegreeLat,samplesPerDegreeLng,maxLat,maxLng` for latitude and
//! longitude, sample `(col, row)` at `(minLng + col/spdLng, maxLat − row/spdLat)`; or
//! `U,zone,minX,minY,maxX,maxY,metresPerSample` for UTM, sample at `(minX + col·m, maxY − row·m)`);
//! then `P,id,col,row,elevation` per peak and `S,id,type,col,row,elevation` per saddle (ids from 1,
//! in order; type `p` for a prominence saddle, `b` basin, `f` false, `e` error); `R` runoffs and
//! `E` runoff edges; and `N,index,parent,saddle` per peak in order after a placeholder node 0:
//! each peak is joined to `parent` through `saddle` (`-1`: none). Rows count from the top.
//!
//! Written trees are final (no runoffs: a single DEM has nothing to splice), each component rooted
//! at its highest peak, on the whole-degree canvas around the grid when its samples fall on it
//! (as akirmse's tiles do), so its tools can merge them with their own.

use std::fmt::{self, Write as _};

use glam::DVec2;
use relief_heightfield::{Crs, GridSpec, Units};

use crate::union_find::find;
use crate::{DivideTree, OrometryError, TreePeak, TreeSaddle};

/// How far (in cells, over the whole grid) sample positions may drift from the `.dvt` lattice.
const DRIFT: f64 = 0.01;

/// The sample lattice of a `.dvt` file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DvtGrid {
    /// Latitude and longitude (`G` line), whole samples per degree.
    Degrees {
        /// Southern edge, degrees.
        min_lat: f64,
        /// Western edge (column 0), degrees.
        min_lng: f64,
        /// Northern edge (row 0), degrees.
        max_lat: f64,
        /// Eastern edge, degrees.
        max_lng: f64,
        /// Samples per degree of latitude and of longitude.
        samples_per_degree: [u32; 2],
    },
    /// A UTM zone (`U` line), whole metres at the corners.
    Utm {
        /// Zone number, 1–60.
        zone: u8,
        /// Western edge (column 0) and southern edge, metres.
        min: [i64; 2],
        /// Eastern edge and northern edge (row 0), metres.
        max: [i64; 2],
        /// Metres between samples.
        metres_per_sample: f64,
    },
}

impl DvtGrid {
    /// The lattice a `.dvt` of a tree on `grid` is written on: for a geographic grid, the
    /// whole-degree canvas around it when its samples fall on that canvas (else its own
    /// corners); for a grid in a UTM zone (EPSG 326zz/327zz, NAD83 269zz, ETRS89 258zz), its
    /// corners in whole metres.
    ///
    /// # Errors
    /// [`OrometryError::Dvt`] when the format cannot hold the grid: a cell size that is not a
    /// whole number of samples per degree, a planar grid without a UTM coordinate system, unequal
    /// cell sides or corners off whole metres in UTM.
    pub fn for_grid(grid: &GridSpec, crs: Option<&Crs>) -> Result<Self, OrometryError> {
        match grid.units() {
            Units::Degrees => degrees(grid),
            _ => utm(grid, crs),
        }
    }

    /// World position of sample `(col, row)` (rows from the top): longitude and latitude, or UTM
    /// easting and northing.
    pub fn position(&self, col: i64, row: i64) -> DVec2 {
        match *self {
            Self::Degrees { min_lng, max_lat, samples_per_degree: [lat, lng], .. } => {
                DVec2::new(min_lng + col as f64 / f64::from(lng), max_lat - row as f64 / f64::from(lat))
            }
            Self::Utm { min, max, metres_per_sample, .. } => DVec2::new(
                min[0] as f64 + col as f64 * metres_per_sample,
                max[1] as f64 - row as f64 * metres_per_sample,
            ),
        }
    }

    /// The sample nearest to world point `p`: `(col, row)`, rows from the top.
    pub fn sample(&self, p: DVec2) -> [i64; 2] {
        let (col, row) = match *self {
            Self::Degrees { min_lng, max_lat, samples_per_degree: [lat, lng], .. } => {
                ((p.x - min_lng) * f64::from(lng), (max_lat - p.y) * f64::from(lat))
            }
            Self::Utm { min, max, metres_per_sample, .. } => {
                ((p.x - min[0] as f64) / metres_per_sample, (max[1] as f64 - p.y) / metres_per_sample)
            }
        };
        [col.round() as i64, row.round() as i64]
    }

    /// The first line of a `.dvt` file, as akirmse's program prints it.
    fn header(&self) -> String {
        match *self {
            Self::Degrees { min_lat, min_lng, max_lat, max_lng, samples_per_degree: [lat, lng] } => {
                format!("G,{min_lat:.6},{min_lng:.6},{lat},{lng},{max_lat:.6},{max_lng:.6}")
            }
            Self::Utm { zone, min, max, metres_per_sample } => {
                format!("U,{zone},{},{},{},{},{metres_per_sample:.6}", min[0], min[1], max[0], max[1])
            }
        }
    }

    fn parse(line: &str) -> Result<Self, OrometryError> {
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        match f[0] {
            "G" if f.len() == 7 || f.len() == 5 => {
                let min_lat: f64 = number(f[1], "G minLat")?;
                let min_lng: f64 = number(f[2], "G minLng")?;
                let lat: u32 = number(f[3], "G samplesPerDegreeLat")?;
                let lng: u32 = number(f[4], "G samplesPerDegreeLng")?;
                // Files before the maximum was added describe 1°×1° tiles.
                let (max_lat, max_lng) = if f.len() == 7 {
                    (number(f[5], "G maxLat")?, number(f[6], "G maxLng")?)
                } else {
                    (min_lat + 1.0, min_lng + 1.0)
                };
                if lat == 0 || lng == 0 {
                    return Err(dvt_error(format!("`{line}`: samples per degree must be positive")));
                }
                Ok(Self::Degrees { min_lat, min_lng, max_lat, max_lng, samples_per_degree: [lat, lng] })
            }
            "U" if f.len() == 7 => {
                let zone: u8 = number(f[1], "U zone")?;
                let metres_per_sample: f64 = number(f[6], "U metresPerSample")?;
                if !(1..=60).contains(&zone) || metres_per_sample <= 0.0 {
                    return Err(dvt_error(format!("`{line}`: the zone must be 1–60 and the spacing positive")));
                }
                let min = [number(f[2], "U minX")?, number(f[3], "U minY")?];
                let max = [number(f[4], "U maxX")?, number(f[5], "U maxY")?];
                Ok(Self::Utm { zone, min, max, metres_per_sample })
            }
            _ => Err(dvt_error(format!(
                "the first line must describe the grid (`G,minLat,minLng,spdLat,spdLng,maxLat,maxLng` or \
                 `U,zone,minX,minY,maxX,maxY,metresPerSample`), not `{line}`"
            ))),
        }
    }
}

/// A geographic grid's lattice: whole samples per degree, on the whole-degree canvas if the
/// samples fall on it.
fn degrees(grid: &GridSpec) -> Result<DvtGrid, OrometryError> {
    let cell = grid.cell_size();
    let per_degree = |c: f64, n: usize, axis: &str| -> Result<u32, OrometryError> {
        let s = (1.0 / c).round();
        let drift = (c - 1.0 / s).abs() * n as f64 / c;
        if !(1.0..=f64::from(u32::MAX)).contains(&s) || drift > DRIFT {
            return Err(dvt_error(format!(
                "a .dvt needs a whole number of samples per degree; the grid's {axis} spacing is {c}° \
                 ({} per degree): write the divide tree as GeoJSON instead",
                1.0 / c
            )));
        }
        Ok(s as u32)
    };
    let lng = per_degree(cell.x, grid.nx(), "x")?;
    let lat = per_degree(cell.y, grid.ny(), "y")?;
    let extent = grid.extent();
    let (west, north) = (extent.min.x, extent.max.y);
    let on_lattice =
        |v: f64, s: u32| ((v - v.floor()) * f64::from(s) - ((v - v.floor()) * f64::from(s)).round()).abs() <= DRIFT;
    if on_lattice(west, lng) && on_lattice(north, lat) {
        let whole = |v: f64| if (v - v.round()).abs() * f64::from(lat.max(lng)) <= DRIFT { v.round() } else { v };
        return Ok(DvtGrid::Degrees {
            min_lat: whole(extent.min.y).floor(),
            min_lng: whole(west).floor(),
            max_lat: whole(north).ceil(),
            max_lng: whole(extent.max.x).ceil(),
            samples_per_degree: [lat, lng],
        });
    }
    Ok(DvtGrid::Degrees {
        min_lat: extent.min.y,
        min_lng: west,
        max_lat: north,
        max_lng: extent.max.x,
        samples_per_degree: [lat, lng],
    })
}

/// The UTM zone of an EPSG code: WGS 84 (326zz north, 327zz south), NAD83 (269zz), ETRS89 (258zz).
fn utm_zone(epsg: u32) -> Option<u8> {
    let zone = match epsg {
        32601..=32660 => epsg - 32600,
        32701..=32760 => epsg - 32700,
        26901..=26923 => epsg - 26900,
        25828..=25838 => epsg - 25800,
        _ => return None,
    };
    u8::try_from(zone).ok()
}

/// A UTM grid's lattice: its corners in whole metres.
fn utm(grid: &GridSpec, crs: Option<&Crs>) -> Result<DvtGrid, OrometryError> {
    let Some(zone) = crs.and_then(Crs::epsg).and_then(utm_zone) else {
        return Err(dvt_error(format!(
            "a .dvt holds latitude/longitude or UTM grids; this grid is in {} without a UTM zone \
             (write the divide tree as GeoJSON instead)",
            crs.map_or_else(|| "local units".to_owned(), Crs::name)
        )));
    };
    let cell = grid.cell_size();
    if (cell.x - cell.y).abs() > 1e-9 * cell.x {
        return Err(dvt_error(format!("a UTM .dvt needs square cells; these are {} × {} m", cell.x, cell.y)));
    }
    let extent = grid.extent();
    let whole = |v: f64| -> Result<i64, OrometryError> {
        if (v - v.round()).abs() > DRIFT * cell.x {
            return Err(dvt_error(format!("a UTM .dvt needs corners on whole metres; the grid has one at {v} m")));
        }
        Ok(v.round() as i64)
    };
    Ok(DvtGrid::Utm {
        zone,
        min: [whole(extent.min.x)?, whole(extent.min.y)?],
        max: [whole(extent.max.x)?, whole(extent.max.y)?],
        metres_per_sample: cell.x,
    })
}

/// A divide tree in akirmse's format: the lattice and the tree, peaks and saddles in file order.
#[derive(Debug, Clone, PartialEq)]
pub struct Dvt {
    /// The sample lattice; positions in [`Dvt::tree`] are its world coordinates.
    pub grid: DvtGrid,
    /// The tree: one saddle per `N` edge, in the order of the saddles' ids.
    pub tree: DivideTree,
    /// Saddles the file lists that no edge uses (basin saddles and the like), dropped.
    pub unlinked_saddles: usize,
    /// Runoffs the file lists (an unfinished tile's tree), ignored.
    pub runoffs: usize,
}

impl Dvt {
    /// Parses a `.dvt` file.
    ///
    /// # Errors
    /// [`OrometryError::Dvt`] naming the first malformed line (with its number), a reference to a
    /// peak or saddle that does not exist, a saddle used by two edges, or a tree that breaks
    /// [`DivideTree::validate`] (a saddle above a peak it joins).
    pub fn parse(text: &str) -> Result<Self, OrometryError> {
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(k, l)| (k + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        let Some((_, first)) = lines.next() else {
            return Err(dvt_error("the file holds no grid line and no tree".to_owned()));
        };
        let grid = DvtGrid::parse(first)?;
        let mut file = Parsed::default();
        for (number, line) in lines {
            file.line(&grid, line).map_err(|e| match e {
                OrometryError::Dvt(reason) => dvt_error(format!("line {number}: {reason}")),
                other => other,
            })?;
        }
        file.finish(grid)
    }
}

/// Peaks, saddles and edges as read, before they become a tree.
#[derive(Default)]
struct Parsed {
    peaks: Vec<TreePeak>,
    saddles: Vec<(DVec2, f64)>,
    /// `(peak, parent, saddle)`, 0-based.
    edges: Vec<(u32, u32, u32)>,
    nodes: usize,
    runoffs: usize,
}

impl Parsed {
    fn line(&mut self, grid: &DvtGrid, line: &str) -> Result<(), OrometryError> {
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        let expect = |n: usize| {
            if f.len() == n { Ok(()) } else { Err(dvt_error(format!("`{line}` has {} fields, not {n}", f.len()))) }
        };
        let at = |c: &str, r: &str| -> Result<DVec2, OrometryError> {
            Ok(grid.position(number(c, "column")?, number(r, "row")?))
        };
        match f[0] {
            "P" => {
                expect(5)?;
                self.peaks.push(TreePeak { position: at(f[2], f[3])?, elevation: elevation(f[4])? });
            }
            "S" => {
                expect(6)?;
                self.saddles.push((at(f[3], f[4])?, elevation(f[5])?));
            }
            "R" => {
                expect(7)?;
                self.runoffs += 1;
            }
            "E" => expect(3)?,
            "N" => {
                expect(4)?;
                let (parent, saddle): (i64, i64) = (number(f[2], "parent")?, number(f[3], "saddle")?);
                let node = self.nodes;
                self.nodes += 1;
                if node == 0 || parent == -1 {
                    return Ok(());
                }
                let id = |v: i64, what: &str| {
                    u32::try_from(v - 1).map_err(|_| dvt_error(format!("`{line}`: {what} {v} is not an id")))
                };
                if saddle == -1 {
                    return Err(dvt_error(format!("`{line}`: a peak with a parent needs a saddle")));
                }
                self.edges.push((node as u32 - 1, id(parent, "parent")?, id(saddle, "saddle")?));
            }
            other => return Err(dvt_error(format!("unknown line kind `{other}` in `{line}`"))),
        }
        Ok(())
    }

    fn finish(self, grid: DvtGrid) -> Result<Dvt, OrometryError> {
        let (np, ns) = (self.peaks.len(), self.saddles.len());
        if self.nodes != 0 && self.nodes != np + 1 {
            return Err(dvt_error(format!(
                "{} N lines for {np} peaks: expected one per peak after node 0",
                self.nodes
            )));
        }
        let mut used = vec![false; ns];
        let mut edges = self.edges;
        edges.sort_by_key(|e| e.2);
        let mut saddles = Vec::with_capacity(edges.len());
        for (peak, parent, saddle) in edges {
            if parent as usize >= np || saddle as usize >= ns {
                return Err(dvt_error(format!(
                    "peak {} is joined to peak {} through saddle {}, but there are {np} peaks and {ns} saddles",
                    peak + 1,
                    parent + 1,
                    saddle + 1
                )));
            }
            if std::mem::replace(&mut used[saddle as usize], true) {
                return Err(dvt_error(format!("saddle {} joins more than one pair of peaks", saddle + 1)));
            }
            let (position, elevation) = self.saddles[saddle as usize];
            saddles.push(TreeSaddle { position, elevation, peaks: [peak, parent] });
        }
        let tree = DivideTree { peaks: self.peaks, saddles };
        tree.validate().map_err(|e| dvt_error(e.to_string()))?;
        let unlinked_saddles = used.iter().filter(|&&u| !u).count();
        Ok(Dvt { grid, tree, unlinked_saddles, runoffs: self.runoffs })
    }
}

impl fmt::Display for Dvt {
    /// The file akirmse's program would write for this tree: each component rooted at its
    /// highest peak, every saddle of the spanning tree a prominence saddle (`p`); saddles that
    /// close a cycle (possible after edits) are listed as basin saddles (`b`) on no edge.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let tree = &self.tree;
        let (parent, saddle_of) = rooted(tree);
        let mut out = String::with_capacity(32 * (tree.peaks.len() + tree.saddles.len()) + 64);
        let _ = writeln!(out, "# Divide tree written by relief {}", env!("CARGO_PKG_VERSION"));
        let _ = writeln!(out, "{}", self.grid.header());
        for (k, p) in tree.peaks.iter().enumerate() {
            let [c, r] = self.grid.sample(p.position);
            let _ = writeln!(out, "P,{},{c},{r},{:.2}", k + 1, p.elevation);
        }
        let mut on_edge = vec![false; tree.saddles.len()];
        for &s in saddle_of.iter().flatten() {
            on_edge[s as usize] = true;
        }
        for (k, s) in tree.saddles.iter().enumerate() {
            let [c, r] = self.grid.sample(s.position);
            let kind = if on_edge[k] { 'p' } else { 'b' };
            let _ = writeln!(out, "S,{},{kind},{c},{r},{:.2}", k + 1, s.elevation);
        }
        out.push_str("N,0,-1,-1\n");
        for (k, (p, s)) in parent.iter().zip(&saddle_of).enumerate() {
            let id = |v: Option<u32>| v.map_or(-1, |v| i64::from(v) + 1);
            let _ = writeln!(out, "N,{},{},{}", k + 1, id(*p), id(*s));
        }
        f.write_str(&out)
    }
}

/// Per peak, its parent and the saddle to it with each component rooted at its highest peak
/// (ties: the lower index): the spanning forest of the saddles taken highest first, as the
/// prominence flood takes them.
fn rooted(tree: &DivideTree) -> (Vec<Option<u32>>, Vec<Option<u32>>) {
    let n = tree.peaks.len();
    let mut order: Vec<u32> = (0..tree.saddles.len() as u32).collect();
    order.sort_by(|&a, &b| {
        tree.saddles[b as usize].elevation.total_cmp(&tree.saddles[a as usize].elevation).then(a.cmp(&b))
    });
    let mut uf: Vec<u32> = (0..n as u32).collect();
    let mut adjacent: Vec<Vec<(u32, u32)>> = vec![Vec::new(); n];
    for s in order {
        let [a, b] = tree.saddles[s as usize].peaks;
        let (ra, rb) = (find(&mut uf, a), find(&mut uf, b));
        if ra != rb {
            uf[ra as usize] = rb;
            adjacent[a as usize].push((b, s));
            adjacent[b as usize].push((a, s));
        }
    }
    let mut by_height: Vec<u32> = (0..n as u32).collect();
    by_height.sort_by(|&a, &b| {
        tree.peaks[b as usize].elevation.total_cmp(&tree.peaks[a as usize].elevation).then(a.cmp(&b))
    });
    let (mut parent, mut saddle) = (vec![None; n], vec![None; n]);
    let mut seen = vec![false; n];
    let mut stack = Vec::new();
    for root in by_height {
        if seen[root as usize] {
            continue;
        }
        seen[root as usize] = true;
        stack.push(root);
        while let Some(p) = stack.pop() {
            for &(q, s) in &adjacent[p as usize] {
                if !seen[q as usize] {
                    seen[q as usize] = true;
                    parent[q as usize] = Some(p);
                    saddle[q as usize] = Some(s);
                    stack.push(q);
                }
            }
        }
    }
    (parent, saddle)
}

fn dvt_error(reason: String) -> OrometryError {
    OrometryError::Dvt(reason)
}

/// A field as a number, or an error naming it.
fn number<T: std::str::FromStr>(field: &str, what: &str) -> Result<T, OrometryError> {
    field.parse().map_err(|_| dvt_error(format!("{what} `{field}` is not a number of the expected kind")))
}

/// A finite elevation.
fn elevation(field: &str) -> Result<f64, OrometryError> {
    let v: f64 = number(field, "elevation")?;
    if v.is_finite() { Ok(v) } else { Err(dvt_error(format!("elevation `{field}` is not finite"))) }
}
