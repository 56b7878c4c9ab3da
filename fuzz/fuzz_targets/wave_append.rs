#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzzing::wave_append(data));
