//! The workspace's one way to put WGSL together and to describe a pass.
//!
//! **Composition.** Every WGSL file of the workspace is a [`Module`] named `crate::file`
//! (`visbuf::id` is `crates/visbuf/src/wgsl/id.wgsl`) and names what it imports in its
//! own text with `#import` lines; `#if feature` / `#else` / `#endif` lines select code by
//! feature (the subgroup or workgroup appends, for instance). [`compose`] resolves the
//! imports across the crates' module lists and emits each module once, imports first.
//! Nothing is renamed or substituted: names carry their crate's prefix
//! (`visbuf_pack_id`), and numeric variants (a wave width) are WGSL `override`s set when
//! the pipeline is created. Why not `naga_oil` or `wesl`: see ARCHITECTURE.md.
//!
//! **Descriptions.** A [`Pass`] is declared once, next to its WGSL, by the crate that owns
//! the algorithm: its root module and features, its bind groups and bindings by name and
//! kind, its entry points in order with workgroup sizes and dispatch geometry, and the
//! buffers it expects zeroed. A render pass's pipelines are [`Raster`] consts beside it
//! (entry points, colour targets with blend and write mask, depth and stencil, culling,
//! samples). With the `wgpu` feature, [`pipeline`] builds layouts, compute and render
//! pipelines, bind groups (by binding name) and dispatches from them;
//! `shadercheck::check_pass` and `shadercheck::check_raster` prove a description matches
//! its composed module with naga.
//!
//! ```
//! use shader::{Binding, Dispatch, Entry, Group, Kind, Module, Pass, Stage};
//!
//! // A library module and a pass module that imports it, as two crates would ship them.
//! const SQUARE: Module = Module::new(
//!     "demo::square",
//!     "fn demo_square(x: u32) -> u32 { return x * x; }\n",
//! );
//! const MAIN: Module = Module::new(
//!     "demo::main",
//!     "#import demo::square
//! @group(0) @binding(0) var<storage, read> input: array<u32>;
//! @group(0) @binding(1) var<storage, read_write> output: array<u32>;
//! @compute @workgroup_size(64)
//! fn square_all(@builtin(global_invocation_id) id: vec3<u32>) {
//!     if id.x < arrayLength(&input) {
//! #if cube
//!         output[id.x] = demo_square(input[id.x]) * input[id.x];
//! #else
//!         output[id.x] = demo_square(input[id.x]);
//! #endif
//!     }
//! }
//! ",
//! );
//!
//! /// Items to square (the pass's dispatch parameter).
//! struct Items(u32);
//!
//! const SQUARE_ALL: Pass<Items> = Pass {
//!     name: "square all",
//!     module: "demo::main",
//!     library: &[&[SQUARE, MAIN]],
//!     features: &["cube"],
//!     groups: &[Group {
//!         name: "data",
//!         bindings: &[
//!             Binding::new("input", Kind::read(4)),
//!             Binding::new("output", Kind::read_write(4)),
//!         ],
//!     }],
//!     entries: &[Entry {
//!         name: "square_all",
//!         stage: Stage::compute(64, 1, 1),
//!         dispatch: Dispatch::Items(|n| n.0),
//!     }],
//!     zeroed: &[],
//! };
//!
//! let wgsl = SQUARE_ALL.source(&[])?;
//! assert!(wgsl.find("fn demo_square").unwrap() < wgsl.find("fn square_all").unwrap());
//! assert!(!wgsl.contains("* input[id.x]"));
//! let entry = SQUARE_ALL.entry("square_all")?;
//! assert_eq!(entry.workgroups(&Items(1000), &[]), Some([16, 1, 1]));
//! assert_eq!(SQUARE_ALL.binding("output")?.1, 1);
//! # Ok::<(), shader::Error>(())
//! ```

#![no_std]

extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

mod compose;
mod pass;
#[cfg(feature = "wgpu")]
pub mod pipeline;
mod raster;

pub use compose::{Error, Module, compose, compose_source};
pub use pass::{
    Binding, Dim, Dispatch, Entry, Format, Group, Kind, MAX_WORKGROUPS_X, Pass, Sample, Size,
    Stage, StageCounts, join,
};
pub use raster::{
    Attribute, Bias, Blend, BlendComponent, BlendFactor, BlendOp, Compare, Depth, DepthFormat,
    Face, FrontFace, Primitive, Raster, Stencil, StencilFace, StencilOp, Target, Topology,
    VertexBuffer, VertexFormat, integer_target,
};
