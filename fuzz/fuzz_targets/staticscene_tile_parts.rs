#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzzing::staticscene_tile_parts(data));
