//! Empty library: this package exists to hold the workspace's cross-crate test binary
//! (`main.rs`), since a virtual workspace has no root package for `tests/`.
