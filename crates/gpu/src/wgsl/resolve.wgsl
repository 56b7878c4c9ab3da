// gpu: the material resolve of one pixel (seed 000's "shade pixels", seed 004's vertex
// pulling): decode the vis word, pull the triangle's three vertices, transform them,
// analytic barycentrics and derivatives (visbuf), sample with gradients, fill a
// DeferredSurface, store it into the G-buffer (group 2).

#import visbuf::id
#import visbuf::bary
#import visbuf::vertex
#import tiling::common
#import gpu::scene_bindings
#import gpu::ring_slots
#import gpu::material
#import gpu::gbuffer_store

// Group 1: what the resolve reads besides the scene.
@group(1) @binding(0) var<storage, read> indices: array<u32>;
@group(1) @binding(1) var<storage, read> meshes: array<GpuMesh>;
@group(1) @binding(2) var<storage, read> micro_batches: array<GpuMicroBatch>;
@group(1) @binding(3) var vis_texture: texture_2d<u32>;
// HFW's vertex ring (gpu::vertex_ring) and the MicroBatchInfoTable (ring offsets), read
// when the pass uniform names the pass's half (a 32-byte stand-in without a ring).
@group(1) @binding(4) var<storage, read> ring: array<VisbufVertex>;
@group(1) @binding(5) var<storage, read> table: array<TilingMicroBatchInfo>;

// Lanes of the wave-command resolve's workgroup: the wave width the commands were built
// for (8 on lavapipe, 32 on NVIDIA).
override RESOLVE_WAVE_WIDTH: u32 = 32u;

struct ResolvedPixel {
    surface: DeferredSurface,
    ok: bool,
}

// The triangle's three vertices from the ring (slots of the pass's half at `ring_base`),
// resolved like the per-pixel path: barycentrics from the stored HPOS (f16 x, y, f32 w;
// z is the projection's constant near term), normals already in world space, UVs from
// the ring unless flagged, the camera-relative position from the interpolated HPOS, and
// the motion from the interpolated current and previous HPOS.
fn resolve_from_ring(pixel: vec2<u32>, inst: GpuInstance, row: TilingMicroBatchInfo, ring_base: u32, instance: u32, corners: vec3<u32>, base_vertex: u32) -> ResolvedPixel {
    var out: ResolvedPixel;
    out.ok = false;
    let s0 = gpu_ring_slot(ring_base, row.ring_offset, row.vertex_count, instance, corners.x);
    let s1 = gpu_ring_slot(ring_base, row.ring_offset, row.vertex_count, instance, corners.y);
    let s2 = gpu_ring_slot(ring_base, row.ring_offset, row.vertex_count, instance, corners.z);
    let n = arrayLength(&ring);
    if s0 >= n || s1 >= n || s2 >= n {
        return out;
    }
    let r0 = ring[s0];
    let r1 = ring[s1];
    let r2 = ring[s2];
    let near = frame.view_proj[3].z;
    let h0 = visbuf_vertex_hpos(r0.hpos_xy, r0.hpos_w);
    let h1 = visbuf_vertex_hpos(r1.hpos_xy, r1.hpos_w);
    let h2 = visbuf_vertex_hpos(r2.hpos_xy, r2.hpos_w);
    let c0 = vec4<f32>(h0.xy, near, h0.z);
    let c1 = vec4<f32>(h1.xy, near, h1.z);
    let c2 = vec4<f32>(h2.xy, near, h2.z);
    // Clamped: the ring's f16 positions can leave the centre far outside a sub-pixel or
    // edge-on triangle, and the weights extrapolate along its plane (motion 20x its
    // neighbours'). The per-pixel path's exact f32 positions leave it about 1/512 px
    // outside; there the clamp cost the resolve 22-40 us at 4K on the H200, here 0-4.
    let b = visbuf_clamp_barycentrics(visbuf_barycentrics(c0, c1, c2, vec2<f32>(pixel) + 0.5, frame.viewport.xy));
    var t0 = visbuf_unpack_uv(r0.uv);
    var t1 = visbuf_unpack_uv(r1.uv);
    var t2 = visbuf_unpack_uv(r2.uv);
    if ((r0.prev_hpos_w_extra | r1.prev_hpos_w_extra | r2.prev_hpos_w_extra) & (GPU_RING_UV_FROM_VERTICES << 16u)) != 0u {
        let v0 = vertices[base_vertex + corners.x];
        let v1 = vertices[base_vertex + corners.y];
        let v2 = vertices[base_vertex + corners.z];
        t0 = vec2<f32>(v0.u, v0.v);
        t1 = vec2<f32>(v1.u, v1.v);
        t2 = vec2<f32>(v2.u, v2.v);
    }
    let uv = visbuf_interpolate2(b, t0, t1, t2);
    let normal = visbuf_interpolate3(
        b,
        visbuf_unpack_snorm_10_10_10_2(r0.normal).xyz,
        visbuf_unpack_snorm_10_10_10_2(r1.normal).xyz,
        visbuf_unpack_snorm_10_10_10_2(r2.normal).xyz,
    ).value;
    // Tangents as the normals; the handedness is the triangle's (MikkTSpace splits
    // vertices whose handedness differs).
    let tangent = vec4<f32>(visbuf_interpolate3(
        b,
        visbuf_unpack_snorm_10_10_10_2(r0.tangent).xyz,
        visbuf_unpack_snorm_10_10_10_2(r1.tangent).xyz,
        visbuf_unpack_snorm_10_10_10_2(r2.tangent).xyz,
    ).value, visbuf_unpack_snorm_10_10_10_2(r0.tangent).w);
    let now = visbuf_interpolate3(b, h0, h1, h2).value;
    let before = visbuf_interpolate3(
        b,
        visbuf_vertex_prev_hpos(r0.prev_hpos_xy, r0.prev_hpos_w_extra),
        visbuf_vertex_prev_hpos(r1.prev_hpos_xy, r1.prev_hpos_w_extra),
        visbuf_vertex_prev_hpos(r2.prev_hpos_xy, r2.prev_hpos_w_extra),
    ).value;
    let h = frame.inv_view_proj * vec4<f32>(now.xy, near, now.z);
    let p = h.xyz / h.w;
    var motion = vec2<f32>(0.0);
    if now.z > 0.0 && before.z > 0.0 {
        motion = (now.xy / now.z - before.xy / before.z) * frame.viewport.xy * vec2<f32>(0.5, -0.5);
    }
    let scale = visbuf_mip_bias_scale(frame.mip_bias);
    out.surface = material_surface_motion(inst.material, uv.value, uv.ddx * scale, uv.ddy * scale, normal, tangent, p, motion);
    out.ok = true;
    return out;
}

// `ring_base`: the first slot of the pass's half of the vertex ring, or GPU_RING_NONE to
// transform the triangle's vertices here.
fn resolve_pixel(pixel: vec2<u32>, word: u32, ring_base: u32) -> ResolvedPixel {
    var out: ResolvedPixel;
    out.ok = false;
    // With VRS the top two bits are the shading rate (visbuf's VRS layout).
    let id = select(visbuf_micro_batch(word), visbuf_micro_batch_vrs(word), gpu_vrs_layout());
    if visbuf_is_none(word) || id >= arrayLength(&micro_batches) {
        return out;
    }
    let mb = micro_batches[id];
    let field = visbuf_instance_field(word, mb.primitive_bits);
    let primitive = visbuf_primitive(word, mb.primitive_bits);
    let instance_index = mb.first_instance + visbuf_instance_index(id, mb.first_id, field, mb.primitive_bits);
    let mesh = meshes[mb.mesh];
    if primitive >= mesh.primitive_count || instance_index >= arrayLength(&instances) {
        return out;
    }
    let inst = instances[instance_index];
    let first = mesh.first_index + 3u * primitive;
    if ring_base != GPU_RING_NONE && mb.first_id < arrayLength(&table) {
        let corners = vec3<u32>(indices[first], indices[first + 1u], indices[first + 2u]);
        let instance = visbuf_instance_index(id, mb.first_id, field, mb.primitive_bits);
        return resolve_from_ring(pixel, inst, table[mb.first_id], ring_base, instance, corners, mesh.base_vertex);
    }
    let v0 = vertices[mesh.base_vertex + indices[first]];
    let v1 = vertices[mesh.base_vertex + indices[first + 1u]];
    let v2 = vertices[mesh.base_vertex + indices[first + 2u]];
    let r0 = gpu_position(inst, v0.position);
    let r1 = gpu_position(inst, v1.position);
    let r2 = gpu_position(inst, v2.position);
    let c0 = frame.view_proj * vec4<f32>(r0, 1.0);
    let c1 = frame.view_proj * vec4<f32>(r1, 1.0);
    let c2 = frame.view_proj * vec4<f32>(r2, 1.0);
    // Not clamped (resolve_from_ring says why).
    let b = visbuf_barycentrics(c0, c1, c2, vec2<f32>(pixel) + 0.5, frame.viewport.xy);
    let uv = visbuf_interpolate2(b, vec2<f32>(v0.u, v0.v), vec2<f32>(v1.u, v1.v), vec2<f32>(v2.u, v2.v));
    let n = visbuf_interpolate3(b, v0.normal, v1.normal, v2.normal).value;
    let t = visbuf_interpolate3(b, v0.tangent.xyz, v1.tangent.xyz, v2.tangent.xyz).value;
    let tangent = vec4<f32>(gpu_transform_direction(inst, t), v0.tangent.w);
    let scale = visbuf_mip_bias_scale(frame.mip_bias);
    let p = visbuf_interpolate3(b, r0, r1, r2).value;
    // Without wind nothing animates: the previous pose is this one (bit for bit).
    var p_prev = p;
    if frame.wind.w != 0.0 {
        let q0 = gpu_previous_position(inst, v0.position);
        let q1 = gpu_previous_position(inst, v1.position);
        let q2 = gpu_previous_position(inst, v2.position);
        p_prev = visbuf_interpolate3(b, q0, q1, q2).value;
    }
    out.surface = material_surface_moved(inst.material, uv.value, uv.ddx * scale, uv.ddy * scale, gpu_transform_normal(inst, n), tangent, p, p_prev);
    out.ok = true;
    return out;
}

// Full-screen resolve, 8x8 pixels per workgroup: every pixel reads its own vis word. The
// diagnostic counterpart of the wave-command resolve (same per-pixel work, no
// classification); pixels without geometry are left as they are.
@compute @workgroup_size(8, 8)
fn resolve_fullscreen(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(frame.viewport.xy);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let word = textureLoad(vis_texture, vec2<i32>(id.xy), 0).x;
    let r = resolve_pixel(id.xy, word, GPU_RING_NONE);
    if r.ok {
        gbuffer_store(id.xy, r.surface, frame.view_rotation);
    }
}

// The wave-command resolve (seed 000's "shade pixels"): one workgroup of RESOLVE_WAVE_WIDTH
// lanes per wave command, one `dispatch_workgroups_indirect` per pass with that pass's
// PassDispatch. Each lane takes one command of its wave: a pixel of the wave's 128x128
// tile that shows the wave's (pass, batch group), or with VRS a quad command (the sample's
// quad and the mask of the quad's pixels that receive it).
@group(3) @binding(0) var<storage, read> wave_commands: array<TilingWaveCommand>;
@group(3) @binding(1) var<storage, read> pixel_commands: array<u32>;
@group(3) @binding(2) var<storage, read> pass_dispatches: array<TilingPassDispatch>;
// x: the pass this dispatch shades; y: its half of the vertex ring (GPU_RING_NONE: the
// per-pixel transform). A uniform at a dynamic offset per pass.
@group(3) @binding(3) var<uniform> resolve_pass: vec4<u32>;

#if vrs
// The talk's work expansion (BroadcastOutput): whether any lane broadcasts, each lane's
// first entry and receiving-pixel count, the expanded list (lane | dx << 6 | dy << 7, the
// talk's sPixelCommands), each lane's quad origin (sIntermediatePixelX/Y) and its shaded
// result (sIntermediateSpace; the surface, which gbuffer_store packs per target).
var<workgroup> wg_broadcast: atomic<u32>;
var<workgroup> wg_counts: array<u32, RESOLVE_WAVE_WIDTH>;
var<workgroup> wg_total: u32;
var<workgroup> wg_list: array<u32, RESOLVE_LIST_LEN>;
var<workgroup> wg_origin: array<vec2<u32>, RESOLVE_WAVE_WIDTH>;
var<workgroup> wg_surface: array<DeferredSurface, RESOLVE_WAVE_WIDTH>;
var<workgroup> wg_ok: array<u32, RESOLVE_WAVE_WIDTH>;

// Four receiving pixels per lane at most.
override RESOLVE_LIST_LEN: u32 = 4u * RESOLVE_WAVE_WIDTH;
#endif

@compute @workgroup_size(RESOLVE_WAVE_WIDTH)
fn resolve_waves(@builtin(workgroup_id) wg: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let dispatch = pass_dispatches[resolve_pass.x];
    let k = wg.y * TILING_MAX_DISPATCH_X + wg.x;
    if k >= dispatch.count {
        return;
    }
    let wave = wave_commands[dispatch.first + k];
    let live = lane < wave.command_count;
    let tile = tiling_wave_tile_xy(wave.tile) * TILING_TILE_SIZE;
    var pixel = vec2<u32>(0u);
    var mask = 1u;
    if live {
        let c = wave.first_command + lane;
        let command = tiling_command_in_word(pixel_commands[c / 2u], c);
        if gpu_vrs_layout() {
            // The sample: the quad's pixel of the mask's lowest bit (tiling::sample_pixel).
            let quad = vec2<u32>(command & TILING_QUAD_COORD_MASK, (command >> TILING_QUAD_Y_SHIFT) & TILING_QUAD_COORD_MASK);
            mask = (command >> TILING_QUAD_PIXELS_SHIFT) & 0xfu;
            let b = select(0u, firstTrailingBit(mask), mask != 0u);
            pixel = tile + 2u * quad + vec2<u32>(b & 1u, b >> 1u);
        } else {
            pixel = tile + tiling_unpack_pixel_command(command);
        }
    }
    var r: ResolvedPixel;
    r.ok = false;
    if live {
        let word = textureLoad(vis_texture, vec2<i32>(pixel), 0).x;
        r = resolve_pixel(pixel, word, resolve_pass.y);
    }
    if !gpu_vrs_layout() {
        if r.ok {
            gbuffer_store(pixel, r.surface, frame.view_rotation);
        }
        return;
    }
#if vrs
    // Does any lane broadcast? (More than one receiving pixel.)
    if lane == 0u {
        atomicStore(&wg_broadcast, 0u);
    }
    workgroupBarrier();
    let receivers = select(0u, countOneBits(mask), live && r.ok);
    if receivers > 1u {
        atomicOr(&wg_broadcast, 1u);
    }
    wg_counts[lane] = receivers;
    workgroupBarrier();
    if atomicLoad(&wg_broadcast) == 0u {
        // Fast path: every lane writes its own pixel.
        if r.ok {
            gbuffer_store(pixel, r.surface, frame.view_rotation);
        }
        return;
    }
    // Expansion: each lane's run of the list starts at the sum of the counts below it.
    var start = 0u;
    for (var l = 0u; l < lane; l++) {
        start += wg_counts[l];
    }
    if lane == RESOLVE_WAVE_WIDTH - 1u {
        wg_total = start + receivers;
    }
    if receivers > 0u {
        var j = start;
        for (var bit = 0u; bit < 4u; bit++) {
            if (mask & (1u << bit)) != 0u && j < RESOLVE_LIST_LEN {
                wg_list[j] = lane | ((bit & 1u) << 6u) | ((bit >> 1u) << 7u);
                j++;
            }
        }
    }
    wg_origin[lane] = pixel & vec2<u32>(~1u);
    wg_surface[lane] = r.surface;
    wg_ok[lane] = select(0u, 1u, r.ok);
    workgroupBarrier();
    // BroadcastOutput: the lanes walk the expanded list, each entry writing one pixel
    // with its sample's stashed result; every covered pixel is written once.
    let total = min(wg_total, RESOLVE_LIST_LEN);
    let size = vec2<u32>(frame.viewport.xy);
    for (var i = lane; i < total; i += RESOLVE_WAVE_WIDTH) {
        let e = wg_list[i];
        let l = e & 63u;
        let out = wg_origin[l] + vec2<u32>((e >> 6u) & 1u, (e >> 7u) & 1u);
        if wg_ok[l] != 0u && out.x < size.x && out.y < size.y {
            gbuffer_store(out, wg_surface[l], frame.view_rotation);
        }
    }
#else
    // The VRS layout is only used with this feature (RendererConfig::vrs).
    if r.ok {
        gbuffer_store(pixel, r.surface, frame.view_rotation);
    }
#endif
}
