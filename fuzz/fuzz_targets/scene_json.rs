//! Any bytes given to the scene parser are a scene or a typed error naming a JSON path; a scene
//! that parses serializes back to JSON that parses to the same scene.
#![no_main]

use libfuzzer_sys::fuzz_target;
use relief::harness::scene_json;

fuzz_target!(|data: &[u8]| {
    if let Ok(scene) = scene_json(data) {
        let again = serde_json::to_vec(&scene).expect("a parsed scene serializes");
        assert_eq!(scene_json(&again).expect("its JSON parses"), scene);
    }
});
