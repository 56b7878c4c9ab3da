//! Apart from the embedding API: what tests, benchmarks and the `render` tool read back
//! ([`Inspect`], from [`Renderer::inspect`](crate::Renderer::inspect)), the talks'
//! statistics, image comparison, debug views ([`debug`]) and the test hooks ([`Hooks`], from
//! [`Renderer::hooks`](crate::Renderer::hooks)).

pub mod debug;

pub use crate::context::{read_buffer, scoped, wait_idle};
pub use crate::image::{diff_image, diff_metrics, heat_color, id_color};
pub use crate::passes::classify::ClassificationVariant;
pub use crate::passes::compute_laydown::LaydownStats;
pub use crate::passes::vertex_ring::VertexRingReadback;
pub use crate::renderer::{ConditionalLight, Hooks, Inspect, LightPathCounts, LightTiles, WARM_UP};
pub use crate::resources::SceneSummary;
pub use crate::resources::ring::{RING_UV_FROM_VERTICES, RING_VERTEX_BYTES, ring_slot};
pub use crate::resources::uniforms::local_light_rows;
pub use crate::resources::uploads::UploadStats;
pub use crate::stats::{ClassificationStats, GpuClassification};
