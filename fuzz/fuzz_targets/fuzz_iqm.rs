#![no_main]

use libfuzzer_sys::fuzz_target;
use meshflow::io::{Format, Limits, read_bytes};

fuzz_target!(|data: &[u8]| {
    if let Ok(mesh) = read_bytes(data, Format::Iqm, &Limits::default()) {
        assert!(mesh.validate().is_ok(), "reader returned an invalid mesh");
    }
});
