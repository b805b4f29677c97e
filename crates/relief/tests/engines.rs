//! Scenes write heightmaps for game engines (`outputs.engines`): the engine's files at its legal
//! size with the import numbers beside them, and bad sizes refused before any work.

use std::path::Path;

use relief::engine::Engine;
use relief::pipeline::{load_scene, run};
use relief::scene::{EngineOutput, MeshOutput};

#[test]
fn a_scene_writes_engine_heightmaps_beside_its_terrain() {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/scenes");
    let mut scene = load_scene(scenes.join("mountain-ridges.json")).unwrap();
    scene.reconstruction.resolution = [200, 200];
    scene.outputs.engines = vec![
        EngineOutput { engine: Engine::Unity, dir: None, size: None, tile: Some(65), splat: None },
        EngineOutput { engine: Engine::Unreal, dir: Some("ue".into()), size: None, tile: None, splat: None },
    ];
    let out = tempfile::tempdir().unwrap();
    let (terrain, written) = run(&scene, &scenes, out.path(), &mut ()).unwrap();
    // Unity: 3 × 3 tiles of 65 samples keep the 200-sample spacing; Unreal: one 253² PNG.
    let unity: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("unity/heightmap.import.json")).unwrap())
            .unwrap();
    assert_eq!(unity["settings"]["tiles"], serde_json::json!([3, 3]));
    assert_eq!(std::fs::metadata(out.path().join("unity/heightmap_2_0.raw")).unwrap().len(), 65 * 65 * 2);
    let ue = relief::io::read(out.path().join("ue/heightmap.png")).unwrap();
    assert_eq!((ue.nx(), ue.ny()), (253, 253));
    let (lo, hi) = terrain.heightfield.min_max().unwrap();
    let codes = relief::io::quantisation(out.path().join("ue/heightmap.png")).unwrap().unwrap();
    assert_eq!((codes.min, codes.max), (f64::from(lo), f64::from(hi)), "codes 0 … 65535 span the terrain's range");
    assert!(
        written.iter().filter(|p| p.starts_with(out.path().join("unity"))).count() == 10,
        "9 tiles and the sidecar"
    );
    // Every output the scene names up front is among those written.
    for f in scene.output_files() {
        assert!(written.contains(&out.path().join(&f)), "{}", f.display());
    }
}

#[test]
fn engine_sizes_are_checked_before_any_work() {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/scenes");
    let mut scene = load_scene(scenes.join("mountain-ridges.json")).unwrap();
    scene.outputs.engines =
        vec![EngineOutput { engine: Engine::Unity, dir: None, size: Some(1024), tile: None, splat: None }];
    let e = run(&scene, &scenes, tempfile::tempdir().unwrap().path(), &mut ()).unwrap_err();
    assert_eq!(e.scene_path(), Some("outputs.engines[0].size"), "{e}");
    assert!(e.to_string().contains("1025"), "{e}");
    scene.outputs.engines = vec![
        EngineOutput { engine: Engine::Godot, dir: None, size: None, tile: None, splat: None },
        EngineOutput { engine: Engine::Blender, dir: Some("godot".into()), size: None, tile: None, splat: None },
    ];
    let e = run(&scene, &scenes, tempfile::tempdir().unwrap().path(), &mut ()).unwrap_err();
    assert_eq!(e.scene_path(), Some("outputs.engines[1].dir"), "{e}");
    // Scene JSON names the engine with `for`.
    let json = r#"{"for": "unreal", "tile": 127}"#;
    let parsed: EngineOutput = serde_json::from_str(json).unwrap();
    assert_eq!((parsed.engine, parsed.tile, parsed.folder()), (Engine::Unreal, Some(127), "unreal".into()));
}

#[test]
fn a_scene_writes_a_glb_mesh_and_splat_maps() {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/scenes");
    let mut scene = load_scene(scenes.join("mountain-ridges.json")).unwrap();
    scene.reconstruction.resolution = [160, 160];
    // JSON as a user writes it: `"splat": {}` asks for the default layers.
    scene.outputs.engines = vec![serde_json::from_str(r#"{"for": "godot", "splat": {}}"#).unwrap()];
    scene.outputs.mesh = Some(serde_json::from_str(r#"{"max_triangles": 2000}"#).unwrap());
    let out = tempfile::tempdir().unwrap();
    let (terrain, written) = run(&scene, &scenes, out.path(), &mut ()).unwrap();
    let glb = std::fs::read(out.path().join("terrain.glb")).unwrap();
    let doc = gltf::Gltf::from_slice(&glb).unwrap();
    let primitive = doc.meshes().next().unwrap().primitives().next().unwrap();
    let triangles = primitive.indices().unwrap().count() / 3;
    assert!((1990..=2000).contains(&triangles), "{triangles}");
    let (lo, hi) = terrain.heightfield.min_max().unwrap();
    let bounds = primitive.bounding_box();
    // Vertices are samples: within the terrain's range; corners are vertices: its whole extent.
    assert!(bounds.min[1] >= lo && bounds.max[1] <= hi, "{bounds:?} vs {lo} … {hi}");
    let extent = terrain.heightfield.grid().extent();
    let size = (extent.max - extent.min).as_vec2();
    assert_eq!([bounds.max[0] - bounds.min[0], bounds.max[2] - bounds.min[2]], [size.x, size.y]);
    for f in ["godot/heightmap_splat.png", "godot/heightmap_masks.png", "terrain.glb"] {
        assert!(written.contains(&out.path().join(f)), "{f}");
    }
    for f in scene.output_files() {
        assert!(written.contains(&out.path().join(&f)), "{}", f.display());
    }
    // Bad mesh and splat settings are refused with their JSON path, before any work.
    scene.outputs.mesh = Some(MeshOutput { file: "terrain.obj".into(), ..scene.outputs.mesh.clone().unwrap() });
    let e = run(&scene, &scenes, tempfile::tempdir().unwrap().path(), &mut ()).unwrap_err();
    assert_eq!(e.scene_path(), Some("outputs.mesh.file"), "{e}");
    let mesh = MeshOutput { file: "terrain.glb".into(), ..scene.outputs.mesh.clone().unwrap() };
    for (bad, path) in [
        (MeshOutput { max_triangles: Some(1), ..mesh.clone() }, "outputs.mesh.max_triangles"),
        (MeshOutput { max_error_m: Some(f64::NAN), ..mesh.clone() }, "outputs.mesh.max_error_m"),
        (MeshOutput { max_error_m: Some(-1.0), ..mesh }, "outputs.mesh.max_error_m"),
    ] {
        scene.outputs.mesh = Some(bad);
        let e = run(&scene, &scenes, tempfile::tempdir().unwrap().path(), &mut ()).unwrap_err();
        assert_eq!(e.scene_path(), Some(path), "{e}");
    }
    scene.outputs.mesh = None;
    scene.outputs.engines =
        vec![serde_json::from_str(r#"{"for": "unity", "splat": {"rock_slope_deg": [50, 40]}}"#).unwrap()];
    let e = run(&scene, &scenes, tempfile::tempdir().unwrap().path(), &mut ()).unwrap_err();
    assert_eq!(e.scene_path(), Some("outputs.engines[0].splat"), "{e}");
}
