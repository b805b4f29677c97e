//! Contour sets as GeoJSON and SVG, contour overlays on previews, and divide trees as GeoJSON or
//! akirmse/mountains' `.dvt` and peak lists as CSV.

use std::fmt::Write as _;

use glam::DVec2;
use rayon::prelude::*;
use serde_json::json;

use crate::contours::ContourSet;
use crate::heightfield::{Crs, Extent, GridSpec, Heightfield};
use crate::io::{RgbImage, ShadeOptions, shaded_relief};
use crate::orometry::{DivideTree, Dvt, DvtGrid, Orometry, OrometryError};

/// The contours as a GeoJSON `FeatureCollection` of `LineString`s (closed ones repeat their first
/// point), each with properties `id`, `elevation`, `level`, `closed` and `parent` (the id of the
/// innermost contour around it, or null) — the lines `gdal_contour` produces, plus the nesting
/// (run the other way: higher ground on the left, so closed lines go counter-clockwise round hills).
/// With an EPSG-coded `crs`, the collection names it in a `crs` member as GDAL writes it
/// ([`geojson_crs_name`]), so GIS tools place metre coordinates where they belong.
/// [`write_contours_geojson`] streams the same text to a writer.
pub fn contours_geojson(set: &ContourSet, crs: Option<&Crs>) -> String {
    let mut bytes = Vec::new();
    // Writing to memory cannot fail, and the writer produces UTF-8.
    let _ = write_contours_geojson(set, crs, &mut bytes);
    String::from_utf8(bytes).unwrap_or_default()
}

/// Streams [`contours_geojson`]'s text to `w` feature by feature, holding no copy of the whole
/// (a contour map of a large DEM runs to hundreds of megabytes).
///
/// # Errors
/// The writer's.
pub fn write_contours_geojson(set: &ContourSet, crs: Option<&Crs>, w: &mut dyn std::io::Write) -> std::io::Result<()> {
    w.write_all(b"{")?;
    if let Some(name) = crs.and_then(geojson_crs_name) {
        write!(w, r#""crs":{{"properties":{{"name":"{name}"}},"type":"name"}},"#)?;
    }
    w.write_all(br#""features":["#)?;
    // Features are formatted in parallel, a batch of chunks at a time (so the text is never all
    // in memory), and written in order: the bytes do not depend on the thread count.
    let mut chunks = Vec::new();
    let mut start = 0;
    let mut vertices = 0;
    for (k, c) in set.contours().iter().enumerate() {
        vertices += c.points.len();
        if vertices >= GEOJSON_CHUNK_VERTICES || k + 1 == set.len() {
            chunks.push(start..k + 1);
            (start, vertices) = (k + 1, 0);
        }
    }
    for batch in chunks.chunks(2 * rayon::current_num_threads()) {
        let parts: Vec<Vec<u8>> = batch
            .par_iter()
            .map(|chunk| {
                let mut text = Vec::new();
                for k in chunk.clone() {
                    contour_feature(set, k, &mut text);
                }
                text
            })
            .collect();
        for part in parts {
            w.write_all(&part)?;
        }
    }
    w.write_all(br#"],"type":"FeatureCollection"}"#)
}

/// About how many vertices one thread formats at a time (some 40 bytes of text each).
const GEOJSON_CHUNK_VERTICES: usize = 1 << 15;

/// Appends contour `k` as a GeoJSON feature (after a comma unless it is the first).
fn contour_feature(set: &ContourSet, k: usize, text: &mut Vec<u8>) {
    use std::io::Write as _;
    // Writing to memory cannot fail, and serde_json formats every finite f64.
    let number = |text: &mut Vec<u8>, x: f64| serde_json::to_writer(&mut *text, &x).expect("a number");
    let c = &set.contours()[k];
    if k > 0 {
        text.push(b',');
    }
    text.extend_from_slice(br#"{"geometry":{"coordinates":["#);
    let closing = c.closed.then(|| c.points[0]);
    for (i, p) in c.points.iter().chain(closing.iter()).enumerate() {
        text.extend_from_slice(if i == 0 { b"[" } else { b",[" });
        number(text, p.x);
        text.push(b',');
        number(text, p.y);
        text.push(b']');
    }
    let _ = write!(text, r#"],"type":"LineString"}},"properties":{{"closed":{},"elevation":"#, c.closed);
    number(text, c.height);
    let _ = write!(text, r#","id":{k},"level":{},"parent":"#, c.level);
    let _ = match set.parent(k) {
        Some(p) => write!(text, "{p}"),
        None => text.write_all(b"null"),
    };
    text.extend_from_slice(br#"},"type":"Feature"}"#);
}

/// The name a GeoJSON `crs` member gives `crs`, as GDAL writes it: `urn:ogc:def:crs:EPSG::n`, or
/// `urn:ogc:def:crs:OGC:1.3:CRS84` for WGS 84 (EPSG:4326 in longitude, latitude order). `None`
/// without an EPSG code (GeoJSON has no place for WKT).
pub fn geojson_crs_name(crs: &Crs) -> Option<String> {
    match crs.epsg()? {
        4326 => Some("urn:ogc:def:crs:OGC:1.3:CRS84".to_owned()),
        code => Some(format!("urn:ogc:def:crs:EPSG::{code}")),
    }
}

/// A divide tree as a GeoJSON `FeatureCollection`: peaks and saddles as `Point`s (property
/// `kind`: `peak` or `saddle`) and each ridge pair as a `LineString` peak → saddle → peak (`kind`:
/// `ridge`), along the DEM's cells where the analysis traced it ([`Saddle::ridge`](crate::orometry::Saddle::ridge), with
/// `AnalysisOptions::ridge_lines`), else straight. Coordinates are the grid's world coordinates, so a geographic DEM gives
/// longitude/latitude. With the analysis the tree came from, peaks carry its measures
/// (prominence, dominance, isolation, ...), and ridges name the peak they are the key saddle of.
/// With an EPSG-coded `crs`, the collection names it as [`contours_geojson`] does.
pub fn divide_tree_geojson(tree: &DivideTree, analysis: Option<&Orometry>, crs: Option<&Crs>) -> String {
    let mut features = Vec::with_capacity(tree.peaks.len() + 2 * tree.saddles.len());
    for (k, p) in tree.peaks.iter().enumerate() {
        let mut props = json!({ "kind": "peak", "id": k, "elevation": p.elevation });
        if let Some(a) = analysis.and_then(|a| a.peaks.get(k)) {
            let extra = json!({
                "prominence": a.prominence,
                "dominance": a.dominance,
                "relative_prominence": a.relative_prominence,
                "relevance": a.relevance,
                "isolation_m": a.isolation.map(|i| i.distance),
                "isolation_azimuth": a.isolation.map(|i| i.azimuth),
                "key_saddle": a.key_saddle,
                "parent": a.parent,
                "edge_effect": a.edge_effect,
            });
            if let (Some(props), Some(extra)) = (props.as_object_mut(), extra.as_object()) {
                props.extend(extra.clone());
            }
        }
        features.push(json!({
            "type": "Feature",
            "properties": props,
            "geometry": { "type": "Point", "coordinates": [p.position.x, p.position.y] },
        }));
    }
    for (k, s) in tree.saddles.iter().enumerate() {
        let [a, b] = s.peaks.map(|p| tree.peaks[p as usize].position);
        let traced = analysis.and_then(|a| a.saddles.get(k)).filter(|t| !t.ridge.is_empty());
        let line =
            traced.map_or_else(|| json!([[a.x, a.y], [s.position.x, s.position.y], [b.x, b.y]]), |t| json!(t.ridge));
        features.push(json!({
            "type": "Feature",
            "properties": { "kind": "saddle", "id": k, "elevation": s.elevation, "peaks": s.peaks },
            "geometry": { "type": "Point", "coordinates": [s.position.x, s.position.y] },
        }));
        features.push(json!({
            "type": "Feature",
            "properties": { "kind": "ridge", "saddle": k, "peaks": s.peaks },
            "geometry": { "type": "LineString", "coordinates": line },
        }));
    }
    let mut collection = json!({ "type": "FeatureCollection", "features": features });
    if let Some(name) = crs.and_then(geojson_crs_name) {
        collection["crs"] = json!({ "type": "name", "properties": { "name": name } });
    }
    serde_json::to_string(&collection).unwrap_or_default()
}

/// A crest skeleton (§5.1 of the vector-terrain paper) as GeoJSON: each node a point with its
/// `id` (what a crest tool's `node` takes), its `elevation` on `terrain` (a continuous query,
/// no raster) and its `degree`; each edge a line with its `id` and its nodes `from`, `to`.
///
/// # Errors
/// The terrain's [`crate::gaussian_terrain::VectorTerrain::query`] errors.
pub fn skeleton_geojson(
    skeleton: &crate::gaussian_terrain::Skeleton,
    terrain: &crate::gaussian_terrain::VectorTerrain,
    crs: Option<&Crs>,
) -> Result<String, crate::gaussian_terrain::GaussianError> {
    let points: Vec<glam::DVec2> = skeleton.nodes.iter().map(|&p| glam::DVec2::from(p)).collect();
    let elevations = terrain.query()?.elevations(&points);
    let mut degree = vec![0usize; points.len()];
    for &[a, b] in &skeleton.edges {
        degree[a] += 1;
        degree[b] += 1;
    }
    let nodes = points.iter().zip(&elevations).zip(&degree).enumerate().map(|(id, ((p, h), d))| {
        json!({
            "type": "Feature",
            "properties": { "kind": "node", "id": id, "elevation": h, "degree": d },
            "geometry": { "type": "Point", "coordinates": [p.x, p.y] },
        })
    });
    let edges = skeleton.edges.iter().enumerate().map(|(id, &[a, b])| {
        json!({
            "type": "Feature",
            "properties": { "kind": "edge", "id": id, "from": a, "to": b },
            "geometry": { "type": "LineString", "coordinates": [skeleton.nodes[a], skeleton.nodes[b]] },
        })
    });
    let mut collection = json!({ "type": "FeatureCollection", "features": nodes.chain(edges).collect::<Vec<_>>() });
    if let Some(name) = crs.and_then(geojson_crs_name) {
        collection["crs"] = json!({ "type": "name", "properties": { "name": name } });
    }
    Ok(serde_json::to_string(&collection).unwrap_or_default())
}

/// The analysed peaks as CSV, highest first: position (`lon,lat` for geographic grids, else
/// `x,y`), elevation, prominence, the key saddle's position and elevation, the prominence parent's
/// and the line parent's ids ([`Orometry::line_parents`]), dominance, relative prominence,
/// relevance, isolation distance (m), azimuth (°) and limit point (the nearest higher sample),
/// and the edge-effect flag. Empty fields mean "none" (the highest peak has no key saddle,
/// parents or isolation).
pub fn peaks_csv(analysis: &Orometry, geographic: bool) -> String {
    let (x, y) = if geographic { ("lon", "lat") } else { ("x", "y") };
    let mut out = format!(
        "id,{x},{y},elevation,prominence,saddle_{x},saddle_{y},saddle_elevation,prominence_parent,line_parent,\
         dominance,relative_prominence,relevance,isolation_m,isolation_azimuth,isolation_{x},isolation_{y},edge_effect\n"
    );
    let opt = |v: Option<f64>| v.map_or_else(String::new, |v| v.to_string());
    let id = |v: Option<usize>| v.map_or_else(String::new, |v| v.to_string());
    let line = analysis.line_parents();
    for (k, p) in analysis.peaks.iter().enumerate() {
        let saddle = p.key_saddle.map(|s| &analysis.saddles[s]);
        let _ = writeln!(
            out,
            "{k},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            p.position[0],
            p.position[1],
            p.elevation,
            p.prominence,
            opt(saddle.map(|s| s.position[0])),
            opt(saddle.map(|s| s.position[1])),
            opt(saddle.map(|s| s.elevation)),
            id(p.parent),
            id(line[k]),
            p.dominance,
            p.relative_prominence,
            p.relevance,
            opt(p.isolation.map(|i| i.distance)),
            opt(p.isolation.map(|i| i.azimuth)),
            opt(p.isolation.map(|i| i.to[0])),
            opt(p.isolation.map(|i| i.to[1])),
            p.edge_effect,
        );
    }
    out
}

/// The peaks of a divide tree (one read from a `.dvt` file, say) as CSV, most prominent first:
/// id (the tree's index), position, elevation, prominence on the tree down to `base`, and the key
/// saddle's position and elevation (empty for a component's top).
pub fn tree_peaks_csv(tree: &DivideTree, base: f64, geographic: bool) -> String {
    let (x, y) = if geographic { ("lon", "lat") } else { ("x", "y") };
    let mut out = format!("id,{x},{y},elevation,prominence,saddle_{x},saddle_{y},saddle_elevation\n");
    let oro = tree.orometry(base);
    let mut order: Vec<usize> = (0..tree.peaks.len()).collect();
    order.sort_by(|&a, &b| oro.prominence[b].total_cmp(&oro.prominence[a]).then(a.cmp(&b)));
    for k in order {
        let p = &tree.peaks[k];
        let saddle = oro.key_saddle[k].map_or_else(
            || ",,".to_owned(),
            |s| {
                let s = &tree.saddles[s as usize];
                format!("{},{},{}", s.position.x, s.position.y, s.elevation)
            },
        );
        let _ = writeln!(out, "{k},{},{},{},{},{saddle}", p.position.x, p.position.y, p.elevation, oro.prominence[k]);
    }
    out
}

/// The analysed peaks as the lines of akirmse/mountains' `prominence.txt`, most prominent first:
/// `lat,lon,elevation,key_saddle_lat,key_saddle_lon,prominence` (for a projected grid `y,x` in
/// the same places), no header, positions to 6 decimals and heights to 2; a peak without a key
/// saddle (a land mass's top) has the saddle `0,0`, as akirmse writes it.
pub fn peaks_akirmse(analysis: &Orometry) -> String {
    let lines = analysis.peaks.iter().map(|p| {
        let saddle = p.key_saddle.map(|s| analysis.saddles[s].position);
        (p.position, p.elevation, saddle, p.prominence)
    });
    akirmse_lines(lines.collect())
}

/// [`peaks_akirmse`] for the peaks of a divide tree, their prominences on the tree down to
/// `base`.
pub fn tree_peaks_akirmse(tree: &DivideTree, base: f64) -> String {
    let oro = tree.orometry(base);
    let lines = tree.peaks.iter().enumerate().map(|(k, p)| {
        let saddle = oro.key_saddle[k].map(|s| {
            let s = &tree.saddles[s as usize];
            [s.position.x, s.position.y]
        });
        ([p.position.x, p.position.y], p.elevation, saddle, oro.prominence[k])
    });
    akirmse_lines(lines.collect())
}

/// One peak: position `[x, y]`, elevation, key saddle position, prominence.
type AkirmseLine = ([f64; 2], f64, Option<[f64; 2]>, f64);

/// `prominence.txt` lines of `peaks`, most prominent first (ties in the given order).
fn akirmse_lines(mut peaks: Vec<AkirmseLine>) -> String {
    peaks.sort_by(|a, b| b.3.total_cmp(&a.3));
    let mut out = String::new();
    for (p, elevation, saddle, prominence) in peaks {
        let s = saddle.unwrap_or([0.0, 0.0]);
        let _ = writeln!(out, "{:.6},{:.6},{elevation:.2},{:.6},{:.6},{prominence:.2}", p[1], p[0], s[1], s[0]);
    }
    out
}

/// A divide tree in akirmse/mountains' `.dvt` text format ([`Dvt`]) on the lattice of the DEM's
/// `grid` (and coordinate system), so its tools read it.
///
/// # Errors
/// [`OrometryError::Dvt`] when the format cannot hold the grid ([`DvtGrid::for_grid`]).
pub fn divide_tree_dvt(tree: &DivideTree, grid: &GridSpec, crs: Option<&Crs>) -> Result<String, OrometryError> {
    let grid = DvtGrid::for_grid(grid, crs)?;
    Ok(Dvt { grid, tree: tree.clone(), unlinked_saddles: 0, runoffs: 0 }.to_string())
}

/// A colour for a relative elevation `t` in [0, 1]: the hypsometric ramp of the previews, darkened
/// for lines.
fn line_colour(t: f64) -> [u8; 3] {
    const STOPS: [(f64, [f64; 3]); 4] = [
        (0.0, [30.0, 90.0, 50.0]),
        (0.4, [110.0, 100.0, 40.0]),
        (0.75, [120.0, 70.0, 30.0]),
        (1.0, [70.0, 60.0, 60.0]),
    ];
    let t = t.clamp(0.0, 1.0);
    let k = STOPS.iter().rposition(|s| s.0 <= t).unwrap_or(0).min(STOPS.len() - 2);
    let ((t0, a), (t1, b)) = (STOPS[k], STOPS[k + 1]);
    let u = (t - t0) / (t1 - t0);
    [0, 1, 2].map(|i| (a[i] + u * (b[i] - a[i])).round() as u8)
}

/// The contours as an SVG drawing of the `extent` rectangle, `width` pixels wide (north up),
/// coloured by elevation; every fifth level is drawn thicker, as on topographic maps.
pub fn contours_svg(set: &ContourSet, extent: &Extent, width: u32) -> String {
    let size = extent.size();
    let w = f64::from(width.max(1));
    let h = (w * size.y / size.x.max(f64::MIN_POSITIVE)).round().max(1.0);
    let to_px = |p: DVec2| ((p.x - extent.min.x) / size.x * w, (extent.max.y - p.y) / size.y * h);
    let levels = set.levels();
    let (lo, hi) = (levels.first().copied().unwrap_or(0.0), levels.last().copied().unwrap_or(1.0));
    let mut out = String::new();
    let _ = writeln!(out, r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}">"#);
    let _ = writeln!(out, r##"<rect width="100%" height="100%" fill="#f7f4ec"/>"##);
    for c in set.contours() {
        let [r, g, b] = line_colour(if hi > lo { (c.height - lo) / (hi - lo) } else { 0.5 });
        let stroke = if c.level % 5 == 4 { 1.6 } else { 0.7 };
        let mut d = String::new();
        for (i, p) in c.points.iter().enumerate() {
            let (x, y) = to_px(*p);
            let _ = write!(d, "{}{x:.2} {y:.2}", if i == 0 { "M" } else { " L" });
        }
        if c.closed {
            d.push_str(" Z");
        }
        let _ = writeln!(
            out,
            r#"<path d="{d}" fill="none" stroke="rgb({r},{g},{b})" stroke-width="{stroke}"><title>{}</title></path>"#,
            c.height
        );
    }
    out.push_str("</svg>\n");
    out
}

/// Draws the contours on a north-up image of `extent` (a shaded-relief preview), one pixel wide,
/// darkening what is underneath; every fifth level darker still.
pub fn draw_contours(image: &mut RgbImage, set: &ContourSet, extent: &Extent) {
    let (w, h) = (image.width, image.height);
    if w < 2 || h < 2 {
        return;
    }
    let size = extent.size();
    let to_px = |p: DVec2| {
        DVec2::new((p.x - extent.min.x) / size.x * (w - 1) as f64, (extent.max.y - p.y) / size.y * (h - 1) as f64)
    };
    for c in set.contours() {
        let shade = if c.level % 5 == 4 { 0.45 } else { 0.7 };
        for [a, b] in c.segments() {
            let (pa, pb) = (to_px(a), to_px(b));
            let steps = (pb - pa).abs().max_element().ceil().max(1.0) as usize;
            for s in 0..=steps {
                let q = pa + (pb - pa) * (s as f64 / steps as f64);
                let (x, y) = (q.x.round(), q.y.round());
                if x < 0.0 || y < 0.0 || x >= w as f64 || y >= h as f64 {
                    continue;
                }
                let k = 3 * (y as usize * w + x as usize);
                for v in &mut image.pixels[k..k + 3] {
                    *v = (f64::from(*v) * shade) as u8;
                }
            }
        }
    }
}

/// A north-up shaded-relief preview of `dem` (hillshade × hypsometric tint, water below
/// `sea_level`), with `contours` drawn on it when given.
pub fn preview_image(dem: &Heightfield, contours: Option<&ContourSet>, sea_level: Option<f64>) -> RgbImage {
    let mut image = shaded_relief(dem, &ShadeOptions::default().with_sea_level(sea_level));
    if let Some(set) = contours {
        draw_contours(&mut image, set, &dem.extent());
    }
    image
}
