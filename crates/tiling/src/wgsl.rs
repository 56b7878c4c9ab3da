//! The WGSL twins of the passes.
