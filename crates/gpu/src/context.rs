//! Devices: the headless helper, the optional features the renderer asks for, and the
//! paths those features select.

use crate::error::{Error, Result};
pub use crate::resources::readback::{read_buffer, wait_idle};

/// Optional features the renderer uses when the adapter has them. None is required: each
/// missing one selects a fallback path (see [`ActivePaths`]).
pub const OPTIONAL_FEATURES: wgpu::Features = wgpu::Features::SUBGROUP
    .union(wgpu::Features::PRIMITIVE_INDEX)
    .union(wgpu::Features::SHADER_PER_VERTEX)
    .union(wgpu::Features::SHADER_BARYCENTRICS)
    .union(wgpu::Features::SHADER_EARLY_DEPTH_TEST)
    .union(wgpu::Features::TIMESTAMP_QUERY)
    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS)
    .union(wgpu::Features::SHADER_F16)
    .union(wgpu::Features::SHADER_INT64)
    .union(wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX)
    .union(wgpu::Features::TEXTURE_INT64_ATOMIC)
    .union(wgpu::Features::TEXTURE_ATOMIC)
    .union(wgpu::Features::INDIRECT_FIRST_INSTANCE)
    .union(wgpu::Features::MULTI_DRAW_INDIRECT_COUNT)
    .union(wgpu::Features::FLOAT32_BLENDABLE)
    .union(wgpu::Features::DEPTH32FLOAT_STENCIL8);

/// How the laydown's fragment shader learns which triangle it is shading.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PrimitiveIdPath {
    /// `@builtin(primitive_index)` (`Features::PRIMITIVE_INDEX`; on Vulkan it needs
    /// `geometryShader`). No mesh preprocessing.
    Builtin,
    /// HFW's XOR scheme: three per-vertex payloads whose XOR is the primitive ID, read with
    /// `@interpolate(per_vertex)` (`Features::SHADER_PER_VERTEX`). Order-independent.
    PerVertexXor,
    /// A flat payload on the provoking (first) vertex: works on every adapter; meshes are
    /// preprocessed by `visbuf`'s provoking-vertex encoder.
    ProvokingVertex,
}

impl PrimitiveIdPath {
    /// Every path, best first.
    pub const ALL: [PrimitiveIdPath; 3] = [
        PrimitiveIdPath::Builtin,
        PrimitiveIdPath::PerVertexXor,
        PrimitiveIdPath::ProvokingVertex,
    ];

    /// The device features this path needs.
    pub fn required_features(self) -> wgpu::Features {
        match self {
            PrimitiveIdPath::Builtin => wgpu::Features::PRIMITIVE_INDEX,
            PrimitiveIdPath::PerVertexXor => wgpu::Features::SHADER_PER_VERTEX,
            PrimitiveIdPath::ProvokingVertex => wgpu::Features::empty(),
        }
    }

    /// The name of the feature [`PrimitiveIdPath::required_features`] holds ("none" for
    /// the provoking-vertex path).
    pub fn feature_name(self) -> &'static str {
        match self {
            PrimitiveIdPath::Builtin => "PRIMITIVE_INDEX",
            PrimitiveIdPath::PerVertexXor => "SHADER_PER_VERTEX",
            PrimitiveIdPath::ProvokingVertex => "none",
        }
    }

    /// The best path a device with `features` supports.
    pub fn best_for(features: wgpu::Features) -> PrimitiveIdPath {
        Self::ALL
            .into_iter()
            .find(|p| features.contains(p.required_features()))
            .unwrap_or(PrimitiveIdPath::ProvokingVertex)
    }

    /// A short name for tables and CLI flags.
    pub fn name(self) -> &'static str {
        match self {
            PrimitiveIdPath::Builtin => "builtin",
            PrimitiveIdPath::PerVertexXor => "xor",
            PrimitiveIdPath::ProvokingVertex => "provoking",
        }
    }
}

/// Which implementation of each optional technique a device gets.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ActivePaths {
    /// How the laydown gets primitive IDs.
    pub primitive_id: PrimitiveIdPath,
    /// Subgroup (wave) operations for aggregated appends, with the adapter's subgroup size
    /// range; `None` selects the workgroup-atomic fallback.
    pub subgroup_size: Option<(u32, u32)>,
    /// Timestamp queries around passes (`TIMESTAMP_QUERY`).
    pub timestamps: bool,
    /// Timestamps between passes inside one encoder (`TIMESTAMP_QUERY_INSIDE_ENCODERS`).
    pub timestamps_inside_encoders: bool,
    /// `f16` in shaders (`SHADER_F16`).
    pub f16: bool,
    /// 64-bit storage-buffer atomics (`SHADER_INT64` and `SHADER_INT64_ATOMIC_MIN_MAX`):
    /// the compute laydown can run ([`Laydown::Compute`](crate::Laydown)).
    pub int64_atomics: bool,
    /// Hardware barycentrics in fragment shaders (`SHADER_BARYCENTRICS`): the pixel-pull
    /// path ([`RenderPath::PixelPull`](crate::RenderPath)) reads them; without, it traces
    /// the pixel's camera ray against its triangle.
    pub barycentrics: bool,
}

impl ActivePaths {
    /// The paths a device with `features` (and `info`'s subgroup sizes) gets.
    pub fn for_device(features: wgpu::Features, info: &wgpu::AdapterInfo) -> Self {
        Self {
            primitive_id: PrimitiveIdPath::best_for(features),
            subgroup_size: features
                .contains(wgpu::Features::SUBGROUP)
                .then_some((info.subgroup_min_size, info.subgroup_max_size)),
            timestamps: features.contains(wgpu::Features::TIMESTAMP_QUERY),
            timestamps_inside_encoders: features.contains(
                wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS,
            ),
            f16: features.contains(wgpu::Features::SHADER_F16),
            int64_atomics: features.contains(crate::resources::vis64::COMPUTE_LAYDOWN_FEATURES),
            barycentrics: features.contains(wgpu::Features::SHADER_BARYCENTRICS),
        }
    }
}

/// Options for [`headless`].
#[derive(Clone, Debug)]
pub struct HeadlessOptions {
    /// Features not to request even where the adapter has them: how tests select the
    /// fallback paths on a capable adapter.
    pub disable_features: wgpu::Features,
    /// Turn on the backend's own validation (Vulkan validation layers, where installed) in
    /// addition to wgpu's, which is always on.
    pub backend_validation: bool,
    /// wgpu's validation of indirect arguments (`InstanceFlags::VALIDATION_INDIRECT_CALL`,
    /// on by default even in release builds): a compute pass wgpu injects before each
    /// command buffer's indirect dispatches and draws, turning invalid ones into no-ops.
    /// The renderer's own indirect arguments are valid by construction (dispatches are
    /// written as `[min(n, 65 535), ceil(n / 65 535), 1]` with `n` bounded by a buffer's
    /// length; draws carry index ranges from `prepare` and instance counts bounded by
    /// their reserved ranges; it binds no instance-rate vertex buffer), so turning it off
    /// only saves time (on the H200 the resolve's per-pass dispatches took 0.03-0.15 ms
    /// less; BENCHMARKS.md). Default: off. On D3D12 it stays on whatever this says:
    /// without it `@builtin(num_workgroups)`, which the classification reads, is 0 there.
    pub indirect_validation: bool,
}

impl Default for HeadlessOptions {
    fn default() -> Self {
        Self {
            disable_features: wgpu::Features::empty(),
            backend_validation: false,
            indirect_validation: false,
        }
    }
}

/// A device the renderer made for itself, with what it found out about it.
pub struct GpuContext {
    /// The wgpu instance.
    pub instance: wgpu::Instance,
    /// The adapter chosen.
    pub adapter: wgpu::Adapter,
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// The adapter's name, backend, driver and subgroup sizes.
    pub info: wgpu::AdapterInfo,
    /// The paths the enabled features select.
    pub paths: ActivePaths,
}

impl GpuContext {
    /// One line naming the adapter and backend, for every printed figure.
    pub fn adapter_line(&self) -> String {
        adapter_line(&self.info)
    }
}

/// "NVIDIA H100 80GB HBM3 (Vulkan, driver 580.x)": the adapter line printed beside figures.
pub fn adapter_line(info: &wgpu::AdapterInfo) -> String {
    let driver = if info.driver_info.is_empty() {
        info.driver.clone()
    } else {
        format!("{} {}", info.driver, info.driver_info)
    };
    format!(
        "{} ({:?}, {:?}, {})",
        info.name,
        info.backend,
        info.device_type,
        driver.trim()
    )
}

/// An instance with `flags` (the environment's settings otherwise) and its
/// high-performance adapter, or any adapter (such as lavapipe) if it has none.
fn high_performance_adapter(flags: wgpu::InstanceFlags) -> Result<(wgpu::Instance, wgpu::Adapter)> {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    desc.flags = flags;
    let instance = wgpu::Instance::new(desc);
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        force_fallback_adapter: false,
        compatible_surface: None,
        apply_limit_buckets: false,
    }))
    .or_else(|first| {
        pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::None,
            force_fallback_adapter: true,
            compatible_surface: None,
            apply_limit_buckets: false,
        }))
        .map_err(|_| first)
    })
    .map_err(|e| Error::NoAdapter {
        reason: e.to_string(),
    })?;
    Ok((instance, adapter))
}

/// Creates a device without a window: the high-performance adapter first, any adapter
/// (such as lavapipe) otherwise. Requests every optional feature of
/// [`OPTIONAL_FEATURES`] the adapter has (minus `options.disable_features`) and the
/// adapter's own limits, and reports the paths they select.
pub fn headless(options: &HeadlessOptions) -> Result<GpuContext> {
    let mut flags = wgpu::InstanceDescriptor::new_without_display_handle_from_env().flags;
    if options.backend_validation {
        flags |= wgpu::InstanceFlags::VALIDATION;
    }
    flags.set(
        wgpu::InstanceFlags::VALIDATION_INDIRECT_CALL,
        options.indirect_validation,
    );
    let (mut instance, mut adapter) = high_performance_adapter(flags)?;
    if !options.indirect_validation && adapter.get_info().backend == wgpu::Backend::Dx12 {
        // D3D12 needs the validation for @builtin(num_workgroups).
        flags |= wgpu::InstanceFlags::VALIDATION_INDIRECT_CALL;
        (instance, adapter) = high_performance_adapter(flags)?;
    }

    let features = adapter.features() & OPTIONAL_FEATURES & !options.disable_features;
    let info = adapter.get_info();
    let limits = adapter.limits();
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("gpu-driven headless device"),
        required_features: features,
        required_limits: limits,
        experimental_features: wgpu::ExperimentalFeatures::disabled(),
        memory_hints: wgpu::MemoryHints::Performance,
        trace: wgpu::Trace::Off,
    }))
    .map_err(|e| Error::RequestDevice(e.to_string()))?;
    let paths = ActivePaths::for_device(device.features(), &info);
    Ok(GpuContext {
        instance,
        adapter,
        device,
        queue,
        info,
        paths,
    })
}

/// Runs `f` inside validation and out-of-memory error scopes on `device`, turning what they
/// catch into [`Error`]s instead of wgpu's default panic.
pub fn scoped<T>(device: &wgpu::Device, f: impl FnOnce() -> Result<T>) -> Result<T> {
    let oom = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
    let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let out = f();
    let validation = pollster::block_on(validation.pop());
    let oom = pollster::block_on(oom.pop());
    if let Some(e) = oom {
        return Err(Error::OutOfMemory(e.to_string()));
    }
    if let Some(e) = validation {
        return Err(Error::Validation(e.to_string()));
    }
    out
}
