#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzzing::deferred_gbuffer_decode(data));
