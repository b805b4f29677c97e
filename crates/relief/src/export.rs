//! Contour sets as GeoJSON and SVG, and contour overlays on previews.

use std::fmt::Write as _;

use glam::DVec2;
use serde_json::json;

use crate::contours::ContourSet;
use crate::heightfield::{Extent, Heightfield};
use crate::io::{RgbImage, ShadeOptions, shaded_relief};

/// The contours as a GeoJSON `FeatureCollection` of `LineString`s (closed ones repeat their first
/// point), each with properties `id`, `elevation`, `level`, `closed` and `parent` (the id of the
/// innermost contour around it, or null) — the shape `gdal_contour` produces, plus the nesting.
pub fn contours_geojson(set: &ContourSet) -> String {
    let features: Vec<serde_json::Value> = set
        .contours()
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let mut coords: Vec<[f64; 2]> = c.points.iter().map(|p| [p.x, p.y]).collect();
            if c.closed {
                coords.push([c.points[0].x, c.points[0].y]);
            }
            json!({
                "type": "Feature",
                "properties": { "id": k, "elevation": c.height, "level": c.level, "closed": c.closed, "parent": set.parent(k) },
                "geometry": { "type": "LineString", "coordinates": coords },
            })
        })
        .collect();
    let collection = json!({ "type": "FeatureCollection", "features": features });
    serde_json::to_string(&collection).unwrap_or_default()
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
