//! Engine exports at the sizes users take into engines: a 1025² terrain (`relief_fixtures::fbm_dem`,
//! massifs and crests over 1 km²) and the real Jacksboro DEM. Rows: the glTF mesh end to end
//! (greedy-insertion decimation to an error bound, normals, colours, GLB encoding), the splat
//! masks (slope, elevation, convexity, D8 flow on the filled terrain) and a heightmap's
//! resampling and tiling.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use relief_engine_export::{Engine, ExportOptions, MeshOptions, SplatOptions, TerrainMesh, masks, prepare};
use relief_heightfield::Heightfield;

fn jacksboro() -> Heightfield {
    relief_heightfield_io::read(concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/dem/jacksboro.asc"))
        .expect("the Jacksboro fixture")
}

/// The mesh within `fraction` of the height range, as a `.glb`.
fn glb(dem: &Heightfield, fraction: f64) -> Vec<u8> {
    let (lo, hi) = dem.min_max().expect("valid samples");
    let options = MeshOptions { max_error_m: Some(fraction * f64::from(hi - lo)), ..MeshOptions::default() };
    TerrainMesh::from_heightfield(dem, &options).and_then(|m| m.to_glb(true)).expect("a mesh")
}

fn engine(c: &mut Criterion) {
    let fbm = relief_fixtures::fbm_dem(1025, 7).expect("the fBm fixture");
    let jacksboro = jacksboro();
    let mut g = c.benchmark_group("engine_export");
    g.sample_size(10);
    g.bench_function("glb/fbm_1025_error_0.1pct", |b| b.iter(|| black_box(glb(&fbm, 1e-3))));
    g.bench_function("glb/fbm_1025_error_1pct", |b| b.iter(|| black_box(glb(&fbm, 1e-2))));
    g.bench_function("glb/jacksboro_error_1pct", |b| b.iter(|| black_box(glb(&jacksboro, 1e-2))));
    g.bench_function("splat/fbm_1025", |b| {
        b.iter(|| black_box(masks(&fbm, &SplatOptions::default()).expect("masks").splat()));
    });
    let tiles = ExportOptions { tile: Some(257), ..ExportOptions::default() };
    g.bench_function("prepare/unity_fbm_1025_tiles_257", |b| {
        b.iter(|| black_box(prepare(&fbm, Engine::Unity, &tiles).expect("tiles")));
    });
    g.finish();
}

criterion_group!(benches, engine);
criterion_main!(benches);
