//! The truth section's references, path-traced once: each is kept in the output folder
//! under a hash of the export, the renderer script, the sample count, Mitsuba's
//! variant, the seed and the bounce limit, beside the seconds it took to path-trace
//! (what a reference costs: the frame's loading and its own samples), so a rerun
//! path-traces nothing it has; a frame's references are path-traced together, loaded once.

use std::path::{Path, PathBuf};

use crate::export::reference::{
    read_pfm, Job, LinearImage, Reference, TraceOptions, Variant, SCRIPT,
};
use fur_gpu::error::Result;

/// The longest cost file read back (a number and a newline).
const COST_FILE_LIMIT: u64 = 64;

/// How the section's references are path-traced: samples a pixel and the variant.
#[derive(Clone, Copy, Debug)]
pub(super) struct Sampling {
    pub spp: u32,
    pub variant: Variant,
}

/// A reference and what it cost.
pub(super) struct Traced {
    pub image: LinearImage,
    /// Seconds it took to path-trace, if known (a reference kept from before costs
    /// were kept has none).
    pub seconds: Option<f64>,
}

/// The reference of `usda` (whose text is `text`) sampled as `sampling` says, seed
/// `seed`, at most `depth` bounces, path-traced unless a file of the same hash is there.
pub(super) fn cached_trace(
    reference: &Reference,
    usda: &Path,
    text: &str,
    sampling: Sampling,
    seed: u32,
    depth: Option<u32>,
) -> Result<Traced> {
    let mut traced = cached_traces(reference, usda, text, sampling, &[(seed, depth)])?;
    Ok(traced.remove(0))
}

/// The references of `usda` for each (seed, longest path) of `wanted`, in order: those
/// not kept are path-traced together, the frame loaded once (each one's cost is what it
/// would have cost alone: the loading and its own samples).
pub(super) fn cached_traces(
    reference: &Reference,
    usda: &Path,
    text: &str,
    sampling: Sampling,
    wanted: &[(u32, Option<u32>)],
) -> Result<Vec<Traced>> {
    let stems: Vec<PathBuf> = wanted
        .iter()
        .map(|&(seed, depth)| stem(usda, text, sampling, seed, depth))
        .collect();
    let pfms: Vec<PathBuf> = stems.iter().map(|s| s.with_extension("pfm")).collect();
    let missing: Vec<usize> = (0..wanted.len()).filter(|&i| !pfms[i].is_file()).collect();
    if !missing.is_empty() {
        let jobs: Vec<Job> = missing
            .iter()
            .map(|&i| Job {
                seed: wanted[i].0,
                max_depth: wanted[i].1,
                out: &pfms[i],
            })
            .collect();
        let options = TraceOptions {
            spp: sampling.spp,
            variant: sampling.variant,
            ..Default::default()
        };
        let costs = reference.trace_jobs(usda, &jobs, &options, &[])?;
        for (&i, seconds) in missing.iter().zip(costs) {
            let cost = stems[i].with_extension("seconds");
            let seconds = format!("{seconds:.1}\n");
            fur_core::files::write_output(
                &cost,
                seconds.as_bytes(),
                "write the reference's cost to",
            )?;
        }
    }
    stems
        .iter()
        .zip(&pfms)
        .map(|(stem, pfm)| {
            Ok(Traced {
                image: read_pfm(pfm)?,
                seconds: kept_seconds(&stem.with_extension("seconds")),
            })
        })
        .collect()
}

/// The seconds a reference's cost file `path` holds, if it holds a sound figure.
fn kept_seconds(path: &Path) -> Option<f64> {
    let text = fur_core::files::read_text_bounded(path, COST_FILE_LIMIT, "a cost").ok()?;
    text.trim()
        .parse::<f64>()
        .ok()
        .filter(|s| s.is_finite() && *s >= 0.0)
}

/// The path of the reference's files without their extension.
fn stem(usda: &Path, text: &str, sampling: Sampling, seed: u32, depth: Option<u32>) -> PathBuf {
    let Sampling { spp, variant } = sampling;
    // The scalar variant's key is as it was before the variant was one, so references
    // kept from then are found.
    let variant = match variant {
        Variant::Scalar => String::new(),
        v => format!(" {}", v.name()),
    };
    let key = fnv64(&[
        text.as_bytes(),
        SCRIPT.as_bytes(),
        format!("{spp} {seed} {depth:?}{variant}").as_bytes(),
    ]);
    let dir = usda.parent().map_or(PathBuf::from("."), Path::to_path_buf);
    dir.join(format!("reference-{key:016x}"))
}

/// FNV-1a, 64 bits, over the parts in order.
fn fnv64(parts: &[&[u8]]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for part in parts {
        for &b in *part {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A reference's cost is read back from its file; a missing, empty, negative or
    /// non-numeric one reads as unknown, and another seed or variant is another
    /// reference's file; the scalar variant's file is the one kept before the variant was
    /// part of the key.
    /// Seen failing against parsing the file whole (its newline made every kept cost
    /// unknown).
    #[test]
    fn a_kept_cost_reads_back_and_a_bad_one_is_unknown() {
        let dir = std::env::temp_dir().join(format!("fur-trace-cost-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let usda = dir.join("frame.usda");
        let sampling = |variant| Sampling { spp: 16, variant };
        let cost =
            stem(&usda, "frame", sampling(Variant::Scalar), 0, None).with_extension("seconds");
        assert_eq!(kept_seconds(&cost), None);
        for (written, read) in [
            ("83.2\n", Some(83.2)),
            ("", None),
            ("-1\n", None),
            ("NaN\n", None),
            ("fast\n", None),
        ] {
            std::fs::write(&cost, written).unwrap();
            assert_eq!(kept_seconds(&cost), read, "{written:?}");
        }
        assert_ne!(
            cost,
            stem(&usda, "frame", sampling(Variant::Scalar), 1, None).with_extension("seconds")
        );
        assert_ne!(
            cost,
            stem(&usda, "frame", sampling(Variant::Llvm), 0, None).with_extension("seconds")
        );
        // The scalar variant's key is the one kept before the variant was part of it.
        let before = fnv64(&["frame".as_bytes(), SCRIPT.as_bytes(), b"16 0 None"]);
        assert_eq!(
            cost,
            dir.join(format!("reference-{before:016x}.seconds")),
            "a scalar reference kept from before is not found"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
