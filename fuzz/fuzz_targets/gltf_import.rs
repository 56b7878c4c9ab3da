#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzzing::gltf_import(data));
