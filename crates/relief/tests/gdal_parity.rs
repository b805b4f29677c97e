//! Raster contours beside `gdal_contour`'s on the same DEMs (`fixtures/gdal/`: outputs of one run of
//! GDAL 3.6.2, committed with the commands that made them): the same lines, level by level.

use std::collections::HashMap;
use std::path::Path;

use glam::DVec2;
use relief::contours::extract_dem;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn json(path: &str) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(root().join(path)).unwrap()).unwrap()
}

#[test]
fn jacksboro_contours_have_gdal_contours_lines_and_vertices_at_every_level() {
    let reference = json("fixtures/gdal/jacksboro-50m.json");
    let levels: Vec<(f64, usize, usize)> = reference["levels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| {
            (
                l["elevation"].as_f64().unwrap(),
                l["lines"].as_u64().unwrap() as usize,
                l["vertices"].as_u64().unwrap() as usize,
            )
        })
        .collect();
    let dem = relief::io::read(root().join("fixtures/dem/jacksboro.asc")).unwrap();
    let heights: Vec<f64> = levels.iter().map(|l| l.0).collect();
    let set = extract_dem(&dem, &heights).unwrap();
    set.check_invariants().unwrap();
    for &(h, gdal_lines, gdal_vertices) in &levels {
        let ours: Vec<_> = set.contours().iter().filter(|c| c.height == h).collect();
        // GeoJSON repeats a closed line's first point; count the same way.
        let vertices: usize = ours.iter().map(|c| c.points.len() + usize::from(c.closed)).sum();
        assert_eq!((ours.len(), vertices), (gdal_lines, gdal_vertices), "{h} m: lines and vertices");
    }
}

/// GDAL's lines at each elevation, as point lists (a closed line's repeated first point dropped).
fn gdal_lines(path: &str) -> HashMap<u64, Vec<(bool, Vec<DVec2>)>> {
    let mut lines: HashMap<u64, Vec<(bool, Vec<DVec2>)>> = HashMap::new();
    for feature in json(path)["features"].as_array().unwrap() {
        let elevation = feature["properties"]["elev"].as_f64().unwrap();
        let mut points: Vec<DVec2> = feature["geometry"]["coordinates"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| DVec2::new(p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
            .collect();
        let closed = points.len() > 2 && points[0] == points[points.len() - 1];
        if closed {
            points.pop();
        }
        lines.entry(elevation.to_bits()).or_default().push((closed, points));
    }
    lines
}

/// Whether `ours` is `theirs` run backwards (GDAL keeps higher ground on the right), from any
/// starting point of a closed line, within `tol`.
fn same_line(ours: &[DVec2], closed: bool, theirs: &[DVec2], tol: f64) -> bool {
    let n = theirs.len();
    if ours.len() != n {
        return false;
    }
    let reversed: Vec<DVec2> = theirs.iter().rev().copied().collect();
    let shifts = if closed { n } else { 1 };
    (0..shifts).any(|s| (0..n).all(|i| ours[i].distance(reversed[(i + s) % n]) < tol))
}

#[test]
fn contours_of_a_dem_with_holes_are_gdal_contours_lines_point_for_point() {
    // Jacksboro's elevations on 30 m cells with no-data blocks inside, on the border and in a
    // corner: lines end half-way to missing samples and run on to the raster's outer edge.
    let dem = relief::io::read(root().join("fixtures/gdal/holes.asc")).unwrap();
    assert!(dem.samples().iter().filter(|h| h.is_nan()).count() > 30);
    let gdal = gdal_lines("fixtures/gdal/holes-20m.geojson");
    let mut levels: Vec<f64> = gdal.keys().map(|&b| f64::from_bits(b)).collect();
    levels.sort_by(f64::total_cmp);
    let set = extract_dem(&dem, &levels).unwrap();
    set.check_invariants().unwrap();
    assert_eq!(set.len(), gdal.values().map(Vec::len).sum::<usize>(), "as many lines as GDAL draws");
    for (h, lines) in &gdal {
        let ours: Vec<_> = set.contours().iter().filter(|c| c.height.to_bits() == *h).collect();
        for (closed, theirs) in lines {
            assert!(
                ours.iter().any(|c| c.closed == *closed && same_line(&c.points, *closed, theirs, 1e-6)),
                "GDAL's {} m line from {:?} is not ours",
                f64::from_bits(*h),
                theirs[0]
            );
        }
    }
}
