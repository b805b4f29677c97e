//! Raster contours beside `gdal_contour`'s on the same DEM (`fixtures/gdal/`: counts from one run
//! of GDAL 3.6.2, committed). The lines are marching squares' lines like GDAL's, so the vertex
//! counts agree closely; the line counts differ a little where saddles split the other way (ours
//! along the south-west–north-east diagonal, GDAL's by the cell's mean) and at the raster's edge
//! (GDAL carries lines half a cell further, to the outer edge).

use std::path::Path;

use relief::contours::extract_dem;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

#[test]
fn jacksboro_contours_have_gdal_contours_vertices_and_about_its_lines() {
    let reference: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(root().join("fixtures/gdal/jacksboro-50m.json")).unwrap())
            .unwrap();
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
    let (mut lines, mut vertices) = (0, 0);
    let (mut gdal_lines, mut gdal_vertices) = (0, 0);
    for &(h, gl, gv) in &levels {
        let ours: Vec<_> = set.contours().iter().filter(|c| c.height == h).collect();
        // GeoJSON repeats a closed line's first point; count the same way.
        let v: usize = ours.iter().map(|c| c.points.len() + usize::from(c.closed)).sum();
        let off = |a: usize, b: usize| a.abs_diff(b) as f64 / b.max(1) as f64;
        assert!(off(v, gv) < 0.03 || v.abs_diff(gv) <= 2, "{h} m: {v} vertices, gdal_contour {gv}");
        assert!(
            off(ours.len(), gl) < 0.2 || ours.len().abs_diff(gl) <= 2,
            "{h} m: {} lines, gdal_contour {gl}",
            ours.len()
        );
        (lines, vertices, gdal_lines, gdal_vertices) =
            (lines + ours.len(), vertices + v, gdal_lines + gl, gdal_vertices + gv);
    }
    // Over all levels: vertices within 1 %, lines within 3 %.
    assert!(
        vertices.abs_diff(gdal_vertices) * 100 < gdal_vertices,
        "{vertices} vertices, gdal_contour {gdal_vertices}"
    );
    assert!(lines.abs_diff(gdal_lines) * 100 < 3 * gdal_lines, "{lines} lines, gdal_contour {gdal_lines}");
}
