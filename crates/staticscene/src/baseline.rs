//! The flat baseline of the benches: the query without tiles, clusters or packing.
//!
//! Every instance is one unpacked record ([`Flat`], about 200 bytes: its object-to-world
//! and local-to-world matrices, f32 setup bounds, f32 LOD boxes and distances, scale,
//! filter, handle) in f32 world space, and [`flat_query`] runs the same tests in the same
//! order over all of them (filter, parent and child LOD, frustum, size, HiZ occlusion,
//! fade) and emits one draw item per visible instance: what a straightforward CPU culler
//! does, and what HZD's packed tiles and clusters are measured against. World space here
//! is the floating space of the origin given to [`flatten_scene`] (the benches use the
//! world origin: the demo city lies near it).

use alloc::vec::Vec;

use glam::{IVec3, Mat4, Vec3};

use crate::{
    DrawableSetupBatch, DrawableSetupInstance, HiZ, INSTANCE_FLAG_NO_FADE,
    INSTANCE_FLAG_NO_OCCLUSION, InstanceState, QUERY_FLAG_FADE, QUERY_FLAG_OCCLUSION, QueryParams,
    STATE_FADING, STATE_FADING_OUT, Scene, Transform4x3, box_outside_frustum, sort_key,
};

/// One instance, unpacked, in f32 world space: what the flat baseline loops over.
#[derive(Clone, Copy)]
pub struct Flat {
    /// Object to world.
    pub object_to_world: Transform4x3,
    /// Setup local space to world.
    pub local_to_world: Transform4x3,
    /// Setup bounds minimum, local space.
    pub setup_min: Vec3,
    /// Setup bounds maximum, local space.
    pub setup_max: Vec3,
    /// Parent LOD box (object space) and `[min, max)` metres.
    pub parent: (Vec3, Vec3, f32, f32),
    /// Child LOD box (object space) and `[min, max)` metres.
    pub child: (Vec3, Vec3, f32, f32),
    /// Object LOD scale.
    pub lod_scale: f32,
    /// Filter bits.
    pub filter: u8,
    /// Instance flags (`INSTANCE_FLAG_*`).
    pub flags: u8,
    /// Whether the object ignores the view's LOD scale.
    pub ignore_global_lod_scale: bool,
    /// Setup handle.
    pub handle: u64,
}

/// Unpacks the built tiles into flat records in the floating space of `origin` (the
/// benches use the world origin: plain f32 world space).
pub fn flatten_scene(scene: &Scene, origin: IVec3) -> Vec<Flat> {
    let mut out = Vec::with_capacity(scene.instance_count());
    for t in scene.tiles() {
        for q in t.instances() {
            let f = q.try_unpack().unwrap();
            let o = &t.objects()[f.object as usize];
            let o2w = o.object_to_floating(origin);
            let s = &t.setups()[f.setup as usize];
            let pb = &t.bounds()[f.parent_bounds as usize];
            let cb = &t.bounds()[f.child_bounds as usize];
            out.push(Flat {
                object_to_world: o2w,
                local_to_world: o2w.mul(&t.transforms()[f.matrix as usize]),
                setup_min: s.min(),
                setup_max: s.max(),
                parent: (
                    pb.min(),
                    pb.max(),
                    f.parent_lod.min.metres(),
                    f.parent_lod.max.metres(),
                ),
                child: (
                    cb.min(),
                    cb.max(),
                    f.child_lod.min.metres(),
                    f.child_lod.max.metres(),
                ),
                lod_scale: o.lod_scale(),
                filter: f.filter,
                flags: f.flags,
                ignore_global_lod_scale: o.ignores_global_lod_scale(),
                handle: s.handle,
            });
        }
    }
    out
}

fn dist2(p: Vec3, min: Vec3, max: Vec3) -> f32 {
    let d = (min - p).max(p - max).max(Vec3::ZERO);
    d.dot(d)
}

/// The flat baseline: every instance, every test, in order, one item per visible one.
/// The flat loop over `items` (with their fade states `fade`), flattened at
/// `flat_origin`; `base` numbers the instances in the output states.
#[expect(
    clippy::too_many_arguments,
    reason = "the flat baseline takes the same inputs and outputs as the query pass it is measured against"
)]
pub fn flat_query(
    items: &[Flat],
    fade: &mut [u8],
    p: &QueryParams,
    flat_origin: IVec3,
    hiz: Option<&HiZ>,
    out: &mut Vec<DrawableSetupInstance>,
    batches: &mut Vec<DrawableSetupBatch>,
    base: u32,
) {
    // Shift the view from its floating space to the records'.
    let origin = crate::records::floating_offset(p.origin(), flat_origin);
    let lod_point = p.lod_point() + origin;
    let m = p.clip_from_floating() * Mat4::from_translation(-origin);
    let hm = p.hiz_clip_from_floating() * Mat4::from_translation(-origin);
    let planes: [[f32; 4]; 6] = core::array::from_fn(|i| {
        let pl = p.planes[i];
        [
            pl[0],
            pl[1],
            pl[2],
            pl[3] - (pl[0] * origin.x + pl[1] * origin.y + pl[2] * origin.z),
        ]
    });
    let w_row = m.row(3);
    let n = p.fade_frames as u8;
    let fade_on = p.flags & QUERY_FLAG_FADE != 0 && n > 0;
    let hiz = if p.flags & QUERY_FLAG_OCCLUSION != 0 {
        hiz
    } else {
        None
    };
    for (i, (it, fs)) in items.iter().zip(fade.iter_mut()).enumerate() {
        if u32::from(it.filter) & p.filter_mask == 0 {
            continue;
        }
        let scale = if it.ignore_global_lod_scale {
            it.lod_scale
        } else {
            it.lod_scale * p.lod_point[3]
        };
        let s2 = scale * scale;
        let sel = |(lo, hi, a, b): (Vec3, Vec3, f32, f32)| {
            let (mn, mx) = it.object_to_world.transform_aabb(lo, hi);
            let d2 = dist2(lod_point, mn, mx);
            d2 >= a * a * s2 && d2 < b * b * s2
        };
        let lod = sel(it.parent) && sel(it.child);
        if !lod && (!fade_on || *fs == 0) {
            continue;
        }
        let (mn, mx) = it.local_to_world.transform_aabb(it.setup_min, it.setup_max);
        let in_frustum = !box_outside_frustum(&planes, mn, mx);
        let c = (mn + mx) * 0.5;
        let r = (mx - mn).length() * 0.5;
        let w = w_row.truncate().dot(c) + w_row.w - r * w_row.truncate().length();
        let big = w <= 0.0 || 2.0 * r * p.viewport[3] >= p.viewport[2] * w;
        let occluded = in_frustum
            && big
            && it.flags & INSTANCE_FLAG_NO_OCCLUSION == 0
            && hiz.is_some_and(|z| z.occluded(&hm, mn, mx, p.hiz_scan_levels));
        let (shown, fade, flags) = if fade_on && it.flags & INSTANCE_FLAG_NO_FADE == 0 {
            *fs = if !in_frustum {
                if lod { n } else { 0 }
            } else if lod {
                (*fs + 1).min(n)
            } else {
                fs.saturating_sub(1)
            };
            let mut flags = if *fs < n { STATE_FADING } else { 0 };
            if !lod {
                flags |= STATE_FADING_OUT;
            }
            (*fs > 0, f32::from(*fs) / f32::from(n), flags)
        } else {
            (lod, 1.0, 0)
        };
        if !(in_frustum && big && !occluded && shown) {
            continue;
        }
        batches.push(DrawableSetupBatch {
            sort_key: sort_key(it.handle, 0.0),
            setup: it.handle,
            sphere: [c.x, c.y, c.z, r],
            first_instance: out.len() as u32,
            flags,
            count: 1,
            stride: 64,
        });
        out.push(DrawableSetupInstance {
            state: InstanceState {
                fade,
                flags,
                tile: 0,
                instance: base + i as u32,
            },
            local_to_floating: it.local_to_world,
        });
    }
}
