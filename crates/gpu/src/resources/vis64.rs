//! The compute laydown's 64-bit target: which kind the device can have ([`LaydownTarget`])
//! and the resource itself.

/// The device features the compute laydown needs: 64-bit integers and their atomic
/// min/max on storage buffers (`atomicMax` of the 64-bit target).
pub const COMPUTE_LAYDOWN_FEATURES: wgpu::Features =
    wgpu::Features::SHADER_INT64.union(wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX);

/// The features of [`LaydownTarget::Texture`] besides [`COMPUTE_LAYDOWN_FEATURES`]:
/// `r64uint` storage textures with atomic min and max, and storage textures with atomic
/// access at all (`TEXTURE_ATOMIC`, which wgpu checks when it creates the layout).
pub const LAYDOWN_TEXTURE_FEATURES: wgpu::Features =
    wgpu::Features::TEXTURE_INT64_ATOMIC.union(wgpu::Features::TEXTURE_ATOMIC);

/// Where the compute laydown's 64-bit visibility target lives (the same words either
/// way: depth bits high, vis word low).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LaydownTarget {
    /// A row-major storage buffer with 64-bit `atomicMax` (`SHADER_INT64_ATOMIC_MIN_MAX`;
    /// lavapipe has it), cleared before the raster.
    Buffer,
    /// An `r64uint` storage texture with `textureAtomicMax` (`TEXTURE_INT64_ATOMIC`: the
    /// H200 over Vulkan has it, lavapipe not), in the driver's 2D-tiled layout; reset to 0 by
    /// the unpack that reads it. Chosen only when forced.
    Texture,
}

impl LaydownTarget {
    /// Short name for tables and the command line.
    pub fn name(self) -> &'static str {
        match self {
            LaydownTarget::Buffer => "buffer",
            LaydownTarget::Texture => "texture",
        }
    }

    /// The device features this target needs (with [`COMPUTE_LAYDOWN_FEATURES`]).
    pub fn required_features(self) -> wgpu::Features {
        match self {
            LaydownTarget::Buffer => COMPUTE_LAYDOWN_FEATURES,
            LaydownTarget::Texture => COMPUTE_LAYDOWN_FEATURES | LAYDOWN_TEXTURE_FEATURES,
        }
    }

    /// The target a device with `features` gets unless one is forced: the buffer (on the
    /// H200 the texture rasterises no faster and its unpack costs 0.41 ms at 4K against
    /// the buffer's 0.05), else the texture; `None` without 64-bit atomics.
    pub fn best_for(features: wgpu::Features) -> Option<Self> {
        [LaydownTarget::Buffer, LaydownTarget::Texture]
            .into_iter()
            .find(|t| features.contains(t.required_features()))
    }
}

/// The 64-bit target of one renderer.
pub(crate) enum TargetResource {
    Buffer(wgpu::Buffer),
    Texture(wgpu::TextureView),
}

impl TargetResource {
    /// A `width` x `height` target of `kind`.
    pub(crate) fn new(device: &wgpu::Device, kind: LaydownTarget, width: u32, height: u32) -> Self {
        match kind {
            LaydownTarget::Buffer => {
                TargetResource::Buffer(device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("64-bit visibility target"),
                    size: (u64::from(width) * u64::from(height) * 8).max(8),
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }))
            }
            // Created zeroed; each unpack resets what it read.
            LaydownTarget::Texture => TargetResource::Texture(
                device
                    .create_texture(&wgpu::TextureDescriptor {
                        label: Some("64-bit visibility target"),
                        size: wgpu::Extent3d {
                            width,
                            height,
                            depth_or_array_layers: 1,
                        },
                        mip_level_count: 1,
                        sample_count: 1,
                        dimension: wgpu::TextureDimension::D2,
                        format: wgpu::TextureFormat::R64Uint,
                        usage: wgpu::TextureUsages::STORAGE_BINDING
                            | wgpu::TextureUsages::STORAGE_ATOMIC,
                        view_formats: &[],
                    })
                    .create_view(&Default::default()),
            ),
        }
    }

    pub(crate) fn binding(&self) -> wgpu::BindingResource<'_> {
        match self {
            TargetResource::Buffer(b) => b.as_entire_binding(),
            TargetResource::Texture(v) => wgpu::BindingResource::TextureView(v),
        }
    }

    pub(crate) fn kind(&self) -> LaydownTarget {
        match self {
            TargetResource::Buffer(_) => LaydownTarget::Buffer,
            TargetResource::Texture(_) => LaydownTarget::Texture,
        }
    }
}
