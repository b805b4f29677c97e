//! glTF meshes loaded back with the `gltf` crate, as a viewer would: bounds in metres, the
//! triangle count, up-facing normals and winding, UVs over the unit square, the error bound.

use glam::{DVec2, DVec3};
use relief_engine_export::{EngineError, MAX_MESH_TRIANGLES, MeshOptions, TerrainMesh};
use relief_heightfield::{GridSpec, Heightfield};
use relief_tin::Tin;

fn jacksboro() -> Heightfield {
    relief_heightfield_io::read(concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/dem/jacksboro.asc")).unwrap()
}

/// What a glTF reader gets back.
struct Loaded {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    uvs: Vec<[f32; 2]>,
    colours: Option<Vec<[u8; 4]>>,
    indices: Vec<u32>,
    min: Vec<f64>,
    max: Vec<f64>,
}

fn load(glb: &[u8]) -> Loaded {
    let doc = gltf::Gltf::from_slice(glb).expect("a valid glTF 2.0 binary");
    assert_eq!(doc.meshes().count(), 1);
    let blob = doc.blob.clone().expect("the binary chunk");
    let primitive = doc.meshes().next().unwrap().primitives().next().unwrap();
    assert_eq!(primitive.mode(), gltf::mesh::Mode::Triangles);
    // What an importer shows: the default scene's node holds the mesh, named; the material is
    // matte (a terrain does not shine).
    let scene = doc.default_scene().expect("a default scene");
    let node = scene.nodes().next().expect("a node in the scene");
    assert_eq!(node.mesh().map(|m| m.index()), Some(0));
    assert_eq!((node.name(), doc.meshes().next().unwrap().name()), (Some("terrain"), Some("terrain")));
    let material = primitive.material();
    let pbr = material.pbr_metallic_roughness();
    assert_eq!((material.name(), pbr.metallic_factor(), pbr.roughness_factor()), (Some("terrain"), 0.0, 1.0));
    let bounds = primitive.bounding_box();
    let reader = primitive.reader(|_| Some(&blob));
    Loaded {
        positions: reader.read_positions().unwrap().collect(),
        normals: reader.read_normals().unwrap().collect(),
        uvs: reader.read_tex_coords(0).unwrap().into_f32().collect(),
        colours: reader.read_colors(0).map(|c| c.into_rgba_u8().collect()),
        indices: reader.read_indices().unwrap().into_u32().collect(),
        min: bounds.min.iter().map(|&v| f64::from(v)).collect(),
        max: bounds.max.iter().map(|&v| f64::from(v)).collect(),
    }
}

#[test]
fn a_real_dem_loads_back_with_its_bounds_triangles_and_error() {
    let dem = jacksboro();
    let (lo, hi) = dem.min_max().unwrap();
    let options = MeshOptions { max_error_m: Some(8.0), ..MeshOptions::default() };
    let mesh = TerrainMesh::from_heightfield(&dem, &options).unwrap();
    assert!(mesh.max_error_m <= 8.0 && mesh.max_error_m > 7.0, "{}", mesh.max_error_m);
    let glb = mesh.to_glb(true).unwrap();
    let got = load(&glb);
    assert_eq!(got.indices.len(), 3 * mesh.triangles.len(), "the triangle count survives");
    assert_eq!(got.positions.len(), mesh.positions.len());
    assert!(got.indices.iter().all(|&v| (v as usize) < got.positions.len()));
    // glTF is y-up: x east over the DEM's width, y the elevations, z south over its height.
    let grid = dem.grid();
    // Jacksboro is in degrees: metres at its middle row.
    let scale = grid.metres_per_unit(grid.ny() / 2);
    let size = grid.cell_size() * scale * DVec2::new((grid.nx() - 1) as f64, (grid.ny() - 1) as f64);
    let expect_min = [0.0, f64::from(lo), -size.y];
    let expect_max = [size.x, f64::from(hi), 0.0];
    for a in 0..3 {
        assert!((got.min[a] - expect_min[a]).abs() < 1e-2, "min {:?} vs {expect_min:?}", got.min);
        assert!((got.max[a] - expect_max[a]).abs() < 1e-2, "max {:?} vs {expect_max:?}", got.max);
    }
    // The accessor bounds are the positions' own (validators check this).
    let actual_max = got.positions.iter().fold([f32::MIN; 3], |m, p| [0, 1, 2].map(|a| m[a].max(p[a])));
    assert_eq!(actual_max.map(f64::from).to_vec(), got.max);
    // Under a third of the grid's triangles (8 m is 1 % of the relief of a rough 90 m DEM), every
    // one facing up, every normal up.
    assert!(mesh.triangles.len() < 2 * (grid.nx() - 1) * (grid.ny() - 1) / 3, "{}", mesh.triangles.len());
    for t in got.indices.chunks(3) {
        let [a, b, c] = [0, 1, 2].map(|k| DVec3::from(got.positions[t[k] as usize].map(f64::from)));
        assert!((b - a).cross(c - a).y > 0.0, "a triangle faces down (wrong winding)");
    }
    assert!(got.normals.iter().all(|n| n[1] > 0.0 && (DVec3::from(n.map(f64::from)).length() - 1.0).abs() < 1e-5));
    assert!(got.uvs.iter().all(|uv| (0.0..=1.0).contains(&uv[0]) && (0.0..=1.0).contains(&uv[1])));
    // Colours follow the hypsometric ramp: the highest vertex is the ramp's white.
    let colours = got.colours.expect("COLOR_0");
    let top = (0..got.positions.len()).max_by(|&a, &b| got.positions[a][1].total_cmp(&got.positions[b][1])).unwrap();
    assert_eq!(colours[top], [250, 250, 250, 255]);
    assert!(load(&mesh.to_glb(false).unwrap()).colours.is_none());
}

#[test]
fn the_error_bound_is_kept_and_the_triangle_budget_caps_the_mesh() {
    let dem = jacksboro();
    let exact = |max_error_m| {
        let options = MeshOptions { max_error_m: Some(max_error_m), max_triangles: usize::MAX >> 40, colours: false };
        TerrainMesh::from_heightfield(&dem, &options).unwrap()
    };
    let (coarse, fine) = (exact(8.0), exact(1.0));
    assert!(coarse.triangles.len() < fine.triangles.len());
    // Every sample within the bound: sample the mesh back onto the grid through a TIN.
    let points: Vec<DVec2> = fine.positions.iter().map(|p| p.truncate()).collect();
    let tin = Tin::from_parts(points, fine.triangles.clone()).unwrap();
    let heights: Vec<f64> = fine.positions.iter().map(|p| p.z).collect();
    let cell = dem.grid().cell_size() * dem.grid().metres_per_unit(dem.ny() / 2);
    let local = GridSpec::new(dem.nx(), dem.ny(), DVec2::ZERO, cell).unwrap();
    let back = tin.rasterize(&heights, &local).unwrap();
    let worst = dem.samples().iter().zip(back.samples()).map(|(a, b)| (a - b).abs()).fold(0.0, f32::max);
    assert!(worst <= 1.0 + 1e-3, "{worst} m");
    let capped = TerrainMesh::from_heightfield(
        &dem,
        &MeshOptions { max_error_m: Some(0.0), max_triangles: 1000, colours: false },
    )
    .unwrap();
    assert!((990..=1000).contains(&capped.triangles.len()), "{}", capped.triangles.len());
    assert!(capped.max_error_m > 1.0);
    let load_back = load(&capped.to_glb(false).unwrap());
    assert_eq!(load_back.indices.len(), 3 * capped.triangles.len());
}

#[test]
fn a_tin_becomes_a_mesh_as_it_is() {
    let points = vec![DVec2::new(10.0, 10.0), DVec2::new(110.0, 10.0), DVec2::new(60.0, 90.0), DVec2::new(60.0, 40.0)];
    let tin = Tin::new(points).unwrap();
    let mesh = TerrainMesh::from_tin(&tin, &[0.0, 5.0, 10.0, 40.0]).unwrap();
    assert_eq!(mesh.origin, DVec2::new(10.0, 10.0));
    assert_eq!(mesh.triangles.len(), 3);
    let got = load(&mesh.to_glb(true).unwrap());
    assert_eq!(got.max, vec![100.0, 40.0, 0.0]);
    assert_eq!(got.min, vec![0.0, 0.0, -80.0]);
    // UVs span the bounds wherever the positions sit (the fields are public).
    let moved = TerrainMesh {
        positions: mesh.positions.iter().map(|p| *p + glam::DVec3::new(500.0, -70.0, 0.0)).collect(),
        ..mesh.clone()
    };
    let uvs = load(&moved.to_glb(false).unwrap()).uvs;
    assert!(uvs.iter().all(|uv| (0.0..=1.0).contains(&uv[0]) && (0.0..=1.0).contains(&uv[1])), "{uvs:?}");
    assert!(uvs.contains(&[0.0, 1.0]) && uvs.contains(&[1.0, 1.0]), "the south corners: {uvs:?}");
    assert!(matches!(TerrainMesh::from_tin(&tin, &[0.0; 3]), Err(EngineError::Tin(_))));
    assert!(matches!(TerrainMesh::from_tin(&tin, &[0.0, 1.0, f64::NAN, 2.0]), Err(EngineError::Tin(_))));
}

#[test]
fn bad_inputs_are_refused() {
    let empty = Heightfield::from_fn(GridSpec::new(4, 4, DVec2::ZERO, DVec2::ONE).unwrap(), |_| f32::NAN).unwrap();
    assert!(matches!(TerrainMesh::from_heightfield(&empty, &MeshOptions::default()), Err(EngineError::NoData)));
    let line = Heightfield::from_fn(GridSpec::new(1, 9, DVec2::ZERO, DVec2::ONE).unwrap(), |_| 1.0).unwrap();
    assert!(matches!(TerrainMesh::from_heightfield(&line, &MeshOptions::default()), Err(EngineError::Tin(_))));
    let refused = |options: MeshOptions| match TerrainMesh::from_heightfield(&jacksboro(), &options) {
        Err(EngineError::InvalidMesh { field, .. }) => field,
        other => panic!("{options:?} gave {other:?}"),
    };
    let default = MeshOptions::default();
    assert_eq!(refused(MeshOptions { max_triangles: MAX_MESH_TRIANGLES + 1, ..default }), "max_triangles");
    assert_eq!(refused(MeshOptions { max_triangles: 1, ..default }), "max_triangles");
    assert_eq!(refused(MeshOptions { max_error_m: Some(f64::NAN), ..default }), "max_error_m");
    assert_eq!(refused(MeshOptions { max_error_m: Some(-0.5), ..default }), "max_error_m");
    assert_eq!(refused(MeshOptions { max_error_m: Some(f64::INFINITY), ..default }), "max_error_m");
    let edges = [MeshOptions { max_triangles: 2, max_error_m: Some(0.0), ..default }];
    assert!(edges.iter().all(|o| o.validate().is_ok()));
    let message = MeshOptions { max_triangles: 1, ..default }.validate().unwrap_err().to_string();
    assert!(message.contains("max_triangles") && message.contains("from 2 to 16777216"), "{message}");
}
