#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzzing::deferred_normal_codecs(data));
