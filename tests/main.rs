//! The workspace's cross-crate tests, one module per topic. Run with
//! `cargo test -p integration`. (Device tests live beside the crate whose GPU twins they
//! test, in its `tests/device.rs`; see `testkit`.)

mod fuzz_regressions;
mod gltf_render;
