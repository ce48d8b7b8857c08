#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| breakshot_fuzz::record(data));
