//! Expressions of `seam transfer --expr`: parse, then evaluate at a few points.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(e) = seam_case::Expression::parse(text) else { return };
    for p in [[0.0, 0.0, 0.0], [0.5, -1.0, 2.0], [1e30, -1e-30, 3.0]] {
        let _ = e.at(p);
    }
});
