//! The GPU twins: complete WGSL compute modules, one per pass, with the buffer layouts of
//! this crate's Pod structs. The `gpu` crate creates a pipeline per entry point, binds the
//! buffers below at `@group(0)`, dispatches as listed, and can compare every output with
//! the CPU twin bit for bit (the pixel commands after [`canonical_sort`](crate::canonical_sort)).
//!
//! Each module is self-contained: `visbuf`'s [`ID_WGSL`](visbuf::ID_WGSL) (every bit
//! of the vis word is decoded by its functions), a `wave` pass module where the pass
//! appends (path-neutral `wave_append_begin` / `wave_append_end`: one atomic per subgroup
//! on the subgroup path, per workgroup on the fallback), then this crate's common part
//! ([`COMMON_WGSL`]: constants, structs, the single-workgroup scan) and the pass.
//! The two pixel phases (`count_pixels`, `write_commands`) aggregate through a keyed
//! workgroup histogram (`keyed.wgsl`): a 16x16 block lies in one tile whose counters are
//! contiguous, so one LDS atomic per pixel and one global atomic per counter of the block
//! replace the wave-append loop over keys; tiles with more than 256 counters take that loop
//! (`wave`'s appends, one atomic per subgroup and key). Both give the same counts and, after
//! [`canonical_sort`](crate::canonical_sort), the same commands; `tests/device.rs` runs both.
//! The classification modules come in two builds: the plain name needs no optional
//! feature (validated with `Caps::CORE`), `_SUBGROUP` needs `wgpu::Features::SUBGROUP`;
//! [`mid_classify_module`] and [`classify_output_module`] pick one.
//!
//! Units: every length and offset is in elements of the named buffer. "Zero first" means
//! the buffer must hold zeros when the named entry point starts (a `clear_buffer`, or a
//! compute clear). Entry points run in the order listed, each a separate dispatch.
//!
//! # [`LAYDOWN_FINALIZE`] (phase 1)
//!
//! | binding | buffer | element | access |
//! | --- | --- | --- | --- |
//! | 0 | params | [`TilingParams`] | uniform |
//! | 1 | vis buffer, `width * height` | `u32` | read |
//! | 2 | validity bitmask, `ceil(width * height / 32)` (any non-empty buffer without [`FLAG_VALIDITY`]) | `u32` | read |
//! | 3 | MicroBatchInfoTable | [`MicroBatchInfo`] | read |
//! | 4 | masks, `tiles * P` | `atomic<u32>` | read_write, zero first |
//!
//! `laydown_finalize`: workgroup 16x16, dispatch `(ceil(width / 16), ceil(height / 16), 1)`.
//!
//! # [`MID_CLASSIFY`] / [`MID_CLASSIFY_SUBGROUP`] (phase 2)
//!
//! | binding | buffer | element | access |
//! | --- | --- | --- | --- |
//! | 0-3 | as phase 1 | | |
//! | 4 | masks (phase 1) | `u32` | read |
//! | 5 | counter offsets, `tiles * P` | `u32` | read_write |
//! | 6 | counts, one per counter (at most `tiles * P * 32`) | `atomic<u32>` | read_write, zero before `count_pixels` |
//! | 7 | pixel offsets, one per counter | `u32` | read_write |
//! | 8 | vertex cull buffer, `ceil(chunk_count / 4)` (four bytes per word) | `atomic<u32>` | read_write, zero before `count_pixels` |
//! | 9 | index buffer (the table's `first_index` points into it) | `u32` | read |
//! | 10 | totals | [`Totals`] | read_write |
//! | 11 | stats | [`PixelStats`] as `array<atomic<u32>, 8>` | read_write, zero before `count_pixels` |
//!
//! `counter_offsets_pass`: workgroup 256, dispatch `(1, 1, 1)`; writes binding 5 and
//! `totals.counter_count`. `count_pixels`: workgroup 16x16, dispatch
//! `(ceil(width / 16), ceil(height / 16), 1)`; writes 6, 8, 11. `pixel_offsets_pass`:
//! workgroup 256, dispatch `(1, 1, 1)`; writes 7 and `totals.command_count`.
//!
//! # [`CLASSIFY_OUTPUT`] / [`CLASSIFY_OUTPUT_SUBGROUP`] (phase 3)
//!
//! | binding | buffer | element | access |
//! | --- | --- | --- | --- |
//! | 0-3 | as phase 1 (with the final validity) | | |
//! | 4 | masks (phase 1) | `u32` | read |
//! | 5 | counter offsets (phase 2) | `u32` | read |
//! | 6 | counts (phase 2) | `u32` | read |
//! | 7 | pixel offsets (phase 2) | `u32` | read |
//! | 8 | final counts, one per counter | `atomic<u32>` | read_write, zero before `write_commands` |
//! | 9 | commands, `ceil(command_count / 2)`: command `i` in bits `16 (i % 2)..` of word `i / 2` | `atomic<u32>` | read_write, zero before `write_commands` |
//! | 10 | wave offsets, one per counter | `u32` | read_write |
//! | 11 | wave commands (at most `command_count` of them) | [`WaveCommand`] | read_write |
//! | 12 | pass dispatches, `P` (the indirect buffer of the shading passes) | [`PassDispatch`] | read_write |
//! | 13 | totals | [`Totals`] | read_write |
//! | 14 | stats | [`PixelStats`] as `array<atomic<u32>, 8>` | read_write, zero before `write_commands` |
//!
//! `write_commands`: workgroup 16x16, dispatch `(ceil(width / 16), ceil(height / 16), 1)`;
//! writes 8, 9, 14. `wave_offsets_pass`: workgroup 256, dispatch `(1, 1, 1)`; clamps 8 to
//! the counts, writes 10, 12 and `totals.wave_count`. `write_waves`: workgroup 64,
//! dispatch `(ceil(tiles * P / 64), 1, 1)`; writes 11.
//!
//! # [`VERTEX_WAVES`]
//!
//! | binding | buffer | element | access |
//! | --- | --- | --- | --- |
//! | 0 | params ([`TilingParams::micro_batch_count`], `chunk_count`, `uber_count`, `pass_count`, `table_len` used) | [`TilingParams`] | uniform |
//! | 1 | MicroBatchInfoTable | [`MicroBatchInfo`] | read |
//! | 2 | micro-batch order buffer | `u32` | read |
//! | 3 | passes | [`PassInfo`] | read |
//! | 4 | vertex cull buffer (phase 2) | `u32` | read |
//! | 5 | uber chunks, `ceil(chunk_count / 64)` | [`UberChunk`] | read_write |
//! | 6 | histogram pyramid ([`pyramid_levels`]: the sum of the level lengths) | `u32` | read_write |
//! | 7 | deltas, then micro-batch IDs, at least the visible chunks (`chunk_count` is enough) | `atomic<u32>` | read_write, zero before `micro_batch_deltas` |
//! | 8 | vertex waves per order entry | `u32` | read_write |
//! | 9 | vertex wave commands, one per visible chunk | [`VertexWaveCommand`] | read_write |
//! | 10 | vertex dispatches, `P` | [`PassDispatch`] | read_write |
//! | 11 | visible vertices per pass, `P` | `atomic<u32>` | read_write, zero before `micro_batch_deltas` |
//! | 12 | totals | [`Totals`] | read_write |
//!
//! `uber_chunks`: workgroup 64, dispatch `(ceil(uber_count / 64), 1, 1)`. `build_pyramid`:
//! workgroup 256, `(1, 1, 1)`; writes `totals.visible_chunks`. `micro_batch_deltas`:
//! workgroup 64, `(ceil(micro_batch_count / 64), 1, 1)`. `scan_deltas`: workgroup 256,
//! `(1, 1, 1)`. `write_vertex_commands`: workgroup 64, `(ceil(chunk_count / 64), 1, 1)`
//! (past 65 535 workgroups: `(65535, y, 1)`; command `gid.y * 64 * 65535 + gid.x`).
//! `pass_args`: workgroup 64, `(ceil(P / 64), 1, 1)`.
//!
//! [`TilingParams`]: crate::TilingParams
//! [`TilingParams::micro_batch_count`]: crate::TilingParams::micro_batch_count
//! [`FLAG_VALIDITY`]: crate::classify::FLAG_VALIDITY
//! [`MicroBatchInfo`]: crate::MicroBatchInfo
//! [`PassInfo`]: crate::PassInfo
//! [`Totals`]: crate::Totals
//! [`PixelStats`]: crate::PixelStats
//! [`WaveCommand`]: crate::WaveCommand
//! [`PassDispatch`]: crate::PassDispatch
//! [`UberChunk`]: crate::UberChunk
//! [`VertexWaveCommand`]: crate::VertexWaveCommand
//! [`pyramid_levels`]: crate::vertex::pyramid_levels

/// This crate's common WGSL (constants, structs, the workgroup scan), without bindings.
pub const COMMON_WGSL: &str = include_str!("wgsl/common.wgsl");

/// The classification passes' shared bindings 0-3 and pixel decode (needs `visbuf`'s ID
/// snippet and [`COMMON_WGSL`] in front).
pub const PIXEL_WGSL: &str = include_str!("wgsl/pixel.wgsl");

const LAYDOWN_SRC: &str = include_str!("wgsl/laydown_finalize.wgsl");
const MID_SRC: &str = include_str!("wgsl/mid_classify.wgsl");
const OUTPUT_SRC: &str = include_str!("wgsl/classify_output.wgsl");
const VERTEX_SRC: &str = include_str!("wgsl/vertex_waves.wgsl");
const KEYED_SRC: &str = include_str!("wgsl/keyed.wgsl");

const fn joined_len(parts: &[&str]) -> usize {
    let mut n = 0;
    let mut i = 0;
    while i < parts.len() {
        n += parts[i].len() + 1;
        i += 1;
    }
    n
}

const fn join<const N: usize>(parts: &[&str]) -> [u8; N] {
    let mut out = [0u8; N];
    let mut k = 0;
    let mut i = 0;
    while i < parts.len() {
        let b = parts[i].as_bytes();
        let mut j = 0;
        while j < b.len() {
            out[k] = b[j];
            k += 1;
            j += 1;
        }
        out[k] = b'\n';
        k += 1;
        i += 1;
    }
    out
}

/// A `&'static str` made at compile time from string constants (those of other crates
/// included), each followed by a newline.
macro_rules! wgsl_module {
    ($(#[$doc:meta])* $name:ident = [$($part:expr),+ $(,)?]) => {
        $(#[$doc])*
        pub const $name: &str = {
            const PARTS: &[&str] = &[$($part),+];
            const BYTES: [u8; joined_len(PARTS)] = join(PARTS);
            match core::str::from_utf8(&BYTES) {
                Ok(s) => s,
                Err(_) => panic!("WGSL sources are UTF-8"),
            }
        };
    };
}

wgsl_module!(
    /// Phase 1, entry point `laydown_finalize` (core WGSL). See the [module docs](self).
    LAYDOWN_FINALIZE = [visbuf::ID_WGSL, COMMON_WGSL, PIXEL_WGSL, LAYDOWN_SRC]
);

wgsl_module!(
    /// Phase 2, entry points `counter_offsets_pass`, `count_pixels`,
    /// `pixel_offsets_pass`, with `wave`'s workgroup fallback (core WGSL).
    MID_CLASSIFY = [visbuf::ID_WGSL, wave::PASS_MODULE_FALLBACK, COMMON_WGSL, PIXEL_WGSL, MID_SRC, KEYED_SRC]
);

wgsl_module!(
    /// [`MID_CLASSIFY`] with `wave`'s subgroup path (`wgpu::Features::SUBGROUP`).
    MID_CLASSIFY_SUBGROUP = [visbuf::ID_WGSL, wave::PASS_MODULE_SUBGROUP, COMMON_WGSL, PIXEL_WGSL, MID_SRC, KEYED_SRC]
);

wgsl_module!(
    /// Phase 3, entry points `write_commands`, `wave_offsets_pass`, `write_waves`, with
    /// `wave`'s workgroup fallback (core WGSL).
    CLASSIFY_OUTPUT = [visbuf::ID_WGSL, wave::PASS_MODULE_FALLBACK, COMMON_WGSL, PIXEL_WGSL, OUTPUT_SRC, KEYED_SRC]
);

wgsl_module!(
    /// [`CLASSIFY_OUTPUT`] with `wave`'s subgroup path (`wgpu::Features::SUBGROUP`).
    CLASSIFY_OUTPUT_SUBGROUP = [visbuf::ID_WGSL, wave::PASS_MODULE_SUBGROUP, COMMON_WGSL, PIXEL_WGSL, OUTPUT_SRC, KEYED_SRC]
);

wgsl_module!(
    /// The vertex wave commands, entry points `uber_chunks`, `build_pyramid`,
    /// `micro_batch_deltas`, `scan_deltas`, `write_vertex_commands`, `pass_args` (core
    /// WGSL).
    VERTEX_WAVES = [COMMON_WGSL, VERTEX_SRC]
);

/// [`MID_CLASSIFY_SUBGROUP`] on a device with `wgpu::Features::SUBGROUP`, else
/// [`MID_CLASSIFY`].
#[must_use]
pub const fn mid_classify_module(subgroups: bool) -> &'static str {
    if subgroups {
        MID_CLASSIFY_SUBGROUP
    } else {
        MID_CLASSIFY
    }
}

/// [`CLASSIFY_OUTPUT_SUBGROUP`] on a device with `wgpu::Features::SUBGROUP`, else
/// [`CLASSIFY_OUTPUT`].
#[must_use]
pub const fn classify_output_module(subgroups: bool) -> &'static str {
    if subgroups {
        CLASSIFY_OUTPUT_SUBGROUP
    } else {
        CLASSIFY_OUTPUT
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::classify::*;
    use crate::plan::*;
    use crate::vertex::*;
    use alloc::string::String;
    use alloc::vec::Vec;
    use shadercheck::{Caps, assert_valid, const_u32, validate};

    /// Every `TILING_` constant of the common part, with its Rust value.
    fn expected_constants() -> Vec<(&'static str, u32)> {
        let stat = |field: usize| (field / 4) as u32;
        alloc::vec![
            ("TILING_TILE_SIZE", TILE_SIZE),
            ("TILING_TILE_SHIFT", TILE_SHIFT),
            ("TILING_PIXEL_Y_SHIFT", PIXEL_Y_SHIFT),
            ("TILING_PIXEL_COORD_MASK", PIXEL_COORD_MASK),
            ("TILING_QUAD_Y_SHIFT", QUAD_Y_SHIFT),
            ("TILING_QUAD_COORD_MASK", QUAD_COORD_MASK),
            ("TILING_QUAD_PIXELS_SHIFT", QUAD_PIXELS_SHIFT),
            ("TILING_MAX_PASSES", MAX_PASSES),
            ("TILING_MAX_BATCH_GROUPS", MAX_BATCH_GROUPS_PER_PASS),
            ("TILING_MAX_PRIMITIVE_BITS", visbuf::MAX_PRIMITIVE_BITS),
            ("TILING_CHUNK_SIZE", VERTEX_CHUNK_SIZE),
            ("TILING_UBER_CHUNKS", UBER_CHUNK_CHUNKS),
            ("TILING_PYRAMID_FANOUT", PYRAMID_FANOUT),
            ("TILING_MAX_DISPATCH_X", MAX_DISPATCH_X),
            ("TILING_FLAG_VALIDITY", FLAG_VALIDITY),
            ("TILING_FLAG_VRS", FLAG_VRS),
            ("TILING_WAVE_TILE_Y_SHIFT", WAVE_TILE_Y_SHIFT),
            ("TILING_WAVE_GROUP_SHIFT", WAVE_GROUP_SHIFT),
            ("TILING_COMMAND_BITS", u16::BITS),
            ("TILING_NONE", u32::MAX),
            (
                "TILING_STAT_VALID",
                stat(core::mem::offset_of!(PixelStats, valid))
            ),
            (
                "TILING_STAT_EMPTY",
                stat(core::mem::offset_of!(PixelStats, empty))
            ),
            (
                "TILING_STAT_UNKNOWN",
                stat(core::mem::offset_of!(PixelStats, unknown))
            ),
            (
                "TILING_STAT_OUT_OF_RANGE",
                stat(core::mem::offset_of!(PixelStats, out_of_range))
            ),
            (
                "TILING_STAT_COMMANDS",
                stat(core::mem::offset_of!(PixelStats, commands))
            ),
            (
                "TILING_STAT_DROPPED",
                stat(core::mem::offset_of!(PixelStats, dropped))
            ),
            (
                "TILING_STAT_BAD_INDICES",
                stat(core::mem::offset_of!(PixelStats, bad_indices))
            ),
            ("TILING_STAT_COUNT", (size_of::<PixelStats>() / 4) as u32),
        ]
    }

    #[test]
    fn common_constants_match_rust() {
        let m = assert_valid("tiling COMMON_WGSL", COMMON_WGSL, Caps::CORE);
        let expect = expected_constants();
        for (name, value) in &expect {
            assert_eq!(const_u32(&m, name), Some(*value), "WGSL const {name}");
        }
        for name in shadercheck::const_names(&m) {
            assert!(
                expect.iter().any(|(n, _)| *n == name),
                "unchecked WGSL const {name}"
            );
        }
    }

    /// (WGSL struct, Rust size, Rust field names) for every shared struct.
    fn structs() -> Vec<(&'static str, usize, Vec<&'static str>)> {
        alloc::vec![
            (
                "TilingParams",
                size_of::<TilingParams>(),
                alloc::vec![
                    "width",
                    "height",
                    "tiles_x",
                    "tiles_y",
                    "pass_count",
                    "wave_width",
                    "flags",
                    "table_len",
                    "micro_batch_count",
                    "chunk_count",
                    "uber_count",
                    "pad"
                ]
            ),
            (
                "TilingMicroBatchInfo",
                size_of::<MicroBatchInfo>(),
                alloc::vec![
                    "first_id",
                    "id_count",
                    "pass_index",
                    "batch_group",
                    "primitive_bits",
                    "primitive_count",
                    "vertex_count",
                    "instance_count",
                    "first_instance",
                    "batch",
                    "batch_first_instance",
                    "first_index",
                    "base_vertex",
                    "first_chunk",
                    "ring_offset",
                    "order"
                ]
            ),
            (
                "TilingPassInfo",
                size_of::<PassInfo>(),
                alloc::vec![
                    "first_micro_batch",
                    "micro_batch_count",
                    "vertex_count",
                    "first_chunk",
                    "chunk_count",
                    "batch_group_count",
                    "shader",
                    "pad"
                ]
            ),
            (
                "TilingWaveCommand",
                size_of::<WaveCommand>(),
                alloc::vec!["tile", "pass_group", "first_command", "command_count"]
            ),
            (
                "TilingPassDispatch",
                size_of::<PassDispatch>(),
                alloc::vec!["x", "y", "z", "first", "count", "items"]
            ),
            (
                "TilingUberChunk",
                size_of::<UberChunk>(),
                alloc::vec!["mask_lo", "mask_hi", "count", "pad"]
            ),
            (
                "TilingVertexWaveCommand",
                size_of::<VertexWaveCommand>(),
                alloc::vec!["micro_batch", "chunk"]
            ),
            (
                "TilingTotals",
                size_of::<Totals>(),
                alloc::vec![
                    "counter_count",
                    "command_count",
                    "wave_count",
                    "visible_chunks"
                ]
            ),
        ]
    }

    #[test]
    fn structs_have_the_rust_layouts() {
        // Rust field order, checked against the Pod structs by constructing them with
        // distinct values and reading the words back.
        let p = TilingParams {
            width: 0,
            height: 1,
            tiles_x: 2,
            tiles_y: 3,
            pass_count: 4,
            wave_width: 5,
            flags: 6,
            table_len: 7,
            micro_batch_count: 8,
            chunk_count: 9,
            uber_count: 10,
            pad: 11,
        };
        assert_eq!(
            bytemuck::cast::<_, [u32; 12]>(p),
            core::array::from_fn(|i| i as u32)
        );
        let m = MicroBatchInfo {
            first_id: 0,
            id_count: 1,
            pass: 2,
            batch_group: 3,
            primitive_bits: 4,
            primitive_count: 5,
            vertex_count: 6,
            instance_count: 7,
            first_instance: 8,
            batch: 9,
            batch_first_instance: 10,
            first_index: 11,
            base_vertex: 12,
            first_chunk: 13,
            ring_offset: 14,
            order: 15,
        };
        assert_eq!(
            bytemuck::cast::<_, [u32; 16]>(m),
            core::array::from_fn(|i| i as u32)
        );
        let d = PassDispatch {
            x: 0,
            y: 1,
            z: 2,
            first: 3,
            count: 4,
            items: 5,
        };
        assert_eq!(
            bytemuck::cast::<_, [u32; 6]>(d),
            core::array::from_fn(|i| i as u32)
        );
        let s = PixelStats {
            valid: 0,
            empty: 1,
            unknown: 2,
            out_of_range: 3,
            commands: 4,
            dropped: 5,
            bad_indices: 6,
            pad: 7,
        };
        assert_eq!(
            bytemuck::cast::<_, [u32; 8]>(s),
            core::array::from_fn(|i| i as u32)
        );

        let module = assert_valid("tiling COMMON_WGSL", COMMON_WGSL, Caps::CORE);
        for (name, size, fields) in structs() {
            let ty = module
                .types
                .iter()
                .find(|(_, t)| t.name.as_deref() == Some(name))
                .unwrap_or_else(|| panic!("struct {name}"))
                .1;
            match &ty.inner {
                naga::TypeInner::Struct { members, span } => {
                    assert_eq!(*span as usize, size, "{name} size");
                    let names: Vec<&str> = members
                        .iter()
                        .map(|m| m.name.as_deref().unwrap_or(""))
                        .collect();
                    assert_eq!(names, fields, "{name} fields");
                    for (k, m) in members.iter().enumerate() {
                        assert_eq!(m.offset as usize, 4 * k, "{name}.{} offset", names[k]);
                    }
                }
                other => panic!("{name} is not a struct: {other:?}"),
            }
        }
    }

    fn entry_points(m: &naga::Module) -> Vec<String> {
        m.entry_points.iter().map(|e| e.name.clone()).collect()
    }

    #[test]
    fn every_module_validates_with_the_narrowest_caps() {
        let m = assert_valid("LAYDOWN_FINALIZE", LAYDOWN_FINALIZE, Caps::CORE);
        assert_eq!(entry_points(&m), ["laydown_finalize"]);
        for (name, src, caps) in [
            ("MID_CLASSIFY", MID_CLASSIFY, Caps::CORE),
            (
                "MID_CLASSIFY_SUBGROUP",
                MID_CLASSIFY_SUBGROUP,
                Caps::SUBGROUP,
            ),
        ] {
            let m = assert_valid(name, src, caps);
            assert_eq!(
                entry_points(&m),
                ["counter_offsets_pass", "count_pixels", "pixel_offsets_pass"]
            );
        }
        for (name, src, caps) in [
            ("CLASSIFY_OUTPUT", CLASSIFY_OUTPUT, Caps::CORE),
            (
                "CLASSIFY_OUTPUT_SUBGROUP",
                CLASSIFY_OUTPUT_SUBGROUP,
                Caps::SUBGROUP,
            ),
        ] {
            let m = assert_valid(name, src, caps);
            assert_eq!(
                entry_points(&m),
                ["write_commands", "wave_offsets_pass", "write_waves"]
            );
        }
        let m = assert_valid("VERTEX_WAVES", VERTEX_WAVES, Caps::CORE);
        assert_eq!(
            entry_points(&m),
            [
                "uber_chunks",
                "build_pyramid",
                "micro_batch_deltas",
                "scan_deltas",
                "write_vertex_commands",
                "pass_args"
            ]
        );
        // The subgroup builds really need the capability.
        assert!(validate(MID_CLASSIFY_SUBGROUP, Caps::CORE).is_err());
        assert!(validate(CLASSIFY_OUTPUT_SUBGROUP, Caps::CORE).is_err());
        assert_eq!(mid_classify_module(true), MID_CLASSIFY_SUBGROUP);
        assert_eq!(classify_output_module(false), CLASSIFY_OUTPUT);
    }

    #[test]
    fn modules_decode_ids_through_visbuf_and_name_everything_tiling() {
        for src in [LAYDOWN_FINALIZE, MID_CLASSIFY, CLASSIFY_OUTPUT] {
            assert!(src.starts_with(visbuf::ID_WGSL));
        }
        // No re-derived vis-word layout in this crate's sources: no shift by 16 or 30 of a
        // word, no 0xffff / 0x3fff masks.
        for src in [
            COMMON_WGSL,
            PIXEL_WGSL,
            LAYDOWN_SRC,
            MID_SRC,
            OUTPUT_SRC,
            VERTEX_SRC,
        ] {
            for pattern in ["0xffffu", "0x3fffu", ">> 16u", ">> 30u"] {
                assert!(
                    !src.contains(pattern),
                    "tiling WGSL re-derives the vis word: `{pattern}`"
                );
            }
            // Module-scope names carry the prefix (bindings and entry points excepted).
            for line in src.lines() {
                for kw in ["const ", "fn tiling", "struct ", "var<workgroup> "] {
                    if let Some(rest) = line.strip_prefix(kw) {
                        assert!(
                            rest.starts_with("TILING_")
                                || rest.starts_with("Tiling")
                                || rest.starts_with("tiling_")
                                || kw == "fn tiling",
                            "unprefixed: {line}"
                        );
                    }
                }
            }
        }
    }
}
