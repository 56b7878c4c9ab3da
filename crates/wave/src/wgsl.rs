//! The WGSL twins: binding-free snippets (functions, structs, constants, and for the
//! workgroup path a few `var<workgroup>` scratch variables) that the `gpu` crate
//! concatenates in front of its passes.
//!
//! | module | needs | contents |
//! | --- | --- | --- |
//! | [`WAVE_WGSL`] | core | `WAVE_NO_SLOT`, `WaveAppend`, `WaveBatch`, `wave_slot`, ballot-mask helpers (`wave_ballot_count`, `wave_ballot_count_below` = MaskBitCnt, `wave_ballot_first`) |
//! | [`WAVE_SUBGROUP_WGSL`] | `Features::SUBGROUP` | `wave_sg_is_leader`, `wave_sg_append_begin` / `_n_begin` / `_end`: `subgroupBallot`, `subgroupExclusiveAdd`, `subgroupBroadcastFirst` |
//! | [`WAVE_WORKGROUP_WGSL`] | core | the fallback: `wave_wg_ballot` (workgroup-shared `atomicOr`), `wave_wg_append_*`, `wave_wg_broadcast_leader`, and the run-grouped batch output `wave_wg_batch_begin` / `wave_wg_batch_headers_begin` |
//!
//! Each snippet after the first needs [`WAVE_WGSL`] in front of it; [`SUBGROUP_MODULE`]
//! and [`WORKGROUP_MODULE`] are those concatenations, ready to prepend. For a pass that
//! should run on either kind of adapter, [`module_for`] picks [`PASS_MODULE_SUBGROUP`] or
//! [`PASS_MODULE_FALLBACK`], which also bind the path-neutral `wave_append_begin`,
//! `wave_append_n_begin` and `wave_append_end` to one path.
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

/// Returned by the WGSL `*_append_end` functions to invocations that append nothing (WGSL
/// `WAVE_NO_SLOT`).
pub const NO_SLOT: u32 = u32::MAX;

/// Largest workgroup the WGSL workgroup ballot covers (WGSL `WAVE_WG_INVOCATIONS_MAX`):
/// wgpu's default `max_compute_invocations_per_workgroup`.
pub const WG_INVOCATIONS_MAX: u32 = 256;

/// 32-bit words in a WGSL workgroup ballot (WGSL `WAVE_WG_BALLOT_WORDS`).
pub const WG_BALLOT_WORDS: u32 = WG_INVOCATIONS_MAX / 32;

/// Common definitions (core WGSL): constants, `WaveAppend`, `WaveBatch`, ballot-mask
/// helpers. Prepend to either path.
pub const WAVE_WGSL: &str = include_str!("wgsl/common.wgsl");

/// The subgroup path (`wgpu::Features::SUBGROUP`); needs [`WAVE_WGSL`] in front.
pub const WAVE_SUBGROUP_WGSL: &str = include_str!("wgsl/subgroup.wgsl");

/// The workgroup path for adapters without subgroups, and the run-grouped batch output
/// (core WGSL); needs [`WAVE_WGSL`] in front.
pub const WAVE_WORKGROUP_WGSL: &str = include_str!("wgsl/workgroup.wgsl");

/// [`WAVE_WGSL`] followed by [`WAVE_SUBGROUP_WGSL`].
pub const SUBGROUP_MODULE: &str = concat!(
    include_str!("wgsl/common.wgsl"),
    "\n",
    include_str!("wgsl/subgroup.wgsl")
);

/// [`WAVE_WGSL`] followed by [`WAVE_WORKGROUP_WGSL`].
pub const WORKGROUP_MODULE: &str = concat!(
    include_str!("wgsl/common.wgsl"),
    "\n",
    include_str!("wgsl/workgroup.wgsl")
);

/// Everything for an adapter with `Features::SUBGROUP`: both paths, the batch output, and
/// the path-neutral `wave_append_begin` / `wave_append_n_begin` / `wave_append_end` bound
/// to the subgroup path. See [`module_for`].
pub const PASS_MODULE_SUBGROUP: &str = concat!(
    include_str!("wgsl/common.wgsl"),
    "\n",
    include_str!("wgsl/subgroup.wgsl"),
    "\n",
    include_str!("wgsl/workgroup.wgsl"),
    "\n",
    include_str!("wgsl/select_subgroup.wgsl")
);

/// Everything for an adapter without subgroups (core WGSL): the workgroup path, the batch
/// output, and `wave_append_*` bound to the workgroup path. See [`module_for`].
pub const PASS_MODULE_FALLBACK: &str = concat!(
    include_str!("wgsl/common.wgsl"),
    "\n",
    include_str!("wgsl/workgroup.wgsl"),
    "\n",
    include_str!("wgsl/select_workgroup.wgsl")
);

/// The module to prepend to a pass written against the path-neutral `wave_append_*`
/// functions: [`PASS_MODULE_SUBGROUP`] when the device has `wgpu::Features::SUBGROUP`,
/// else [`PASS_MODULE_FALLBACK`]. The pass passes `@builtin(local_invocation_index)` as
/// the id on both paths, so its source is the same.
///
/// ```
/// let pass = "
/// @group(0) @binding(0) var<storage, read_write> counter: atomic<u32>;
/// @group(0) @binding(1) var<storage, read_write> out: array<u32>;
/// @compute @workgroup_size(64)
/// fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(local_invocation_index) li: u32) {
///     let a = wave_append_begin(id.x % 3u == 0u, li);
///     var old = 0u;
///     if (a.total != 0u) { old = atomicAdd(&counter, a.total); }
///     let slot = wave_append_end(a, old);
///     if (slot < arrayLength(&out)) { out[slot] = id.x; }
/// }";
/// for subgroups in [true, false] {
///     let src = format!("{}\n{pass}", wave::module_for(subgroups));
///     assert!(src.contains("fn wave_append_begin"));
/// }
/// ```
#[must_use]
pub const fn module_for(subgroups: bool) -> &'static str {
    if subgroups {
        PASS_MODULE_SUBGROUP
    } else {
        PASS_MODULE_FALLBACK
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shadercheck::{Caps, assert_valid, const_u32, validate};
    use std::format;
    use std::string::String;

    /// A test kernel over the snippet: compaction of `input` by a predicate, with the
    /// counter in `out.counter`.
    fn compaction_kernel(prefix: &str, lane: &str, builtin: &str) -> String {
        format!(
            "{prefix}
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
        )
    }

    #[test]
    fn common_snippet_is_core_wgsl() {
        assert_valid("WAVE_WGSL", WAVE_WGSL, Caps::CORE);
    }

    #[test]
    fn subgroup_path_validates_and_needs_subgroups() {
        assert_valid("SUBGROUP_MODULE", SUBGROUP_MODULE, Caps::SUBGROUP);
        let k = compaction_kernel(
            SUBGROUP_MODULE,
            "sg",
            "@builtin(subgroup_invocation_id) lane: u32",
        );
        assert_valid("subgroup compaction kernel", &k, Caps::SUBGROUP);
        assert!(
            validate(&k, Caps::CORE).is_err(),
            "the subgroup path must need the SUBGROUP capability"
        );
    }

    #[test]
    fn workgroup_fallback_validates_with_core_caps() {
        assert_valid("WORKGROUP_MODULE", WORKGROUP_MODULE, Caps::CORE);
        let k = compaction_kernel(
            WORKGROUP_MODULE,
            "wg",
            "@builtin(local_invocation_index) lane: u32",
        );
        assert_valid("workgroup compaction kernel", &k, Caps::CORE);
    }

    #[test]
    fn one_pass_source_validates_on_both_paths() {
        let pass = "
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
        let sg = format!("{}\n{pass}", module_for(true));
        assert_valid("pass on the subgroup path", &sg, Caps::SUBGROUP);
        assert!(validate(&sg, Caps::CORE).is_err());
        let wg = format!("{}\n{pass}", module_for(false));
        assert_valid("pass on the fallback", &wg, Caps::CORE);
    }

    #[test]
    fn both_paths_concatenate_into_one_module() {
        let both = format!("{WAVE_WGSL}\n{WAVE_SUBGROUP_WGSL}\n{WAVE_WORKGROUP_WGSL}");
        assert_valid("both paths", &both, Caps::SUBGROUP);
    }

    #[test]
    fn batch_output_kernel_validates_with_core_caps() {
        let k = format!(
            "{WORKGROUP_MODULE}
struct Counters {{ instances: atomic<u32>, batches: atomic<u32> }}
@group(0) @binding(0) var<storage, read> input: array<u32>;
@group(0) @binding(1) var<storage, read_write> counters: Counters;
@group(0) @binding(2) var<storage, read_write> instances: array<u32>;
@group(0) @binding(3) var<storage, read_write> batches: array<WaveBatch>;
var<workgroup> bounds_max: array<atomic<u32>, WAVE_WG_INVOCATIONS_MAX>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) li: u32) {{
    let i = gid.x;
    let has = i < arrayLength(&input);
    var rec = 0u;
    if (has) {{ rec = input[i]; }}
    let lane = wave_wg_batch_begin(has && (rec & 1u) != 0u, has && (rec & 2u) != 0u, li);
    var old = 0u;
    if (lane.instance.total != 0u) {{ old = atomicAdd(&counters.instances, lane.instance.total); }}
    let slot = wave_wg_append_end(lane.instance, old);
    if (slot < arrayLength(&instances)) {{ instances[slot] = rec; }}
    if (lane.instance.amount != 0u) {{ atomicMax(&bounds_max[lane.group], rec >> 2u); }}
    let hdr = wave_wg_batch_headers_begin(lane, li);
    var old_b = 0u;
    if (hdr.append.total != 0u) {{ old_b = atomicAdd(&counters.batches, hdr.append.total); }}
    let b = wave_wg_append_end(hdr.append, old_b);
    if (b < arrayLength(&batches)) {{ batches[b] = WaveBatch(slot, hdr.instance_count); }}
    if (hdr.append.amount != 0u) {{ atomicStore(&bounds_max[lane.group], 0u); }}
}}"
        );
        assert_valid("batch output kernel", &k, Caps::CORE);
    }

    #[test]
    fn wgsl_constants_match_rust() {
        let m = assert_valid("WORKGROUP_MODULE", WORKGROUP_MODULE, Caps::CORE);
        assert_eq!(const_u32(&m, "WAVE_NO_SLOT"), Some(NO_SLOT));
        assert_eq!(
            const_u32(&m, "WAVE_WG_INVOCATIONS_MAX"),
            Some(WG_INVOCATIONS_MAX)
        );
        assert_eq!(const_u32(&m, "WAVE_WG_BALLOT_WORDS"), Some(WG_BALLOT_WORDS));
        for name in shadercheck::const_names(&m) {
            assert!(name.starts_with("WAVE_"), "unprefixed constant {name}");
        }
    }

    #[test]
    fn every_item_is_prefixed_and_there_are_no_bindings_or_entry_points() {
        let m = assert_valid("PASS_MODULE_SUBGROUP", PASS_MODULE_SUBGROUP, Caps::SUBGROUP);
        assert!(m.entry_points.is_empty());
        for (_, f) in m.functions.iter() {
            let name = f.name.as_deref().unwrap_or("");
            assert!(name.starts_with("wave_"), "unprefixed function {name}");
        }
        for (_, g) in m.global_variables.iter() {
            assert!(g.binding.is_none(), "snippet declares a binding");
            assert_eq!(g.space, naga::AddressSpace::WorkGroup);
            let name = g.name.as_deref().unwrap_or("");
            assert!(name.starts_with("wave_wg_"), "unprefixed variable {name}");
        }
        for (_, t) in m.types.iter() {
            if let Some(name) = t.name.as_deref() {
                assert!(name.starts_with("Wave"), "unprefixed struct {name}");
            }
        }
    }

    #[test]
    fn wave_batch_matches_the_rust_layout() {
        let m = assert_valid("WAVE_WGSL", WAVE_WGSL, Caps::CORE);
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(m.to_ctx()).expect("layout");
        let (h, _) = m
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some("WaveBatch"))
            .expect("WaveBatch declared");
        assert_eq!(
            layouter[h].size as usize,
            size_of::<crate::WaveBatch>(),
            "WGSL WaveBatch size"
        );
    }
}
