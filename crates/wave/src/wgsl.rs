//! The WGSL twins: library modules (functions, structs, constants, and for the workgroup
//! path a few `var<workgroup>` scratch variables; no bindings, no entry points) that a pass
//! imports with `#import wave::append` and the like (see the `shader` crate).
//!
//! | module | needs | contents |
//! | --- | --- | --- |
//! | `wave::common` ([`COMMON`]) | core | `WAVE_NO_SLOT`, `WaveAppend`, `WaveBatch`, `wave_slot`, ballot-mask helpers (`wave_ballot_count`, `wave_ballot_count_below` = MaskBitCnt over `wave_word_count_below`, `wave_ballot_first`), order-preserving float words (`wave_ordered_f32`, `wave_unordered_f32`) |
//! | `wave::subgroup` ([`SUBGROUP`]) | `Features::SUBGROUP` | `wave_sg_is_leader`, `wave_sg_append_begin` / `_n_begin` / `_end`: `subgroupBallot`, `subgroupExclusiveAdd`, `subgroupBroadcastFirst` |
//! | `wave::workgroup` ([`WORKGROUP`]) | core | the fallback: `wave_wg_ballot` (workgroup-shared `atomicOr`), `wave_wg_append_*`, `wave_wg_broadcast_leader`, and the run-grouped batch output `wave_wg_batch_begin` / `wave_wg_batch_headers_begin` |
//! | `wave::append` ([`APPEND`]) | with the `subgroups` feature, `Features::SUBGROUP` | the path-neutral `wave_append_begin`, `wave_append_n_begin`, `wave_append_end`: the subgroup path's with the `subgroups` feature, the fallback's without; also imports `wave::workgroup` (the batch output) |
//!
//! # The call-site pattern
//!
//! naga rejects `ptr<storage, ...>` and `ptr<workgroup, ...>` function arguments, so the
//! one global atomic stays in the caller, which can then use any `atomic<u32>` it has (a
//! binding, an array element per tile). Both paths have the same shape:
//!
//! ```wgsl
//! let a = wave_append_begin(keep, li);     // li: @builtin(local_invocation_index)
//! var old = 0u;
//! if (a.total != 0u) { old = atomicAdd(&counter, a.total); }   // the leader only
//! let slot = wave_append_end(a, old);
//! if (slot < arrayLength(&out)) { out[slot] = item; }
//! ```
//!
//! (`wave_sg_append_*` and `wave_wg_append_*` name a path explicitly.)
//!
//! The subgroup functions are subgroup operations and the workgroup ones contain barriers:
//! call them from every invocation (uniform control flow) with the predicate as an
//! argument. Slot order equals the CPU model's: subgroup lane order on the subgroup path
//! (one atomic per subgroup), `local_invocation_index` order on the fallback (one atomic
//! per workgroup, the whole workgroup being one "wave" of up to
//! [`WG_INVOCATIONS_MAX`] lanes). The variable-amount fallback
//! (`wave_wg_append_n_begin`) uses a workgroup-shared `atomicAdd`, so its ranges are
//! contiguous per workgroup but in no fixed order within it.
//!
//! The batch output runs workgroup-wide on every adapter (batches of up to the workgroup
//! size, 2 KiB of workgroup scratch, the talk's "about 2KB of LDS"); with a workgroup of 8,
//! 16, 32 or 64 invocations it equals [`Wave::batch_output`](crate::Wave::batch_output) on
//! a wave of that width, lane for lane.
//!
//! ```
//! // One pass source, both paths: the feature picks the appends.
//! let pass = "#import wave::append
//! @group(0) @binding(0) var<storage, read_write> counter: atomic<u32>;
//! @group(0) @binding(1) var<storage, read_write> out: array<u32>;
//! @compute @workgroup_size(64)
//! fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(local_invocation_index) li: u32) {
//!     let a = wave_append_begin(id.x % 3u == 0u, li);
//!     var old = 0u;
//!     if (a.total != 0u) { old = atomicAdd(&counter, a.total); }
//!     let slot = wave_append_end(a, old);
//!     if (slot < arrayLength(&out)) { out[slot] = id.x; }
//! }";
//! let sg = shader::compose_source(&[wave::wgsl::MODULES], "pass", pass, &["subgroups"])?;
//! assert!(sg.contains("return wave_sg_append_begin(want, local_index);"));
//! let wg = shader::compose_source(&[wave::wgsl::MODULES], "pass", pass, &[])?;
//! assert!(wg.contains("return wave_wg_append_begin(want, local_index);"));
//! assert!(!wg.contains("fn wave_sg_append_begin"));
//! # Ok::<(), shader::Error>(())
//! ```

use shader::Module;

/// Returned by the WGSL `*_append_end` functions to invocations that append nothing (WGSL
/// `WAVE_NO_SLOT`).
pub const NO_SLOT: u32 = u32::MAX;

/// Largest workgroup the WGSL workgroup ballot covers (WGSL `WAVE_WG_INVOCATIONS_MAX`):
/// wgpu's default `max_compute_invocations_per_workgroup`.
pub const WG_INVOCATIONS_MAX: u32 = 256;

/// 32-bit words in a WGSL workgroup ballot (WGSL `WAVE_WG_BALLOT_WORDS`).
pub const WG_BALLOT_WORDS: u32 = WG_INVOCATIONS_MAX / 32;

/// `wave::common`: constants, `WaveAppend`, `WaveBatch`, ballot-mask helpers (core).
pub const COMMON: Module = Module::new("wave::common", include_str!("wgsl/common.wgsl"));

/// `wave::subgroup`: the subgroup path (`wgpu::Features::SUBGROUP`).
pub const SUBGROUP: Module = Module::new("wave::subgroup", include_str!("wgsl/subgroup.wgsl"));

/// `wave::workgroup`: the fallback for adapters without subgroups, and the run-grouped
/// batch output (core).
pub const WORKGROUP: Module = Module::new("wave::workgroup", include_str!("wgsl/workgroup.wgsl"));

/// `wave::append`: `wave_append_*` bound to the subgroup path with the `subgroups`
/// feature, to the workgroup fallback without it.
pub const APPEND: Module = Module::new("wave::append", include_str!("wgsl/append.wgsl"));

/// This crate's modules.
pub const MODULES: &[Module] = &[COMMON, SUBGROUP, WORKGROUP, APPEND];

#[cfg(test)]
mod tests {
    use super::*;
    use shadercheck::{Caps, const_u32, validate};
    use std::format;
    use std::string::String;

    fn composed(root: &str, source: &str, features: &[&str]) -> String {
        shader::compose_source(&[MODULES], root, source, features)
            .unwrap_or_else(|e| panic!("{root}: {e}"))
    }

    fn module(m: Module, caps: Caps) -> naga::Module {
        shadercheck::assert_composed(&[MODULES], m.name, &[], caps)
    }

    /// A test kernel over one path: compaction of `input` by a predicate, with the
    /// counter in `out.counter`.
    fn compaction_kernel(import: &str, lane: &str, builtin: &str) -> String {
        composed(
            "compaction kernel",
            &format!(
                "#import {import}
struct Out {{ counter: atomic<u32>, items: array<u32> }}
@group(0) @binding(0) var<storage, read> input: array<u32>;
@group(0) @binding(1) var<storage, read_write> out: Out;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, {builtin}) {{
    let i = gid.x;
    var item = 0u;
    if (i < arrayLength(&input)) {{ item = input[i]; }}
    let keep = i < arrayLength(&input) && item % 3u == 0u;
    let a = wave_{lane}_append_begin(keep, lane);
    var old = 0u;
    if (a.total != 0u) {{ old = atomicAdd(&out.counter, a.total); }}
    let slot = wave_{lane}_append_end(a, old);
    if (slot < arrayLength(&out.items)) {{ out.items[slot] = item; }}
}}"
            ),
            &[],
        )
    }

    #[test]
    fn common_module_is_core_wgsl() {
        module(COMMON, Caps::CORE);
    }

    #[test]
    fn subgroup_path_validates_and_needs_subgroups() {
        module(SUBGROUP, Caps::SUBGROUP);
        let k = compaction_kernel(
            "wave::subgroup",
            "sg",
            "@builtin(subgroup_invocation_id) lane: u32",
        );
        shadercheck::assert_valid("subgroup compaction kernel", &k, Caps::SUBGROUP);
        assert!(
            validate(&k, Caps::CORE).is_err(),
            "the subgroup path must need the SUBGROUP capability"
        );
    }

    #[test]
    fn workgroup_fallback_validates_with_core_caps() {
        module(WORKGROUP, Caps::CORE);
        let k = compaction_kernel(
            "wave::workgroup",
            "wg",
            "@builtin(local_invocation_index) lane: u32",
        );
        shadercheck::assert_valid("workgroup compaction kernel", &k, Caps::CORE);
    }

    #[test]
    fn one_pass_source_validates_on_both_paths() {
        let pass = "#import wave::append
@group(0) @binding(0) var<storage, read_write> counter: atomic<u32>;
@group(0) @binding(1) var<storage, read_write> out: array<u32>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    let a = wave_append_begin(id.x % 3u == 0u, li);
    var old = 0u;
    if (a.total != 0u) { old = atomicAdd(&counter, a.total); }
    let slot = wave_append_end(a, old);
    if (slot < arrayLength(&out)) { out[slot] = id.x; }
    let n = wave_append_n_begin(id.x % 4u, li);
    var old_n = 0u;
    if (n.total != 0u) { old_n = atomicAdd(&counter, n.total); }
    let first = wave_append_end(n, old_n);
    if (first < arrayLength(&out)) { out[first] = id.x; }
}";
        let sg = composed("pass", pass, &["subgroups"]);
        shadercheck::assert_valid("pass on the subgroup path", &sg, Caps::SUBGROUP);
        assert!(validate(&sg, Caps::CORE).is_err());
        let wg = composed("pass", pass, &[]);
        shadercheck::assert_valid("pass on the fallback", &wg, Caps::CORE);
    }

    #[test]
    fn both_paths_compose_into_one_module() {
        let both = composed(
            "both",
            "#import wave::subgroup\n#import wave::workgroup\n",
            &[],
        );
        shadercheck::assert_valid("both paths", &both, Caps::SUBGROUP);
    }

    #[test]
    fn batch_output_kernel_validates_with_core_caps() {
        let k = composed(
            "batch kernel",
            "#import wave::workgroup
struct Counters { instances: atomic<u32>, batches: atomic<u32> }
@group(0) @binding(0) var<storage, read> input: array<u32>;
@group(0) @binding(1) var<storage, read_write> counters: Counters;
@group(0) @binding(2) var<storage, read_write> instances: array<u32>;
@group(0) @binding(3) var<storage, read_write> batches: array<WaveBatch>;
var<workgroup> bounds_max: array<atomic<u32>, WAVE_WG_INVOCATIONS_MAX>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    let i = gid.x;
    let has = i < arrayLength(&input);
    var rec = 0u;
    if (has) { rec = input[i]; }
    let lane = wave_wg_batch_begin(has && (rec & 1u) != 0u, has && (rec & 2u) != 0u, li);
    var old = 0u;
    if (lane.instance.total != 0u) { old = atomicAdd(&counters.instances, lane.instance.total); }
    let slot = wave_wg_append_end(lane.instance, old);
    if (slot < arrayLength(&instances)) { instances[slot] = rec; }
    if (lane.instance.amount != 0u) { atomicMax(&bounds_max[lane.group], rec >> 2u); }
    let hdr = wave_wg_batch_headers_begin(lane, li);
    var old_b = 0u;
    if (hdr.append.total != 0u) { old_b = atomicAdd(&counters.batches, hdr.append.total); }
    let b = wave_wg_append_end(hdr.append, old_b);
    if (b < arrayLength(&batches)) { batches[b] = WaveBatch(slot, hdr.instance_count); }
    if (hdr.append.amount != 0u) { atomicStore(&bounds_max[lane.group], 0u); }
}",
            &[],
        );
        shadercheck::assert_valid("batch output kernel", &k, Caps::CORE);
    }

    #[test]
    fn wgsl_constants_match_rust() {
        let m = module(WORKGROUP, Caps::CORE);
        assert_eq!(const_u32(&m, "WAVE_NO_SLOT"), Some(NO_SLOT));
        assert_eq!(
            const_u32(&m, "WAVE_WG_INVOCATIONS_MAX"),
            Some(WG_INVOCATIONS_MAX)
        );
        assert_eq!(const_u32(&m, "WAVE_WG_BALLOT_WORDS"), Some(WG_BALLOT_WORDS));
    }

    #[test]
    fn every_item_is_prefixed_and_there_are_no_bindings_or_entry_points() {
        for (m, features, caps) in [
            (APPEND, &["subgroups"][..], Caps::SUBGROUP),
            (APPEND, &[][..], Caps::CORE),
        ] {
            let module = shadercheck::assert_composed(&[MODULES], m.name, features, caps);
            shadercheck::assert_prefixed(m.name, &module, "wave", &[], true);
        }
        // `subgroups` is the one feature, and only `wave::append` reads it.
        assert!(shader::compose(&[MODULES], "wave::workgroup", &["subgroups"]).is_err());
    }

    #[test]
    fn wave_batch_matches_the_rust_layout() {
        use crate::WaveBatch;
        shadercheck::assert_struct_layout(
            &module(COMMON, Caps::CORE),
            "WaveBatch",
            size_of::<WaveBatch>(),
            &shadercheck::members!(WaveBatch {
                first_instance,
                instance_count
            }),
        );
    }
}
