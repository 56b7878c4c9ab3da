#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzzing::water_world_decode(data));
