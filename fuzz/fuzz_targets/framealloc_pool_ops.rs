#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzzing::framealloc_pool_ops(data));
