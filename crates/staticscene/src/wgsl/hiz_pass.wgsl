// staticscene::hiz_pass: one level of the conservative HiZ pyramid from the level below
// (twin of HiZ::build): each texel the farthest of the up to 2x2 texels under it, the
// maximum for standard depth, the minimum for reversed; ceil-halved sizes, so odd edges
// keep their last row and column. Level sizes and offsets come from the buffer's header
// (Rust: pass::hiz_header); one dispatch per level, finest first.

#import staticscene::query

struct StaticsceneHizStep {
    // The source level (the dispatch writes level + 1).
    level: u32,
    // Non-zero for reversed depth.
    reversed: u32,
    pad: vec2<u32>,
}

@group(0) @binding(0) var<uniform> step: StaticsceneHizStep;
@group(0) @binding(1) var<storage, read_write> hiz: array<u32>;

fn staticscene_hiz_at(i: u32) -> f32 {
    return bitcast<f32>(hiz[min(i, arrayLength(&hiz) - 1u)]);
}

fn staticscene_farthest(a: f32, b: f32) -> f32 {
    return select(max(a, b), min(a, b), step.reversed != 0u);
}

@compute @workgroup_size(8, 8)
fn hiz_reduce(@builtin(global_invocation_id) id: vec3<u32>) {
    let src = step.level;
    if (src + 1u >= min(hiz[0], STATICSCENE_HIZ_MAX_LEVELS)) {
        return;
    }
    let sw = hiz[4u + src * 4u];
    let sh = hiz[5u + src * 4u];
    let so = hiz[6u + src * 4u];
    let dw = hiz[8u + src * 4u];
    let dh = hiz[9u + src * 4u];
    let dst = hiz[10u + src * 4u];
    if (id.x >= dw || id.y >= dh || sw == 0u || sh == 0u) {
        return;
    }
    let x0 = 2u * id.x;
    let x1 = min(2u * id.x + 1u, sw - 1u);
    let y0 = 2u * id.y;
    let y1 = min(2u * id.y + 1u, sh - 1u);
    let v = staticscene_farthest(
        staticscene_farthest(staticscene_hiz_at(so + y0 * sw + x0), staticscene_hiz_at(so + y0 * sw + x1)),
        staticscene_farthest(staticscene_hiz_at(so + y1 * sw + x0), staticscene_hiz_at(so + y1 * sw + x1)),
    );
    let at = dst + id.y * dw + id.x;
    if (at < arrayLength(&hiz)) {
        hiz[at] = bitcast<u32>(v);
    }
}
