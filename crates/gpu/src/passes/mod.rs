//! The passes of a frame, one module each, and the order they run in.
//!
//! Each module holds its pass's description (`shader::Pass`: bindings by name, entry
//! points, dispatch geometry) next to its WGSL (`src/wgsl/<name>.wgsl`), builds its
//! pipelines from it, makes its bind groups by binding name, and records itself inside its
//! own timing scope, from the frame's [`context::FrameContext`]. No pass imports another:
//! what two passes share lives in `crate::resources` (buffers, rows, the groups' types) or in
//! [`raster`] (the raster passes' shared states and draw loops); the frame module holds one
//! of each pass and records them in the frame's order.
//! New passes (HZD's static-scene query, KZ2's shadows and tiled lights, FC5's water, HFW's
//! vertex ring) go in a module here and a line there.
//!
//! | pass | module | what |
//! | --- | --- | --- |
//! | laydown | [`laydown`] | depth + vis buffer (and the baseline's depth prepass) |
//! | compute laydown | [`compute_laydown`] | triangles rasterised in compute into a 64-bit target (hardware part for large and near-plane ones), then depth + vis texture + vis words |
//! | vis copy | [`vis_copy`] | vis texture -> word buffer |
//! | classification | [`classify`] | `tiling`'s three phases, and the zero fill before them |
//! | vertex ring | [`vertex_ring`] | vertex wave commands from the vertex cull buffer (`tiling`'s pass), then per pass the transform of its visible chunks into the 32-byte vertex ring |
//! | resolve | [`resolve`] | material resolve by wave commands (or full screen) -> G-buffer |
//! | baseline | [`baseline`] | HZD's depth-equal geometry pass -> G-buffer |
//! | pixel pull | [`pixel_pull`] | seed 004's depth-equal pass: position-only vertex stage, vertices pulled in the fragment stage -> G-buffer |
//! | regular geometry | [`regular`] | HFW's mixed frame: regular materials' G-buffer pass after the laydown, clearing validity bits |
//! | light volume tests | [`light_volumes`], [`conditional`] | KZ2's conditional rendering emulated: shadowed volume lights' pixel counts -> indirect draws of their spot maps and shading |
//! | light volumes | [`light_volumes`] | KZ2's stencil light volumes (large lights) -> light accumulation |
//! | light tiles | [`lights`] | depth target -> per-tile depth ranges -> per-tile light lists (`deferred`'s culling pass) |
//! | lighting | [`lighting`] | sun, ambient, local lights from the tile lists, tone mapping -> output |
//! | static query | [`query`] | HZD's static query over pooled tile records (`staticscene`'s pass) |
//! | static placement | [`static_place`] | the query's batches -> instance rows and indirect draws |
//! | HiZ build | [`query`] | the depth target -> HZD's HiZ pyramid (`gpu::hiz_depth`, then `staticscene`'s reduction) |
//! | water | [`water`] | FC5's water after lighting: visibility, the mini G-buffer, displacement, tiles, screen-space tessellation, normals, foam, composite (the table in `crate::water_scene`) |

pub(crate) mod baseline;
pub(crate) mod classify;
pub(crate) mod compute_laydown;
pub(crate) mod conditional;
pub(crate) mod context;
pub(crate) mod depth_reductions;
pub(crate) mod laydown;
pub(crate) mod light_volumes;
pub(crate) mod lighting;
pub(crate) mod lights;
pub(crate) mod pixel_pull;
pub(crate) mod query;
pub(crate) mod raster;
pub(crate) mod regular;
pub(crate) mod resolve;
pub(crate) mod static_place;
pub(crate) mod vertex_ring;
pub(crate) mod vis_copy;
pub(crate) mod water;
