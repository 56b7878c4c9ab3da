//! HFW's vertex side on the GPU: the vertex wave commands built from the frame's own vertex
//! cull buffer equal `tiling`'s CPU twin on the read-back cull buffer; every vertex the
//! ring holds equals `VisbufVertex::pack` of an independent CPU transform (f64, the wind's
//! CPU reference, both cameras) within f16 rounding; the talk's "vertices after culling"
//! from the GPU's own dispatch counters equals the read-back's count. After a frame each
//! half of the ring holds the last pass that used it (pass p + 2 reuses p's half), so the
//! contents are checked for the last two passes, with rings of one and of three passes.

mod common;

use demo::{DemoOptions, DemoScene};
use glam::{DMat4, DVec3, Vec3};
use gpu::config::PrimitiveIdPath;
use gpu::scene::Wind;
use gpu::{Camera, RenderPath, RendererConfig};
use visbuf::{Vertex, VertexCore, VisbufVertex};

const W: u32 = 192;
const H: u32 = 108;

/// World -> clip of `camera` for the renderer's aspect (f64).
fn view_proj(camera: &Camera) -> DMat4 {
    let aspect = f64::from(W) / f64::from(H);
    DMat4::perspective_infinite_reverse_rh(f64::from(camera.fov_y), aspect, f64::from(camera.near))
        * DMat4::look_at_rh(
            camera.position.as_dvec3(),
            camera.target.as_dvec3(),
            camera.up.as_dvec3(),
        )
}

/// The largest f16 rounding step at `x` (half an ulp of binary16), with a floor for
/// subnormals.
fn half_step(x: f32) -> f32 {
    (x.abs() * 2f32.powi(-10)).max(2f32.powi(-14))
}

#[test]
fn ring_holds_the_cpu_transform_and_the_commands_equal_the_cpu_twin() {
    for (ring_bytes, density) in [(gpu::config::RING_BYTES_PS4, 0.1), (1 << 21, 0.05)] {
        let (mut scene, frame) = demo::build(&DemoOptions {
            scene: DemoScene::Forest,
            seed: 3,
            density,
        });
        let wind = Wind::default();
        scene.wind = Some(wind);
        let mut r = common::renderer_with({
            let mut rc = RendererConfig::sized(W, H);
            rc.geometry.primitive_id = Some(PrimitiveIdPath::Builtin);
            rc.geometry.vertex_ring = Some(ring_bytes);
            rc.lighting.shadows = None;
            rc
        });
        let prepared = r.prepare(&scene).unwrap();
        assert_eq!(
            prepared.summary().added_vertices,
            0,
            "builtin primitive IDs"
        );
        // Two frames: the camera moved and time advanced, so previous positions differ.
        let mut before = frame.clone();
        before.camera.position += Vec3::new(-0.4, 0.05, 0.3);
        before.time = 2.0;
        let mut now = frame.clone();
        now.time = 2.25;
        r.render(&prepared, &before, RenderPath::Deferred).unwrap();
        r.render(&prepared, &now, RenderPath::Deferred).unwrap();
        let gpu_class = r.inspect().read_classification(&prepared).unwrap();
        let ring = r
            .inspect()
            .read_vertex_ring(&prepared)
            .unwrap()
            .expect("a ring");
        let plan = prepared.tiling_plan();

        // The commands: tiling's CPU twin on the read-back cull buffer.
        let cpu = tiling::vertex_wave_commands(
            &gpu_class.vertex_cull,
            plan.chunk_count,
            &plan.table,
            &plan.order,
            &plan.passes,
        )
        .unwrap();
        assert_eq!(ring.ubers, cpu.ubers, "uber chunks");
        assert_eq!(ring.pyramid, cpu.pyramid.data, "pyramid");
        let ids: Vec<u32> = cpu.commands.iter().map(|c| c.micro_batch).collect();
        assert_eq!(ring.micro_batch_ids, ids, "scanned micro-batch IDs");
        assert_eq!(ring.micro_batch_waves, cpu.micro_batch_waves);
        assert_eq!(ring.commands, cpu.commands, "vertex wave commands");
        assert_eq!(ring.dispatches, cpu.passes, "vertex dispatches");
        assert_eq!(ring.visible_chunks as usize, cpu.commands.len());
        // The talk's table from the GPU's own counters and from the read-back.
        let (stats, _) = r
            .inspect()
            .classification_statistics(&prepared, &gpu_class)
            .unwrap();
        assert_eq!(ring.vertices_transformed(), cpu.visible_vertices());
        assert_eq!(
            ring.vertices_transformed(),
            stats.vertices_after_chunk_culling,
            "GPU counters vs read-back measurement"
        );
        let scene_vertices = prepared.summary().vertices;
        eprintln!(
            "ring {ring_bytes} B: {} passes, {} of {scene_vertices} vertices transformed ({:.0}%)",
            plan.passes.len(),
            ring.vertices_transformed(),
            100.0 * ring.vertices_transformed() as f64 / scene_vertices as f64
        );
        assert!(ring.vertices_transformed() > 0 && ring.vertices_transformed() < scene_vertices);

        // Every transformed vertex against the CPU transform.
        let origin = prepared.summary().origin;
        let vp_now = view_proj(&now.camera);
        let vp_before = view_proj(&before.camera);
        let (mut checked, mut worst) = (0usize, 0f32);
        for (p, d) in ring.dispatches.iter().enumerate() {
            let base = ring.half_base[p];
            if base == u32::MAX {
                continue;
            }
            // No pass uses more than half the ring.
            assert!(plan.passes[p].vertex_count <= ring.ring_vertices / 2);
            // Pass p + 2 reuses p's half: after the frame, a half holds its last pass.
            if p + 2 < ring.dispatches.len() {
                continue;
            }
            for c in &ring.commands[d.first as usize..(d.first + d.count) as usize] {
                let row = &plan.table[c.micro_batch as usize];
                let batch = &scene.batches[row.batch as usize];
                let mesh = &scene.meshes[batch.mesh.0];
                let shader = scene.materials[batch.material.0].shader;
                let order = prepared.instance_order(row.batch as usize).unwrap();
                for lane in 0..64 {
                    let v = c.chunk * 64 + lane;
                    if v >= row.vertex_count * row.instance_count {
                        break;
                    }
                    let (i, k) = (v / row.vertex_count, (v % row.vertex_count) as usize);
                    let t =
                        &batch.instances[order[(row.batch_first_instance + i) as usize] as usize];
                    let p_obj = mesh.positions[k];
                    let world = t.transform_point3(p_obj).as_dvec3();
                    let sway = |time: f32| -> DVec3 {
                        if shader == scene::ShaderKind::AlphaTested {
                            let tr = Vec3::from(t.translation) - origin;
                            wind.displacement(tr, p_obj, time).as_dvec3()
                        } else {
                            DVec3::ZERO
                        }
                    };
                    let clip = vp_now * (world + sway(now.time)).extend(1.0);
                    let prev = vp_before * (world + sway(before.time)).extend(1.0);
                    let n = t.transform_vector3(mesh.normals[k]).normalize();
                    let tan = mesh.tangents[k];
                    let tx = t.transform_vector3(tan.truncate());
                    let want = VisbufVertex::pack(&Vertex {
                        core: VertexCore {
                            hpos: Vec3::new(clip.x as f32, clip.y as f32, clip.w as f32),
                            normal: n,
                            tangent: tx.extend(tan.w),
                            prev_hpos: Vec3::new(prev.x as f32, prev.y as f32, prev.w as f32),
                        },
                        uv: mesh.uvs[k].clamp(glam::Vec2::ZERO, glam::Vec2::splat(7.999)),
                        color: glam::Vec4::ONE,
                        extra: 0,
                    })
                    .unwrap()
                    .unpack();
                    let slot = gpu::inspect::ring_slot(
                        ring.ring_vertices,
                        p as u32,
                        row.ring_offset,
                        row.vertex_count,
                        i,
                        k as u32,
                    );
                    let got = ring.ring[slot as usize].unpack();
                    let (g, w) = (got.core, want.core);
                    // Positions: within one f16 step (the GPU's f32 transform rounds
                    // differently from the f64 one before packing); w within f32 noise.
                    for (a, b) in [
                        (g.hpos.x, w.hpos.x),
                        (g.hpos.y, w.hpos.y),
                        (g.prev_hpos.x, w.prev_hpos.x),
                        (g.prev_hpos.y, w.prev_hpos.y),
                        (g.prev_hpos.z, w.prev_hpos.z),
                    ] {
                        let err = (a - b).abs() / half_step(b);
                        worst = worst.max(err);
                        assert!(err <= 2.0, "slot {slot}: {a} vs {b} ({g:?} vs {w:?})");
                    }
                    assert!(
                        (g.hpos.z - w.hpos.z).abs() <= 1e-5 * w.hpos.z.abs().max(1e-3),
                        "w {} vs {}",
                        g.hpos.z,
                        w.hpos.z
                    );
                    // Normals and tangents: one 10-bit code.
                    assert!((g.normal - w.normal).abs().max_element() <= 2.0 / 511.0);
                    assert!(
                        (g.tangent.truncate() - w.tangent.truncate())
                            .abs()
                            .max_element()
                            <= 2.0 / 511.0
                    );
                    assert_eq!(g.tangent.w, w.tangent.w);
                    // UVs in the code's range exactly; others flagged for the vertex buffer.
                    let uv = mesh.uvs[k];
                    if uv.cmpge(glam::Vec2::ZERO).all() && uv.cmple(glam::Vec2::splat(7.9999)).all()
                    {
                        assert_eq!(got.uv, want.uv);
                        assert_eq!(got.extra, 0);
                    } else {
                        assert_eq!(got.extra, gpu::inspect::RING_UV_FROM_VERTICES);
                    }
                    checked += 1;
                }
            }
        }
        eprintln!("{checked} ring vertices checked, worst {worst:.2} f16 half-steps");
        let last_two: u64 = ring
            .dispatches
            .iter()
            .rev()
            .take(2)
            .map(|d| u64::from(d.items))
            .sum();
        assert_eq!(checked as u64, last_two);
    }
}

/// The resolve reading its triangle's vertices from the ring writes the G-buffer of the
/// per-pixel transform within the ring's quantisation: per pixel, albedo within 3/255 in
/// 99% of the pixels (f16 HPOS moves barycentrics by about 1e-3 and so UVs and mips;
/// texels near an alpha or colour edge differ more), normals within 0.02, the baked sun
/// term and motion within 0.05 (motion: + 1%, the previous HPOS is f16 too); equal
/// coverage (the vis buffer is the same); a ring of three passes (halves reused)
/// included. Also the mean error is small everywhere.
#[test]
fn resolve_from_the_ring_equals_the_per_pixel_transform() {
    for ring_bytes in [gpu::config::RING_BYTES_PS5, 1 << 21] {
        let (mut scene, frame) = demo::build(&DemoOptions {
            scene: DemoScene::Forest,
            seed: 5,
            density: 0.05,
        });
        scene.wind = Some(Wind::default());
        let mut before = frame.clone();
        before.camera.position += Vec3::new(0.3, 0.0, -0.2);
        before.time = 1.0;
        let mut now = frame.clone();
        now.time = 1.1;
        let mut gbuffers = Vec::new();
        for ring_resolve in [false, true] {
            let mut r = common::renderer_with({
                let mut rc = RendererConfig::sized(W, H);
                rc.geometry.vertex_ring = Some(ring_bytes);
                rc.geometry.ring_resolve = ring_resolve;
                rc.lighting.shadows = None;
                rc
            });
            let prepared = r.prepare(&scene).unwrap();
            r.render(&prepared, &before, RenderPath::Deferred).unwrap();
            let out = r.render(&prepared, &now, RenderPath::Deferred).unwrap();
            let labels: Vec<&str> = out.gpu.iter().map(|t| t.label).collect();
            eprintln!("ring {ring_bytes} B, ring resolve {ring_resolve}: passes timed {labels:?}");
            gbuffers.push((
                r.inspect().read_gbuffer().unwrap(),
                r.inspect().read_depth().unwrap(),
            ));
        }
        let (per_pixel, depth) = &gbuffers[0];
        let (ring, depth_ring) = &gbuffers[1];
        assert!(depth == depth_ring, "the same laydown");
        let (mut covered, mut albedo_off, mut other_off) = (0usize, 0usize, 0usize);
        let (mut albedo_sum, mut normal_worst) = (0f64, 0f32);
        for ((a, b), &d) in per_pixel.iter().zip(ring).zip(depth) {
            // Sky: the G-buffer keeps older frames' values there (lighting reads depth).
            if d <= 0.0 {
                continue;
            }
            covered += 1;
            let da = (a.albedo - b.albedo).abs().max_element();
            albedo_sum += f64::from(da);
            albedo_off += usize::from(da > 3.0 / 255.0);
            let dn = (a.normal - b.normal).abs().max_element();
            normal_worst = normal_worst.max(dn);
            let dm = (a.motion - b.motion).length();
            let bad = dn > 0.02
                || (a.sun_shadow - b.sun_shadow).abs() > 0.05
                || dm > 0.05 + 0.01 * a.motion.length()
                || a.roughness != b.roughness
                || a.specular != b.specular;
            other_off += usize::from(bad);
        }
        eprintln!(
            "ring {ring_bytes} B: {covered} pixels, albedo off by > 3/255 in {albedo_off} (mean {:.5}), \
             normal worst {normal_worst:.4}, {other_off} off in normal / sun / motion",
            albedo_sum / covered as f64
        );
        assert!(covered > 5000);
        assert!(albedo_off * 100 <= covered, "{albedo_off} of {covered}");
        assert!(albedo_sum / (covered as f64) < 1.0 / 255.0);
        assert!(other_off * 200 <= covered, "{other_off} of {covered}");
        // The ring was read: its f16 positions and 10-bit normals leave their mark (a
        // resolve that fell back to the per-pixel transform would equal it exactly).
        assert!(
            albedo_sum > 0.0 || normal_worst > 0.0,
            "the ring resolve equals the per-pixel one bit for bit: the ring was not read"
        );
    }
}
