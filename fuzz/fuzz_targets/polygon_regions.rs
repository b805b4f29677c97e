//! Any set of up to four polygons becomes a region tree and a growth graph with a node in every
//! region, or a typed error (see `relief::harness::polygon_regions` for the byte layout).
#![no_main]

use libfuzzer_sys::fuzz_target;
use relief::harness::polygon_regions;

fuzz_target!(|data: &[u8]| {
    if let Ok(graph) = polygon_regions(data) {
        assert!(graph.inside_count() > 0);
    }
});
