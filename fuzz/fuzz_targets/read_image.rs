//! Any bytes given to the image reader (JPEG, BMP, WebP through the `image` crate) decode to a
//! heightfield or a typed error: no panic, and nothing beyond the reader's cell limit (kept small
//! so that libFuzzer's RSS limit would catch an allocation past it).
#![no_main]

use libfuzzer_sys::fuzz_target;
use relief::harness::{MAX_CELLS, read};
use relief::io::Format;

fuzz_target!(|data: &[u8]| {
    if let Ok(hf) = read(data, Format::Image) {
        assert!(hf.samples().len() as u64 <= MAX_CELLS);
    }
});
