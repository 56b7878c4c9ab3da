#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzzing::visbuf_encode_xor(data));
