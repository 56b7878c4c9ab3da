// gpu: seed 004's geometry pipeline, the third path beside deferred texturing and HZD's
// depth-equal baseline. After the depth prepass (alpha-tested, gpu::laydown) every batch is
// drawn again with depth test Equal, but the vertex stage writes only the position (plus
// the instance and, on the payload paths, the primitive-ID payload): the fragment stage
// pulls its triangle's three vertices from storage by the primitive ID and interpolates
// them itself with barycentrics. Nothing but positions crosses from vertex to pixel.
//
// Primitive ID, the laydown's paths (gpu::PrimitiveIdPath):
//   primitive_builtin   @builtin(primitive_index)                        (PRIMITIVE_INDEX)
//   primitive_xor       XOR of three @interpolate(per_vertex) payloads   (SHADER_PER_VERTEX)
//   neither             the provoking (first) vertex's flat payload      (every adapter)
// Barycentrics:
//   barycentrics        @builtin(barycentric), perspective-correct       (SHADER_BARYCENTRICS;
//                       naga 30 needs no `enable` for it, only the capability)
//   otherwise           the seed's fallback: the pixel's camera ray against the triangle
//                       (visbuf::ray, watertight)
//
// Every vertex is positioned by the shared transform (gpu::geometry's laydown_vertex), so
// this path's positions are the prepass's to the bit and follow whatever that transform
// does. The ray runs in clip space's (x, y, w): a linear image of camera-relative space
// with the eye at its origin (view_proj holds no translation of x, y or w), and a linear
// map keeps both the rays through the eye and the barycentrics of their hits, so the
// laydown's clip positions are all the ray needs; the pixel's ray there is (ndc, 1).

#if primitive_builtin
enable primitive_index;
#else
#if primitive_xor
enable wgpu_per_vertex;
#endif
#endif

#import visbuf::ray
#import visbuf::bary
#import gpu::geometry
#import gpu::material
#import gpu::gbuffer_fragment

// Group 1: the laydown's primitive-ID payloads (unread on the builtin path), and where a
// triangle's vertices are: the index buffer, the meshes and the micro batches.
@group(1) @binding(0) var<storage, read> payloads: array<u32>;
@group(1) @binding(1) var<storage, read> indices: array<u32>;
@group(1) @binding(2) var<storage, read> meshes: array<GpuMesh>;
@group(1) @binding(3) var<storage, read> micro_batches: array<GpuMicroBatch>;

struct PullOut {
    @invariant @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) instance: u32,
    @location(1) @interpolate(flat) payload: u32,
}

struct PullIn {
    @builtin(position) frag: vec4<f32>,
    @location(0) @interpolate(flat) instance: u32,
#if primitive_builtin
    @builtin(primitive_index) primitive: u32,
#else
#if primitive_xor
    @location(1) @interpolate(per_vertex) payload: array<u32, 3>,
#else
    @location(1) @interpolate(flat) payload: u32,
#endif
#endif
#if barycentrics
    @builtin(barycentric) bary: vec3<f32>,
#endif
}

// The position-only vertex stage.
@vertex
fn vs_pull(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> PullOut {
    var out: PullOut;
    out.clip = laydown_vertex(vertex, instance).clip;
    out.instance = instance;
    out.payload = 0u;
#if !primitive_builtin
    out.payload = payloads[min(vertex, arrayLength(&payloads) - 1u)];
#endif
    return out;
}

fn pull_primitive(in: PullIn) -> u32 {
#if primitive_builtin
    return in.primitive;
#else
#if primitive_xor
    return in.payload[0] ^ in.payload[1] ^ in.payload[2];
#else
    return in.payload;
#endif
#endif
}

// `i` clamped into an array of `n` elements (n >= 1: bindings are never empty).
fn pull_clamp(i: u32, n: u32) -> u32 {
    return min(i, n - 1u);
}

// A triangle's three vertex indices (into `vertices`) and whether every lookup on the way
// was in range. Out-of-range IDs (a corrupt payload) read clamped elements, never past an
// array, and come back `ok = false`.
struct PullTriangle {
    v: array<u32, 3>,
    ok: bool,
}

fn pull_triangle(instance: u32, primitive: u32) -> PullTriangle {
    var t: PullTriangle;
    let inst = instances[pull_clamp(instance, arrayLength(&instances))];
    let mb = micro_batches[pull_clamp(inst.micro_batch, arrayLength(&micro_batches))];
    let mesh = meshes[pull_clamp(mb.mesh, arrayLength(&meshes))];
    t.ok = instance < arrayLength(&instances) && inst.micro_batch < arrayLength(&micro_batches)
        && mb.mesh < arrayLength(&meshes) && primitive < mesh.primitive_count;
    let first = mesh.first_index + 3u * min(primitive, mesh.primitive_count);
    for (var k = 0u; k < 3u; k++) {
        let j = first + k;
        let v = mesh.base_vertex + indices[pull_clamp(j, arrayLength(&indices))];
        t.ok = t.ok && j >= mesh.first_index && j < arrayLength(&indices) && v < arrayLength(&vertices);
        t.v[k] = pull_clamp(v, arrayLength(&vertices));
    }
    return t;
}

// The seed's fallback, for a device without hardware barycentrics: the weights of the
// pixel's camera ray (through `frag`, a pixel centre) against the triangle of clip
// positions c0..c2, in clip (x, y, w) space, and the weights' screen-space gradients from
// visbuf's edge functions (the resolve's analytic ones: with no interpolated varying the
// quad's differences would be of per-lane ray hits, and on a rasteriser that gives
// varyings their plane's gradient, lavapipe's, those differ from the baseline's texel for
// texel; BENCHMARKS.md has both). A lane whose ray misses (a covered pixel that f32 puts a
// rounding outside) keeps the edge functions' weights.
fn pull_ray_barycentrics(c0: vec4<f32>, c1: vec4<f32>, c2: vec4<f32>, frag: vec2<f32>) -> VisbufBarycentrics {
    var b = visbuf_barycentrics(c0, c1, c2, frag, frame.viewport.xy);
    let ndc = visbuf_pixel_to_ndc(frag, frame.viewport.xy);
    let hit = visbuf_intersect_watertight(vec3<f32>(0.0), vec3<f32>(ndc, 1.0), c0.xyw, c1.xyw, c2.xyw);
    if (hit.hit) {
        b.lambda = hit.barycentrics;
    }
    return b;
}

// The pixel's G-buffer texels from the triangle `primitive` of `instance`, pulled and
// interpolated; `ok` false when an ID was out of range.
struct PullSurface {
    out: GBufferOut,
    ok: bool,
}

fn pull_gbuffer(in: PullIn) -> PullSurface {
    let instance = pull_clamp(in.instance, arrayLength(&instances));
    let inst = instances[instance];
    let t = pull_triangle(in.instance, pull_primitive(in));
    let l0 = laydown_vertex(t.v[0], instance);
    let l1 = laydown_vertex(t.v[1], instance);
    let l2 = laydown_vertex(t.v[2], instance);
#if barycentrics
    let b = in.bary;
    let uv = b.x * l0.uv + b.y * l1.uv + b.z * l2.uv;
    // Gradients from the 2x2 quad, as any fragment shader's (fine: each pixel's own row
    // and column).
    let duv_dx = dpdxFine(uv);
    let duv_dy = dpdyFine(uv);
#else
    let rb = pull_ray_barycentrics(l0.clip, l1.clip, l2.clip, in.frag.xy);
    let b = rb.lambda;
    let g = visbuf_interpolate2(rb, l0.uv, l1.uv, l2.uv);
    let uv = g.value;
    let duv_dx = g.ddx;
    let duv_dy = g.ddy;
#endif
    // As the baseline: each vertex's normal transformed, then interpolated.
    let n = b.x * gpu_transform_normal(inst, vertices[t.v[0]].normal)
        + b.y * gpu_transform_normal(inst, vertices[t.v[1]].normal)
        + b.z * gpu_transform_normal(inst, vertices[t.v[2]].normal);
    let t0 = vertices[t.v[0]].tangent;
    let tangent = vec4<f32>(b.x * gpu_transform_direction(inst, t0.xyz)
        + b.y * gpu_transform_direction(inst, vertices[t.v[1]].tangent.xyz)
        + b.z * gpu_transform_direction(inst, vertices[t.v[2]].tangent.xyz), t0.w);
    // The camera-relative position back from the interpolated clip position.
    let c = frame.inv_view_proj * (b.x * l0.clip + b.y * l1.clip + b.z * l2.clip);
    let p = c.xyz / c.w;
    // The motion of the swaying foliage's surface (as the resolve's): this pose and the
    // previous one interpolated alike, so a still vertex has none.
    var p_now = vec3<f32>(0.0);
    var p_prev = vec3<f32>(0.0);
    for (var k = 0u; k < 3u; k++) {
        let q = vertices[t.v[k]].position;
        p_now += b[k] * gpu_position(inst, q);
        p_prev += b[k] * gpu_previous_position(inst, q);
    }
    let s = material_surface_motion(inst.material, uv, duv_dx, duv_dy, n, tangent, p, material_motion(p_now, p_prev));
    return PullSurface(gbuffer_fragment(s, frame.view_rotation), t.ok);
}

@fragment
fn fs_pull(in: PullIn) -> GBufferOut {
    let r = pull_gbuffer(in);
    if (!r.ok) {
        discard;
    }
    return r.out;
}

// The static instances' variant: the laydown's fade dither first (as fs_baseline_fade).
@fragment
fn fs_pull_fade(in: PullIn) -> GBufferOut {
    let r = pull_gbuffer(in);
    if (!r.ok || !gpu_fade_keeps(instances[pull_clamp(in.instance, arrayLength(&instances))].primitive_bits, vec2<u32>(in.frag.xy))) {
        discard;
    }
    return r.out;
}
