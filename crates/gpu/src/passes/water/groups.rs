use crate::resources::lights::LightBuffers;
/// The water's bind groups.
pub(crate) struct WaterGroups {
    pub hiz: Vec<(wgpu::BindGroup, staticscene::pass::HizGrid)>,
    pub visibility: wgpu::BindGroup,
    pub position: wgpu::BindGroup,
    pub displacement: wgpu::BindGroup,
    pub tiles: wgpu::BindGroup,
    pub tessellation: wgpu::BindGroup,
    pub tile_depth: wgpu::BindGroup,
    pub cull: wgpu::BindGroup,
    pub normals: wgpu::BindGroup,
    pub foam: wgpu::BindGroup,
    pub composite: wgpu::BindGroup,
    /// Lighting's group 2: the HDR target.
    pub hdr: wgpu::BindGroup,
}

/// What the groups are made over: the renderer's frame uniforms, depth, output and light
/// buffers.
pub(crate) struct Shared<'a> {
    pub frame: &'a wgpu::Buffer,
    pub depth: &'a wgpu::TextureView,
    pub output: &'a wgpu::TextureView,
    pub local: &'a wgpu::Buffer,
    pub lights: &'a LightBuffers,
    /// The lighting's water layouts (group `water`: the HDR target).
    pub hdr_layout: &'a shader::pipeline::Layouts,
}
