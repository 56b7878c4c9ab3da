//! What the renderer's integration tests share: a renderer on testkit's device.
#![allow(dead_code)]

use gpu::{Renderer, RendererConfig};
use testkit::device::ctx;

/// A renderer of `width` x `height` on the shared test device, subgroups on or off.
pub fn renderer(width: u32, height: u32, subgroups: bool) -> Renderer {
    let c = ctx();
    Renderer::new(
        &c.device,
        &c.queue,
        RendererConfig {
            width,
            height,
            subgroups,
            ..RendererConfig::default()
        },
    )
    .unwrap_or_else(|e| panic!("{e}"))
}
