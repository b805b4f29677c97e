//! `Crs`: WKT 1, WKT 2 and ESRI definitions as GDAL writes them (fixtures/gdal/crs), their EPSG
//! codes, names and units; `Units` names; the CRS kept by derived fields and JSON.

use glam::DVec2;
use relief_heightfield::{Crs, GridSpec, Heightfield, HeightfieldError, Units};

fn fixture(name: &str) -> String {
    let path = format!("{}/../../fixtures/gdal/crs/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

#[test]
fn gdal_wkt_gives_code_name_and_units() {
    let cases = [
        ("epsg-32617.wkt1", Some(32617), "WGS 84 / UTM zone 17N", Units::Metres),
        ("epsg-32617.wkt2", Some(32617), "WGS 84 / UTM zone 17N", Units::Metres),
        ("epsg-2264.wkt1", Some(2264), "NAD83 / North Carolina (ftUS)", Units::UsSurveyFeet),
        ("epsg-2264.wkt2", Some(2264), "NAD83 / North Carolina (ftUS)", Units::UsSurveyFeet),
        ("epsg-2264.esri", None, "NAD_1983_StatePlane_North_Carolina_FIPS_3200_Feet", Units::UsSurveyFeet),
        ("epsg-4269.wkt1", Some(4269), "NAD83", Units::Degrees),
        ("epsg-4269.wkt2", Some(4269), "NAD83", Units::Degrees),
    ];
    for (file, epsg, name, units) in cases {
        let crs = Crs::from_wkt(&fixture(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!(crs.epsg(), epsg, "{file}");
        assert_eq!(crs.name(), name, "{file}");
        assert_eq!(crs.units(), Some(units), "{file}");
        assert!(!crs.is_local(), "{file}");
    }
}

#[test]
fn nested_authorities_are_not_the_crs_code() {
    // Only the root's AUTHORITY names the CRS: the datum's 6326 and the unit's 9001 must not.
    let wkt = r#"PROJCS["custom",GEOGCS["WGS 84",DATUM["WGS_1984",AUTHORITY["EPSG","6326"]]],UNIT["metre",1,AUTHORITY["EPSG","9001"]]]"#;
    let crs = Crs::from_wkt(wkt).unwrap();
    assert_eq!(crs.epsg(), None);
    assert_eq!(crs.to_string(), "custom");
    assert_eq!(crs.units(), Some(Units::Metres));
}

#[test]
fn feet_local_and_unknown_units() {
    let ft = Crs::from_wkt(r#"PROJCS["x",UNIT["foot",0.3048]]"#).unwrap();
    assert_eq!(ft.units(), Some(Units::Feet));
    let yard = Crs::from_wkt(r#"PROJCS["x",UNIT["yard",0.9144]]"#).unwrap();
    assert_eq!(yard.units(), None, "a unit relief does not know is not taken for metres");
    let local = Crs::from_wkt(r#"LOCAL_CS["site",LOCAL_DATUM["none",0],UNIT["metre",1]]"#).unwrap();
    assert!(local.is_local());
    assert_eq!(local.units(), Some(Units::Metres));
    assert_eq!(Crs::from_epsg(4326).unwrap().units(), None, "a bare code has no WKT to read");
}

#[test]
fn malformed_crs_is_refused() {
    for bad in ["", "UTM 17", "PROJCS[\"x\"", "PROJCS[\"x\"]]", "[\"x\"]", "PROJCS[\"x\",UNIT[\"m\",1x]]"] {
        assert!(matches!(Crs::from_wkt(bad), Err(HeightfieldError::InvalidCrs { .. })), "{bad:?}");
    }
    let deep = format!("{}{}", "A[".repeat(10_000), "]".repeat(10_000));
    assert!(Crs::from_wkt(&deep).is_err(), "deep nesting is refused, not a stack overflow");
    for code in [0, 32767, 1_000_000] {
        assert!(Crs::from_epsg(code).is_err(), "{code}");
    }
    assert!(serde_json::from_str::<Crs>("{}").is_err());
}

#[test]
fn units_names_parse_and_scale_distances() {
    for u in [Units::Metres, Units::Degrees, Units::Feet, Units::UsSurveyFeet] {
        assert_eq!(u.name().parse::<Units>().unwrap(), u);
        assert_eq!(serde_json::to_string(&u).unwrap(), format!("\"{}\"", u.name()));
    }
    assert!("furlongs".parse::<Units>().is_err());
    let grid = GridSpec::new(3, 3, DVec2::ZERO, DVec2::splat(10.0)).unwrap().with_units(Units::UsSurveyFeet).unwrap();
    assert!((grid.cell_size_m(0).x - 3.048_006_096).abs() < 1e-9);
    // A 1 ft rise over 10 ftUS of run, measured in metres of run: 1 / 3.048006.
    let ramp = Heightfield::from_fn(grid, |p| (0.1 * p.x) as f32).unwrap();
    assert!((ramp.gradient(1, 1).unwrap().x - 1.0 / 3.048_006_096).abs() < 1e-6);
}

#[test]
fn derived_fields_and_json_keep_the_crs() {
    let crs = Crs::from_wkt(&fixture("epsg-32617.wkt1")).unwrap();
    let grid = GridSpec::new(4, 3, DVec2::new(500_000.0, 4_000_000.0), DVec2::splat(30.0)).unwrap();
    let hf = Heightfield::from_fn(grid, |p| p.y as f32).unwrap().with_crs(Some(crs.clone()));
    assert_eq!(hf.map(|v| v + 1.0).unwrap().crs(), Some(&crs));
    assert_eq!(hf.zip_with(&hf, |a, b| a - b).unwrap().crs(), Some(&crs));
    assert_eq!(hf.resample(7, 5).unwrap().crs(), Some(&crs));
    assert_eq!(hf.slope_map().crs(), Some(&crs));
    let back: Heightfield = serde_json::from_str(&serde_json::to_string(&hf).unwrap()).unwrap();
    assert_eq!(back.crs(), Some(&crs));
    assert_eq!(back, hf);
    assert_eq!(Heightfield::zeros(grid).crs(), None);
}

#[test]
fn wkt_syntax_variants_parse() {
    // Parentheses instead of brackets, spaces around numbers, numbers written .5 or +1.
    let paren = Crs::from_wkt(r#"PROJCS("x", UNIT("foot", .3048 ), AUTHORITY("EPSG", "2222") )"#).unwrap();
    assert_eq!((paren.units(), paren.epsg()), (Some(Units::Feet), Some(2222)));
    let plus = Crs::from_wkt(r#"PROJCS["x",UNIT["metre",+1]]"#).unwrap();
    assert_eq!(plus.units(), Some(Units::Metres));
    assert_eq!(plus.wkt(), Some(r#"PROJCS["x",UNIT["metre",+1]]"#), "the text is kept as given");
    // Sixty-four levels of nesting are WKT; more are refused.
    let nested = |n: usize| format!("{}{}", "A[".repeat(n), "]".repeat(n));
    assert!(Crs::from_wkt(&nested(65)).is_ok());
    assert!(Crs::from_wkt(&nested(66)).is_err());
    // A character no WKT has.
    assert!(Crs::from_wkt(r#"PROJCS["x",@]"#).is_err());
    let err = Crs::from_wkt("UTM zone 17").unwrap_err().to_string();
    assert!(err.contains("UTM zone 17"), "the error quotes the text: {err}");
}

#[test]
fn units_match_their_length_to_a_part_in_ten_million() {
    let unit = |m: &str| Crs::from_wkt(&format!("PROJCS[\"x\",UNIT[\"u\",{m}]]")).unwrap().units();
    assert_eq!(unit("0.304800609601219"), Some(Units::UsSurveyFeet));
    assert_eq!(unit("0.30480002"), Some(Units::Feet), "within 1e-7 of a foot");
    assert_eq!(unit("0.3048001"), None, "3e-7 from a foot is another unit");
    assert_eq!(unit("1000"), None, "kilometres are not metres");
    assert!(Crs::from_epsg(999_999).is_ok());
}

/// ESRI's `.prj` of a WGS 84 DEM (the shared Jacksboro DEM's), with the datum, ellipsoid, meridian
/// and unit to vary.
fn esri_geographic(datum: &str, ellipsoid: &str, meridian: &str, unit: &str) -> String {
    format!(
        "GEOGCS[\"GCS\",DATUM[\"{datum}\",SPHEROID[\"s\",{ellipsoid}]],PRIMEM[\"Greenwich\",{meridian}],UNIT[\"Degree\",{unit}]]"
    )
}

#[test]
fn common_geographic_crss_without_an_authority_are_identified() {
    let degree = "0.0174532925199433";
    let identify = |wkt: &str| Crs::from_wkt(wkt).unwrap().identified().epsg();
    for (datum, ellipsoid, code) in [
        ("D_WGS_1984", "6378137.0,298.257223563", 4326),
        ("WGS_1984", "6378137,298.257223563", 4326),
        ("World Geodetic System 1984", "6378137,298.257223563", 4326),
        ("D_North_American_1983", "6378137.0,298.257222101", 4269),
        ("North_American_Datum_1983", "6378137.0,298.257222101", 4269),
        ("D_North_American_1927", "6378206.4,294.9786982", 4267),
        ("D_ETRS_1989", "6378137.0,298.257222101", 4258),
    ] {
        assert_eq!(identify(&esri_geographic(datum, ellipsoid, "0.0", degree)), Some(code), "{datum}");
    }
    // WKT 2, the unit in the axes.
    let wkt2 = r#"GEOGCRS["WGS 84",DATUM["World Geodetic System 1984",ELLIPSOID["WGS 84",6378137,298.257223563]],PRIMEM["Greenwich",0],CS[ellipsoidal,2],AXIS["lat",north,ANGLEUNIT["degree",0.0174532925199433]],AXIS["lon",east,ANGLEUNIT["degree",0.0174532925199433]]]"#;
    assert_eq!(identify(wkt2), Some(4326));
    // Nothing is guessed for what is not exactly one of them.
    let wgs = "6378137.0,298.257223563";
    assert_eq!(
        identify(&esri_geographic("D_WGS_1984", "6378137.0,298.257222101", "0.0", degree)),
        None,
        "GRS 80 is not WGS 84's ellipsoid"
    );
    assert_eq!(
        identify(&esri_geographic("D_North_American_1983", wgs, "0.0", degree)),
        None,
        "NAD83 on WGS 84's ellipsoid"
    );
    assert_eq!(identify(&esri_geographic("D_WGS_1972", "6378135.0,298.26", "0.0", degree)), None, "another datum");
    assert_eq!(identify(&esri_geographic("D_WGS_1984", wgs, "2.33722917", degree)), None, "Paris meridian");
    assert_eq!(identify(&esri_geographic("D_WGS_1984", wgs, "0.0", "0.0157079632679489")), None, "grads");
    assert_eq!(identify(r#"GEOGCS["GCS",DATUM["D_WGS_1984",SPHEROID["s",6378137.0,298.257223563]]]"#), None, "no unit");
    let projected = format!(
        "PROJCS[\"WGS_1984_UTM_Zone_17N\",{},PROJECTION[\"Transverse_Mercator\"],UNIT[\"Meter\",1.0]]",
        esri_geographic("D_WGS_1984", wgs, "0.0", degree)
    );
    assert_eq!(identify(&projected), None, "a projected CRS gets no code");
    // 3D (ellipsoidal heights: EPSG:4979) and other authorities are not guessed at.
    let wkt2_3d = wkt2.replace("CS[ellipsoidal,2]", "CS[ellipsoidal,3]");
    assert_eq!(identify(&wkt2_3d), None, "WGS 84 3D");
    let three_axes = esri_geographic("D_WGS_1984", wgs, "0.0", degree).replace(
        "UNIT[\"Degree\",0.0174532925199433]]",
        "UNIT[\"Degree\",0.0174532925199433],AXIS[\"Lat\",NORTH],AXIS[\"Long\",EAST],AXIS[\"h\",UP]]",
    );
    assert_eq!(identify(&three_axes), None, "three axes");
    let crs84 = format!("{},ID[\"OGC\",\"CRS84\"]]", &wkt2[..wkt2.len() - 1]);
    assert_eq!(identify(&crs84), None, "OGC's own identifier is kept as the only one");
    // A code of its own wins.
    let own = r#"GEOGCS["NAD83",DATUM["North_American_Datum_1983",SPHEROID["GRS 1980",6378137,298.257222101]],PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433],AUTHORITY["EPSG","4269"]]"#;
    assert_eq!(identify(own), Some(4269));
    let wrong = own.replace("\"4269\"", "\"4152\"");
    assert_eq!(identify(&wrong), Some(4152), "an explicit authority is kept");
}
