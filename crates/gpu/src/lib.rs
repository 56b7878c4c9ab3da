//! The complete wgpu renderer of the workspace: visibility-buffer laydown, GPU
//! classification into loose-tile wave commands, compute material resolve into a G-buffer,
//! deferred lighting, and HZD's depth-equal baseline that it replaces. Every format and
//! algorithm comes from the small crates; this crate owns devices, buffers, pipelines and
//! passes.
//!
//! ```no_run
//! use gpu::{context, demo};
//!
//! let ctx = context::headless(&context::HeadlessOptions::default())?;
//! let scene = demo::build(&demo::DemoOptions::default());
//! println!("{} on {}", scene.instance_count(), ctx.adapter_line());
//! # Ok::<(), gpu::Error>(())
//! ```

pub mod binding;
pub mod classify;
pub mod context;
pub mod debug;
pub mod demo;
pub mod error;
pub mod frame;
pub mod gbuffer;
pub mod geometry;
pub mod image;
pub mod kernel;
pub mod laydown;
pub mod plan;
pub mod readback;
pub mod renderer;
pub mod report;
pub mod scene;
pub mod shaders;
pub mod targets;
pub mod timing;
pub mod upload;

pub use error::{Error, Result, SceneError};
