//! Any small label image becomes a growth graph with a node on every level, or a typed error
//! (see `relief::harness::label_image` for how bytes become an image). The image decoders have
//! their own targets.
#![no_main]

use libfuzzer_sys::fuzz_target;
use relief::harness::label_image;

fuzz_target!(|data: &[u8]| {
    if let Ok(graph) = label_image(data) {
        assert!(graph.inside_count() > 0);
        for level in 1..=graph.max_level() {
            assert!(graph.levels().contains(&level), "level {level} has no node");
        }
    }
});
