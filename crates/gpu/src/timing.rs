//! GPU timings from timestamp queries: each timed pass writes a timestamp at its beginning
//! and end (`TIMESTAMP_QUERY`), and spans with the same label are summed.

use crate::error::Result;
use crate::resources::readback::read_buffer;

/// Collects begin/end timestamps of passes in one frame.
pub struct GpuTimer {
    query_set: Option<wgpu::QuerySet>,
    resolve: Option<wgpu::Buffer>,
    labels: Vec<&'static str>,
    capacity: u32,
    period_ns: f32,
}

/// One timed label: its total GPU time and how many passes it covered.
#[derive(Clone, Debug, PartialEq)]
pub struct Timing {
    /// The label the passes were timed under.
    pub label: &'static str,
    /// Sum over the passes (milliseconds).
    pub ms: f64,
    /// How many passes.
    pub passes: u32,
}

impl GpuTimer {
    /// A timer for up to `max_passes` passes; inert (records nothing) when the device lacks
    /// `TIMESTAMP_QUERY`.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, max_passes: u32) -> Self {
        let capacity = max_passes.max(1) * 2;
        let enabled = device.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let query_set = enabled.then(|| {
            device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: capacity,
            })
        });
        let resolve = enabled.then(|| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp resolve"),
                size: u64::from(capacity) * 8,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        });
        Self {
            query_set,
            resolve,
            labels: Vec::new(),
            capacity,
            period_ns: queue.get_timestamp_period(),
        }
    }

    /// A timer that records nothing (passes submitted outside a measured frame).
    pub(crate) fn inert() -> Self {
        Self {
            query_set: None,
            resolve: None,
            labels: Vec::new(),
            capacity: 0,
            period_ns: 1.0,
        }
    }

    fn next(&mut self, label: &'static str) -> Option<(&wgpu::QuerySet, u32)> {
        let qs = self.query_set.as_ref()?;
        let i = self.labels.len() as u32;
        if 2 * i + 2 > self.capacity {
            return None;
        }
        self.labels.push(label);
        Some((qs, 2 * i))
    }

    /// Timestamp writes for a compute pass timed under `label`.
    pub fn compute(&mut self, label: &'static str) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        self.next(label)
            .map(|(qs, i)| wgpu::ComputePassTimestampWrites {
                query_set: qs,
                beginning_of_pass_write_index: Some(i),
                end_of_pass_write_index: Some(i + 1),
            })
    }

    /// Begins a compute pass in `encoder`, labelled and timed under `label`.
    pub(crate) fn begin_compute<'e>(
        &mut self,
        encoder: &'e mut wgpu::CommandEncoder,
        label: &'static str,
    ) -> wgpu::ComputePass<'e> {
        self.begin_compute_as(encoder, label, label)
    }

    /// Begins a compute pass in `encoder` labelled `label` (what debuggers show) and timed
    /// under `timed` (where several passes share one timing, or the timing's name is shorter).
    pub(crate) fn begin_compute_as<'e>(
        &mut self,
        encoder: &'e mut wgpu::CommandEncoder,
        label: &'static str,
        timed: &'static str,
    ) -> wgpu::ComputePass<'e> {
        encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(label),
            timestamp_writes: self.compute(timed),
        })
    }

    /// Timestamp writes for a render pass timed under `label`.
    pub fn render(&mut self, label: &'static str) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        self.next(label)
            .map(|(qs, i)| wgpu::RenderPassTimestampWrites {
                query_set: qs,
                beginning_of_pass_write_index: Some(i),
                end_of_pass_write_index: Some(i + 1),
            })
    }

    /// Records the resolve of this frame's queries into `encoder` (call once, last).
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        if let (Some(qs), Some(buf)) = (&self.query_set, &self.resolve) {
            let n = self.labels.len() as u32 * 2;
            if n > 0 {
                encoder.resolve_query_set(qs, 0..n, buf, 0);
            }
        }
    }

    /// Forgets this frame's timed passes without reading them (a frame not waited for).
    pub fn discard(&mut self) {
        self.labels.clear();
    }

    /// After the frame's submission: reads the timestamps back and sums them per label, in
    /// first-use order. Clears the timer for the next frame.
    pub fn read(&mut self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<Vec<Timing>> {
        let labels = std::mem::take(&mut self.labels);
        let Some(buf) = &self.resolve else {
            return Ok(Vec::new());
        };
        if labels.is_empty() {
            return Ok(Vec::new());
        }
        let bytes = read_buffer(device, queue, buf, 0, labels.len() as u64 * 16)?;
        let ticks: Vec<u64> = bytemuck::pod_collect_to_vec(&bytes);
        let mut out: Vec<Timing> = Vec::new();
        for (i, label) in labels.into_iter().enumerate() {
            let (b, e) = (ticks[2 * i], ticks[2 * i + 1]);
            let ms = e.saturating_sub(b) as f64 * f64::from(self.period_ns) / 1e6;
            match out.iter_mut().find(|t| t.label == label) {
                Some(t) => {
                    t.ms += ms;
                    t.passes += 1;
                }
                None => out.push(Timing {
                    label,
                    ms,
                    passes: 1,
                }),
            }
        }
        Ok(out)
    }
}
