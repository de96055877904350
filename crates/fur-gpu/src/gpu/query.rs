//! Timestamp and pipeline-statistics query pools.

use std::sync::Arc;

use ash::vk;

use super::Device;
use crate::error::{Result, VkContext};

/// A query pool reset from the host and read back with `WAIT`.
pub struct QueryPool {
    device: Arc<Device>,
    pub raw: vk::QueryPool,
    count: u32,
    /// Values per query (1 for timestamps, one per statistic otherwise).
    values: u32,
}

/// The pipeline statistics the fur pass reports, in Vulkan's bit order.
pub const FUR_STATISTICS: vk::QueryPipelineStatisticFlags =
    vk::QueryPipelineStatisticFlags::from_raw(
        vk::QueryPipelineStatisticFlags::INPUT_ASSEMBLY_PRIMITIVES.as_raw()
            | vk::QueryPipelineStatisticFlags::TESSELLATION_EVALUATION_SHADER_INVOCATIONS.as_raw()
            | vk::QueryPipelineStatisticFlags::GEOMETRY_SHADER_INVOCATIONS.as_raw()
            | vk::QueryPipelineStatisticFlags::GEOMETRY_SHADER_PRIMITIVES.as_raw()
            | vk::QueryPipelineStatisticFlags::TESSELLATION_CONTROL_SHADER_PATCHES.as_raw(),
    );

/// Fur-pass counters read from [`FUR_STATISTICS`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FurStatistics {
    /// Primitives the input assembler made over the target's passes: the body's
    /// triangles, the fur's patches, the master hairs' line segments.
    pub input_primitives: u64,
    /// Patches (mesh triangles) the tessellation control shader ran for.
    pub patches: u64,
    /// Tessellation-evaluation invocations: generated hair points.
    pub tess_eval_invocations: u64,
    /// Geometry-shader invocations: points that reached the geometry shader.
    pub geometry_invocations: u64,
    /// Primitives the geometry shader emitted.
    pub geometry_primitives: u64,
}

impl QueryPool {
    pub fn timestamps(device: &Arc<Device>, name: &str, count: u32) -> Result<Self> {
        Self::new(
            device,
            name,
            vk::QueryType::TIMESTAMP,
            Default::default(),
            count,
            1,
        )
    }

    pub fn fur_statistics(device: &Arc<Device>, name: &str) -> Result<Self> {
        Self::new(
            device,
            name,
            vk::QueryType::PIPELINE_STATISTICS,
            FUR_STATISTICS,
            1,
            FUR_STATISTICS.as_raw().count_ones(),
        )
    }

    fn new(
        device: &Arc<Device>,
        name: &str,
        kind: vk::QueryType,
        statistics: vk::QueryPipelineStatisticFlags,
        count: u32,
        values: u32,
    ) -> Result<Self> {
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(kind)
            .query_count(count)
            .pipeline_statistics(statistics);
        // SAFETY: a create info on a live device; statistics are only asked of a
        // PIPELINE_STATISTICS pool, made only where the device enabled
        // pipelineStatisticsQuery. The pool is destroyed in Drop.
        let raw = unsafe { device.raw.create_query_pool(&info, None) }.vk("vkCreateQueryPool")?;
        device.set_name(raw, name);
        // SAFETY: hostQueryReset is enabled at device creation, the pool was just
        // created (nothing uses it) and `0..count` is its whole range.
        unsafe { device.raw.reset_query_pool(raw, 0, count) };
        Ok(Self {
            device: device.clone(),
            raw,
            count,
            values,
        })
    }

    pub fn raw(&self) -> vk::QueryPool {
        self.raw
    }

    pub fn count(&self) -> u32 {
        self.count
    }

    /// Resets every query from the host (before the command buffer using them runs).
    pub fn reset(&self) {
        self.reset_first(self.count);
    }

    /// Resets the first `count` queries from the host.
    pub fn reset_first(&self, count: u32) {
        // SAFETY: hostQueryReset is enabled; the range is clamped to the pool; callers
        // reset only queries of a frame slot whose last submission has finished (its
        // fence was waited) and before recording the next.
        unsafe {
            self.device
                .raw
                .reset_query_pool(self.raw, 0, count.min(self.count))
        };
    }

    /// Waits for and returns the values of the first `count` queries, `N` per query.
    fn results<const N: usize>(&self, count: u32) -> Result<Vec<[u64; N]>> {
        debug_assert_eq!(N as u32, self.values);
        let mut data = vec![[0u64; N]; count.min(self.count) as usize];
        // SAFETY: the range is clamped to the pool and `data` holds `N` 64-bit values
        // per query, the pool's own count (asserted), as TYPE_64 asks; callers read
        // only queries their finished submission wrote, so WAIT returns.
        unsafe {
            self.device.raw.get_query_pool_results(
                self.raw,
                0,
                &mut data,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .vk("vkGetQueryPoolResults")?;
        Ok(data)
    }

    /// The first `count` timestamps in milliseconds since the first one.
    pub fn timestamps_ms(&self, count: u32) -> Result<Vec<f64>> {
        let ticks: Vec<u64> = self.results::<1>(count)?.into_iter().map(|[t]| t).collect();
        let period = f64::from(self.device.info.timestamp_period) * 1e-6;
        let first = ticks.first().copied().unwrap_or(0);
        Ok(ticks
            .iter()
            .map(|t| t.wrapping_sub(first) as f64 * period)
            .collect())
    }

    /// Reads a [`FurStatistics`] pool.
    pub fn fur_statistics_result(&self) -> Result<FurStatistics> {
        let v = self.results::<5>(1)?[0];
        // Vulkan returns statistics in increasing bit order.
        Ok(FurStatistics {
            input_primitives: v[0],
            geometry_invocations: v[1],
            geometry_primitives: v[2],
            patches: v[3],
            tess_eval_invocations: v[4],
        })
    }
}

impl Drop for QueryPool {
    fn drop(&mut self) {
        // SAFETY: the pool is owned here and destroyed once; owners wait for the device
        // first, so no command buffer in flight writes it.
        unsafe { self.device.raw.destroy_query_pool(self.raw, None) };
    }
}
