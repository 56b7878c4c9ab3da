//! The query on rayon's threads: the same pre-cull and the same cluster jobs as
//! [`Scene::query`], the jobs run in parallel (one compute job per cluster, as on the
//! GPU), each into its own output, then concatenated in job order. The result equals the
//! sequential query exactly (instances, batches, fade states, stats; tested).
//!
//! On the GPU the jobs share one instance counter and one batch counter, so which job's
//! output comes first depends on scheduling; here each job appends through its own
//! counters (with `wave`'s run-grouped output) and the concatenation fixes the order,
//! which is what lets the parallel result be compared with the sequential one.

use alloc::vec::Vec;

use rayon::prelude::*;

use crate::scene::{append, run_into, set_live};
use crate::{
    DrawableSetupBatch, Error, HiZ, OutputInstance, QueryOptions, QueryOutput, QueryParams,
    QueryStats, Scene,
};

struct JobResult<I> {
    instances: Vec<I>,
    batches: Vec<DrawableSetupBatch>,
    stats: QueryStats,
    live: bool,
}

impl Scene {
    /// [`Scene::query`] with the cluster jobs on rayon's threads; equal to it exactly.
    pub fn par_query<I: OutputInstance>(
        &mut self,
        params: &QueryParams,
        hiz: Option<&HiZ>,
        options: &QueryOptions,
        out: &mut QueryOutput<I>,
    ) -> Result<(), Error> {
        let (c, jobs) = self.begin_query(params, options, out);
        let (tiles, parts) = self.parts_mut();

        // Each job's fade states: disjoint sub-slices, jobs being in tile and cluster order.
        let mut rest: Vec<(&mut [u8], usize)> = Vec::with_capacity(parts.len());
        let mut cluster_states: Vec<&mut [u8]> = Vec::with_capacity(parts.len());
        for (inst, clusters) in parts {
            rest.push((inst, 0));
            cluster_states.push(clusters);
        }
        let mut work: Vec<(crate::scene::PlannedJob, &mut [u8])> = Vec::with_capacity(jobs.len());
        for pj in &jobs {
            let fade: &mut [u8] = if c.state {
                let (buf, used) = &mut rest[pj.slot];
                let taken = core::mem::take(buf);
                let (_, tail) = taken.split_at_mut(pj.job.first as usize - *used);
                let (mine, tail) = tail.split_at_mut(pj.job.count as usize);
                *buf = tail;
                *used = (pj.job.first + pj.job.count) as usize;
                mine
            } else {
                &mut []
            };
            work.push((*pj, fade));
        }

        let width = options.wave_width;
        let results: Vec<Result<JobResult<I>, Error>> = work
            .into_par_iter()
            .map_init(
                || (Vec::<I>::new(), Vec::<DrawableSetupBatch>::new()),
                |(si, sb), (pj, fade)| {
                    let mut stats = QueryStats::default();
                    let r = run_into(
                        &c,
                        &tiles[pj.slot],
                        hiz,
                        fade,
                        pj.job,
                        width,
                        si,
                        sb,
                        &mut stats,
                    )?;
                    Ok(JobResult {
                        instances: si[..r.instances].to_vec(),
                        batches: sb[..r.batches].to_vec(),
                        stats,
                        live: r.live,
                    })
                },
            )
            .collect();

        for (pj, r) in jobs.iter().zip(results) {
            let r = r?;
            if c.fade && !c.first {
                set_live(&mut cluster_states[pj.slot][pj.cluster], r.live);
            }
            out.stats = out.stats.merge(&r.stats);
            append(
                &mut out.instances,
                &mut out.batches,
                &r.instances,
                &r.batches,
                r.instances.len(),
                r.batches.len(),
            );
        }
        Ok(())
    }
}
