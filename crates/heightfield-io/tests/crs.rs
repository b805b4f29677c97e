//! Coordinate reference systems end to end: GDAL-written `GeoTIFF`s in a projected metric CRS, a US
//! survey feet CRS and a non-WGS 84 geographic CRS (fixtures/gdal, made by the commands in its
//! README) keep their EPSG code and units through every format that can carry them, `.prj` files
//! are read and written, and the ASCII grid guess and the overrides do what they say.

mod common;

use glam::DVec2;
use relief_heightfield::{Crs, GridSpec, Heightfield, Units};
#[cfg(feature = "geotiff")]
use relief_heightfield_io::read_with;
use relief_heightfield_io::{ReadOptions, parse_crs, read, read_with_notes, write};

fn gdal(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/gdal").join(name)
}

/// (fixture, EPSG code, units, cell size in the file's units).
#[cfg(feature = "geotiff")]
const CASES: [(&str, u32, Units, f64); 3] = [
    ("utm17.tif", 32617, Units::Metres, 90.0),
    ("tn-ftus.tif", 2274, Units::UsSurveyFeet, 300.0),
    ("nad83.tif", 4269, Units::Degrees, 0.000_833_333_3),
];

#[cfg(feature = "geotiff")]
#[test]
fn gdal_geotiffs_give_their_epsg_code_and_units() {
    for (file, code, units, cell) in CASES {
        let hf = read(gdal(file)).unwrap();
        let crs = hf.crs().unwrap_or_else(|| panic!("{file}: no CRS"));
        assert_eq!(crs.epsg(), Some(code), "{file}");
        assert!(crs.wkt().is_some_and(|w| w.contains(&format!("\"{code}\""))), "{file}: WKT filled in from EPSG");
        assert_eq!(hf.grid().units(), units, "{file}");
        assert_eq!(hf.grid().cell_size(), DVec2::splat(cell), "{file}");
    }
    // 300 US survey feet are 91.44 m of ground.
    let ft = read(gdal("tn-ftus.tif")).unwrap();
    assert!((ft.grid().cell_size_m(0).x - 91.440_183).abs() < 1e-5);
}

#[cfg(feature = "geotiff")]
#[test]
fn every_format_with_metadata_keeps_the_crs() {
    let dir = tempfile::tempdir().unwrap();
    let mut files = vec!["x.asc", "x.r32", "x.r16"];
    if cfg!(feature = "geotiff") {
        files.push("x.tif");
    }
    if cfg!(feature = "exr") {
        files.push("x.exr");
    }
    if cfg!(feature = "png") {
        files.push("x.png");
    }
    for (fixture, code, units, _) in CASES {
        let hf = read(gdal(fixture)).unwrap();
        for file in &files {
            let path = dir.path().join(file);
            write(&path, &hf).unwrap();
            let back = read(&path).unwrap();
            assert_eq!(back.crs().and_then(Crs::epsg), Some(code), "{fixture} → {file}");
            assert_eq!(back.grid().units(), units, "{fixture} → {file}");
            assert_eq!(back.grid().origin(), hf.grid().origin(), "{fixture} → {file}");
        }
        let prj = std::fs::read_to_string(dir.path().join("x.prj")).unwrap();
        assert!(prj.contains(&format!("AUTHORITY[\"EPSG\",\"{code}\"]")), "{fixture}: .prj is the CRS's WKT");
    }
}

#[test]
fn a_crs_known_only_by_wkt_keeps_its_wkt_and_units() {
    let esri = std::fs::read_to_string(gdal("crs/epsg-2264.esri")).unwrap();
    let crs = Crs::from_wkt(&esri).unwrap();
    let grid = GridSpec::new(5, 4, DVec2::new(2_000_000.0, 500_000.0), DVec2::splat(100.0))
        .unwrap()
        .with_units(Units::UsSurveyFeet)
        .unwrap();
    let hf = Heightfield::from_fn(grid, |p| (p.x * 1e-4) as f32).unwrap().with_crs(Some(crs.clone()));
    let dir = tempfile::tempdir().unwrap();
    for file in ["w.asc", "w.r32"].into_iter().chain(cfg!(feature = "exr").then_some("w.exr")) {
        let path = dir.path().join(file);
        write(&path, &hf).unwrap();
        let back = read(&path).unwrap();
        assert_eq!(back.crs().map(Crs::name), Some(crs.name()), "{file}");
        assert_eq!(back.grid().units(), Units::UsSurveyFeet, "{file}");
    }
    if cfg!(feature = "geotiff") {
        // GeoTIFF keys hold a code or parameters, not WKT: the name and units survive as a
        // user-defined CRS; the name is in GTCitationGeoKey.
        let path = dir.path().join("w.tif");
        write(&path, &hf).unwrap();
        let back = read(&path).unwrap();
        assert_eq!(back.grid().units(), Units::UsSurveyFeet);
        let bytes = std::fs::read(&path).unwrap();
        let name = crs.name();
        assert!(bytes.windows(name.len()).any(|w| w == name.as_bytes()), "citation names the CRS");
    }
}

#[test]
fn unlabelled_grids_write_what_they_always_did() {
    let grid = GridSpec::new(3, 2, DVec2::ZERO, DVec2::ONE).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for (units, marker) in
        [(Units::Metres, "LOCAL_CS"), (Units::Feet, "UNIT[\"foot\",0.3048]"), (Units::Degrees, "\"4326\"")]
    {
        let hf = Heightfield::zeros(grid.with_units(units).unwrap());
        let path = dir.path().join("u.asc");
        write(&path, &hf).unwrap();
        let prj = std::fs::read_to_string(dir.path().join("u.prj")).unwrap();
        assert!(prj.contains(marker), "{units:?}: {prj}");
        let back = read(&path).unwrap();
        assert_eq!(back.grid().units(), units);
        // A local CRS places nothing on Earth: it reads back unlabelled, as it was written.
        assert_eq!(back.crs().is_none(), units != Units::Degrees, "{units:?}");
    }
}

#[test]
fn ascii_grids_without_prj_guess_degrees_only_when_nothing_else_fits() {
    let dir = tempfile::tempdir().unwrap();
    let asc = |name: &str, xll: f64, yll: f64, cell: f64| {
        let path = dir.path().join(name);
        let text = format!("ncols 2\nnrows 2\nxllcorner {xll}\nyllcorner {yll}\ncellsize {cell}\n1 2\n3 4\n");
        std::fs::write(&path, text).unwrap();
        read_with_notes(&path, &ReadOptions::default()).unwrap()
    };
    let (hf, notes) = asc("geo.asc", -84.4, 36.4, 0.000_277_777_8);
    assert_eq!((hf.grid().units(), notes.len()), (Units::Degrees, 1));
    let (hf, notes) = asc("utm.asc", 500_000.0, 4_000_000.0, 0.5);
    assert_eq!((hf.grid().units(), notes.len()), (Units::Metres, 0), "outside ±180/±90: metres");
    let (hf, notes) = asc("coarse.asc", 10.0, 10.0, 30.0);
    assert_eq!((hf.grid().units(), notes.len()), (Units::Metres, 0), "30-unit cells are not degrees");
    let (hf, notes) = asc("arcminute.asc", 10.0, 10.0, 1.0 / 30.0);
    assert_eq!((hf.grid().units(), notes.len()), (Units::Metres, 0), "2′ cells: no guess");
}

#[cfg(feature = "geotiff")]
#[test]
fn overrides_label_and_take_units_from_the_crs() {
    let jacksboro = gdal("../dem/jacksboro.asc");
    let as_utm = read_with(&jacksboro, &ReadOptions::default().with_crs(parse_crs("EPSG:2274").unwrap())).unwrap();
    assert_eq!(as_utm.crs().and_then(Crs::epsg), Some(2274));
    assert_eq!(as_utm.grid().units(), Units::UsSurveyFeet, "the CRS brings its units");
    let both = ReadOptions::default().with_crs(parse_crs("EPSG:2274").unwrap()).with_units(Units::Metres);
    assert_eq!(read_with(&jacksboro, &both).unwrap().grid().units(), Units::Metres, "--units wins");
    let nad = read_with(&jacksboro, &ReadOptions::default().with_crs(parse_crs("epsg:4269").unwrap())).unwrap();
    assert_eq!(nad.grid().units(), Units::Degrees);
    let relabelled = read_with(gdal("utm17.tif"), &ReadOptions::default().with_crs(parse_crs("EPSG:32616").unwrap()));
    assert_eq!(relabelled.unwrap().crs().and_then(Crs::epsg), Some(32616), "the flag replaces the file's CRS");
}

#[test]
fn crs_specs_parse_or_say_why_not() {
    let prj = gdal("crs/epsg-32617.wkt2");
    assert_eq!(parse_crs(prj.to_str().unwrap()).unwrap().epsg(), Some(32617));
    assert_eq!(parse_crs("urn:ogc:def:crs:EPSG::4269").unwrap().units(), Some(Units::Degrees));
    for bad in ["EPSG:", "EPSG:abc", "EPSG:0", "UTM 17", "PROJCS[\"x\"", "/no/such/file.prj"] {
        let e = parse_crs(bad).unwrap_err();
        assert!(!e.to_string().is_empty(), "{bad}");
    }
    // A code outside the tables stays a bare code: still written as a GeoTIFF key.
    let rare = parse_crs("EPSG:900914").unwrap();
    assert_eq!((rare.epsg(), rare.wkt()), (Some(900_914), None));
}

#[test]
fn the_degrees_guess_needs_every_condition() {
    let dir = tempfile::tempdir().unwrap();
    let units = |name: &str, header: &str| {
        let path = dir.path().join(name);
        std::fs::write(&path, format!("ncols 2\nnrows 2\n{header}\n1 2\n3 4\n")).unwrap();
        read_with_notes(&path, &ReadOptions::default()).unwrap().0.grid().units()
    };
    let fine = 0.000_277_777_8;
    // (name, header, expected): each condition broken alone, and the exact edges of the globe.
    let cases = [
        ("west.asc", format!("xllcenter -180.001\nyllcenter 0\ncellsize {fine}"), Units::Metres),
        ("east.asc", format!("xllcenter 179.9999\nyllcenter 0\ncellsize {fine}"), Units::Metres),
        ("south.asc", format!("xllcenter 0\nyllcenter -90.001\ncellsize {fine}"), Units::Metres),
        ("north.asc", format!("xllcenter 0\nyllcenter 89.9999\ncellsize {fine}"), Units::Metres),
        ("coarse-x.asc", format!("xllcenter 0\nyllcenter 0\ndx 0.02\ndy {fine}"), Units::Metres),
        ("coarse-y.asc", format!("xllcenter 0\nyllcenter 0\ndx {fine}\ndy 0.02"), Units::Metres),
        ("sw-edge.asc", format!("xllcenter -180\nyllcenter -90\ncellsize {fine}"), Units::Degrees),
        ("ne-edge.asc", "xllcenter 179.99\nyllcenter 89.99\ncellsize 0.01".to_owned(), Units::Degrees),
        ("arc-minute.asc", "xllcenter 0\nyllcenter 0\ndx 0.0166666\ndy 0.0166666".to_owned(), Units::Degrees),
    ];
    for (name, header, expected) in cases {
        assert_eq!(units(name, &header), expected, "{name}");
    }
}

/// The shared Jacksboro DEM's `.prj` is ESRI's WGS 84 with no authority, as `ArcGIS` writes it. Read
/// as GDAL reads it (EPSG:4326), its GeoTIFF says WGS 84 instead of an unknown user-defined CRS.
#[cfg(feature = "geotiff")]
#[test]
fn an_esri_wgs84_prj_is_epsg_4326_in_every_format() {
    let dem = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/dem/jacksboro.asc");
    let hf = read(&dem).unwrap();
    let crs = hf.crs().expect("the .prj labels it");
    assert_eq!(crs.epsg(), Some(4326));
    assert!(crs.wkt().is_some_and(|w| w.contains("GCS_WGS_1984")), "the file's own WKT is kept");
    let dir = tempfile::tempdir().unwrap();
    for file in ["j.tif", "j.asc", "j.r32"].into_iter().chain(cfg!(feature = "exr").then_some("j.exr")) {
        let path = dir.path().join(file);
        write(&path, &hf).unwrap();
        let back = read(&path).unwrap();
        assert_eq!(back.crs().and_then(Crs::epsg), Some(4326), "{file}");
        assert_eq!(back.grid().units(), Units::Degrees, "{file}");
    }
    // Relabelled to metres (as `--units metres` does), its GeoTIFF gets no projected code 4326,
    // which would read back in degrees.
    let g = *hf.grid();
    let grid = GridSpec::new(g.nx(), g.ny(), g.origin(), g.cell_size()).unwrap().with_units(Units::Metres).unwrap();
    let metres = Heightfield::from_samples(grid, hf.samples().to_vec()).unwrap().with_crs(hf.crs().cloned());
    let path = dir.path().join("m.tif");
    write(&path, &metres).unwrap();
    let back = read(&path).unwrap();
    assert_eq!(back.grid().units(), Units::Metres);
    assert_eq!(back.crs().and_then(Crs::epsg), None);
}
