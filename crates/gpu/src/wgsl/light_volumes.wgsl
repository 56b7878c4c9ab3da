// gpu: KZ2's stencil light volumes, for lights too large for the tiles (or, by choice,
// every light). The frame's depth is copied into a depth-stencil target first
// (fs_copy_depth); then per light, a convex mesh enclosing its bounding sphere:
//   camera outside: back faces with depth test "behind the scene" (reversed Z: Less) set
//   stencil to 1; front faces with "in front of or at the scene" (GreaterEqual) and
//   stencil == 1 shade, and reset stencil to 0 on depth pass and depth fail alike;
//   camera inside (or the mesh near the near plane): back faces behind the scene shade,
//   no stencil.
// Shading is gpu::light_shading's, added into `light_accumulation` (blend One + One), which
// the compute lighting adds to each pixel. The shading is zero outside the light, so the
// mesh only has to cover it. KZ2's light-shader permutations: feature `spot_shadows` for
// lights with a spot shadow map, feature `no_specular` (gpu::light_shading) for lights
// without a specular term.

#import gpu::frame
#import gpu::gbuffer_load
#import deferred::lights
#import gpu::light_shading

// Rust: passes::light_volumes::GpuLightVolume (32 bytes).
struct GpuLightVolume {
    // view-space centre and the scale of the unit mesh (metres)
    sphere: vec4<f32>,
    // the light's index in `lights`
    light: u32,
    pad: array<u32, 3>,
}

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var depth_texture: texture_depth_2d;
@group(0) @binding(2) var<uniform> local: GpuLocalLights;
@group(0) @binding(3) var<storage, read> lights: array<DeferredLight>;
@group(0) @binding(4) var<storage, read> volumes: array<GpuLightVolume>;
// The shadowed spots' maps and rows (spot_shadows.rs).
@group(0) @binding(5) var spot_shadow_map: texture_depth_2d_array;
@group(0) @binding(6) var<storage, read> spot_shadows: array<GpuSpotShadow>;
// Group 1: the G-buffer (gpu::gbuffer_load).

// One triangle covering the viewport.
@vertex
fn vs_full_screen(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

// The frame's depth into the depth-stencil target.
@fragment
fn fs_copy_depth(@builtin(position) frag: vec4<f32>) -> @builtin(frag_depth) f32 {
    return textureLoad(depth_texture, vec2<i32>(frag.xy), 0);
}

struct VolumeVertex {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) light: u32,
}

// `unit`: a vertex of the unit mesh (it encloses the unit sphere); the instance is the
// volume's index.
@vertex
fn vs_volume(@location(0) unit: vec3<f32>, @builtin(instance_index) instance: u32) -> VolumeVertex {
    let v = volumes[min(instance, arrayLength(&volumes) - 1u)];
    let view = v.sphere.xyz + unit * v.sphere.w;
    // View to camera-relative: the rotation's transpose.
    let rel = (transpose(local.view_rotation) * vec4<f32>(view, 0.0)).xyz;
    return VolumeVertex(frame.view_proj * vec4<f32>(rel, 1.0), v.light);
}

// The stencil-marking draw writes no colour.
@fragment
fn fs_mark() {
}

// The light's contribution at this pixel (zero for the sky or a corrupt light index).
@fragment
fn fs_shade(in: VolumeVertex) -> @location(0) vec4<f32> {
    let pixel = vec2<u32>(in.clip.xy);
    let d = textureLoad(depth_texture, vec2<i32>(pixel), 0);
    let count = arrayLength(&lights);
    if (!(d > 0.0) || in.light >= count) {
        return vec4<f32>(0.0);
    }
    let s = gbuffer_surface(pixel, frame.view_rotation);
    let p = light_shading_position(frame.inv_view_proj, frame.viewport.zw, pixel, d);
    let at = light_shading_point(local.view_rotation, p, s);
    let l = lights[in.light];
    var c = light_shading_local(l, at, s);
#if spot_shadows
    // KZ2's permutation for a light with a shadow map: through the map, as lighting does.
    let slot = light_shading_shadow_slot(l);
    if (slot > 0u && slot <= arrayLength(&spot_shadows) && any(c > vec3<f32>(0.0))) {
        c *= light_shading_spot_visibility(spot_shadow_map, spot_shadows[slot - 1u], slot - 1u, l, at);
    }
#endif
    return vec4<f32>(c, 0.0);
}
