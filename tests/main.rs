//! The workspace's cross-crate tests, one module per topic. Run with
//! `cargo test -p integration`.

mod fuzz_regressions;
mod gpu_common;
mod gpu_morton;
mod gpu_tiling;
mod gpu_visbuf;
