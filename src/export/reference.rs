//! The path-traced reference: `tools/reference/render.py` (Mitsuba 3, embedded in the
//! program) run by the Python of the virtual environment `tools/reference/setup.sh`
//! makes, and the linear images it writes (PFM).

use std::path::{Path, PathBuf};
use std::process::Command;

use glam::Vec3;

use fur_gpu::error::{CoreError, Error, Result};

/// The renderer script, as shipped in `tools/reference/render.py`.
pub const SCRIPT: &str = include_str!("../../tools/reference/render.py");

/// The environment variable naming the reference's Python interpreter.
pub const PYTHON_ENV: &str = "FUR_REFERENCE_PYTHON";

/// Where `tools/reference/setup.sh` puts the interpreter, relative to the repository.
pub const DEFAULT_PYTHON: &str = "tools/reference/.venv/bin/python";

/// The largest reference image read, in bytes (a 16384² float RGB image is 3 GiB).
pub const MAX_PFM_BYTES: u64 = 4 << 30;

/// Which of Mitsuba's builds of the renderer path-traces: the same model and
/// integrator, a different engine (and so another sequence of random samples).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// `scalar_rgb`: one sample at a time, nothing but the Python wheel needed.
    Scalar,
    /// `llvm_ad_rgb`: the whole image's samples JIT-compiled into vector code by LLVM
    /// (Debian's `libllvm19`): a few seconds to compile, then about twice the samples
    /// a second on a CPU.
    Llvm,
}

impl Variant {
    /// Mitsuba's name for it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Scalar => "scalar_rgb",
            Self::Llvm => "llvm_ad_rgb",
        }
    }
}

/// How to path-trace a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TraceOptions {
    pub spp: u32,
    pub seed: u32,
    pub variant: Variant,
    /// Leave the environment light out (the calibration's direct light only).
    pub direct_only: bool,
    pub no_hair: bool,
}

impl Default for TraceOptions {
    fn default() -> Self {
        Self {
            spp: 64,
            seed: 0,
            variant: Variant::Scalar,
            direct_only: false,
            no_hair: false,
        }
    }
}

/// A linear RGB image, rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct LinearImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Vec3>,
}

/// The reference renderer, set up.
#[derive(Clone, Debug)]
pub struct Reference {
    python: PathBuf,
}

impl Reference {
    /// The interpreter `FUR_REFERENCE_PYTHON` names, else the one `tools/reference/setup.sh`
    /// makes under `root`; checked to import Mitsuba and usd-core. The error says how to
    /// set it up.
    pub fn find(root: &Path) -> Result<Self> {
        let python = match std::env::var_os(PYTHON_ENV) {
            Some(p) if !p.is_empty() => PathBuf::from(p),
            _ => root.join(DEFAULT_PYTHON),
        };
        let missing = |why: String| {
            Error::parameter(format!(
                "the path-traced reference is not set up ({why}): run tools/reference/setup.sh, \
                 or name a Python with Mitsuba 3 and usd-core in {PYTHON_ENV}"
            ))
        };
        if !python.is_file() {
            return Err(missing(format!("no Python at {}", python.display())));
        }
        let output = Command::new(&python)
            .args(["-c", "import mitsuba, pxr.Usd"])
            .output()
            .map_err(|e| missing(format!("{}: {e}", python.display())))?;
        if !output.status.success() {
            return Err(missing(format!(
                "{} cannot import mitsuba and pxr: {}",
                python.display(),
                last_line(&output.stderr)
            )));
        }
        Ok(Self { python })
    }

    /// The interpreter used.
    pub fn python(&self) -> &Path {
        &self.python
    }

    /// The fastest variant this set-up runs: the LLVM one where Mitsuba finds the LLVM
    /// library (Debian: `libllvm19`), else the scalar one.
    pub fn fastest_variant(&self) -> Variant {
        let probe = format!(
            "import mitsuba as mi; mi.set_variant('{}')",
            Variant::Llvm.name()
        );
        let runs = Command::new(&self.python)
            .args(["-c", &probe])
            .output()
            .is_ok_and(|o| o.status.success());
        if runs {
            Variant::Llvm
        } else {
            Variant::Scalar
        }
    }

    /// Path-traces the exported frame `usda` into `out` (PFM, linear), with the script
    /// written beside it; `extra` arguments go to the script as they are (tests use
    /// them to break a convention on purpose).
    pub fn trace(
        &self,
        usda: &Path,
        out: &Path,
        options: &TraceOptions,
        extra: &[&str],
    ) -> Result<()> {
        let job = Job {
            seed: options.seed,
            max_depth: None,
            out,
        };
        self.trace_jobs(usda, &[job], options, extra).map(|_| ())
    }

    /// Path-traces the exported frame `usda` once loaded into each job's image (its seed
    /// and longest path; `options.seed` is not used). Returns each image's cost in
    /// seconds: the scene's loading and its own samples, what it would have cost alone.
    pub fn trace_jobs(
        &self,
        usda: &Path,
        jobs: &[Job],
        options: &TraceOptions,
        extra: &[&str],
    ) -> Result<Vec<f64>> {
        let Some(first) = jobs.first() else {
            return Ok(Vec::new());
        };
        let dir = first.out.parent().filter(|d| !d.as_os_str().is_empty());
        let script = dir.unwrap_or(Path::new(".")).join(".fur-reference.py");
        std::fs::write(&script, SCRIPT)
            .map_err(|e| Error::io("write the reference renderer to", &script, e))?;
        let depth = |job: &Job| job.max_depth.unwrap_or(DEFAULT_MAX_DEPTH).to_string();
        let mut command = Command::new(&self.python);
        command
            .arg(&script)
            .arg(usda)
            .arg("--out")
            .arg(first.out)
            .args(["--seed", &first.seed.to_string()])
            .args(["--max-depth", &depth(first)])
            .args(["--spp", &options.spp.to_string()])
            .args(["--variant", options.variant.name()])
            .args(extra);
        for job in &jobs[1..] {
            command
                .arg("--also")
                .arg(job.seed.to_string())
                .arg(depth(job))
                .arg(job.out);
        }
        if options.direct_only {
            command.arg("--direct-only");
        }
        if options.no_hair {
            command.arg("--no-hair");
        }
        let output = command
            .output()
            .map_err(|e| Error::parameter(format!("running {}: {e}", self.python.display())))?;
        let _ = std::fs::remove_file(&script);
        if !output.status.success() {
            return Err(Error::parameter(format!(
                "the reference renderer failed on {}: {}",
                usda.display(),
                last_line(&output.stderr)
            )));
        }
        let costs = costs(&output.stdout);
        if costs.len() != jobs.len() {
            return Err(Error::parameter(format!(
                "the reference renderer wrote {} of {} images of {}",
                costs.len(),
                jobs.len(),
                usda.display()
            )));
        }
        Ok(costs)
    }
}

/// One image of a loaded frame: its seed, its longest path (the script's default of
/// [`DEFAULT_MAX_DEPTH`] bounces if none) and its file.
#[derive(Clone, Copy, Debug)]
pub struct Job<'a> {
    pub seed: u32,
    pub max_depth: Option<u32>,
    pub out: &'a Path,
}

/// The script's longest path, in bounces, when none is asked for.
pub const DEFAULT_MAX_DEPTH: u32 = 64;

/// The seconds each image cost, from the script's last `seconds:` line.
fn costs(stdout: &[u8]) -> Vec<f64> {
    let text = String::from_utf8_lossy(stdout);
    text.lines()
        .rev()
        .find_map(|l| l.strip_prefix("seconds:"))
        .map(|rest| {
            rest.split_whitespace()
                .filter_map(|s| s.parse::<f64>().ok())
                .filter(|s| s.is_finite() && *s >= 0.0)
                .collect()
        })
        .unwrap_or_default()
}

fn last_line(bytes: &[u8]) -> String {
    let text = String::from_utf8_lossy(bytes);
    text.lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("no message")
        .to_string()
}

/// Reads a little-endian float RGB PFM (`PF`, scale < 0) as the reference writes it.
pub fn read_pfm(path: &Path) -> Result<LinearImage> {
    let bad = |message: String| {
        Error::Core(CoreError::Io {
            operation: "read the reference image",
            path: path.to_path_buf(),
            message,
        })
    };
    let bytes =
        fur_core::files::read_bounded(path, MAX_PFM_BYTES, "reference image").map_err(bad)?;
    // Three header lines: "PF", "width height", the scale (negative: little-endian).
    let mut lines = Vec::new();
    let mut at = 0;
    while lines.len() < 3 {
        let end = bytes[at..]
            .iter()
            .position(|&b| b == b'\n')
            .ok_or_else(|| bad("a PFM header has three lines".into()))?;
        lines.push(
            String::from_utf8_lossy(&bytes[at..at + end])
                .trim()
                .to_string(),
        );
        at += end + 1;
    }
    if lines[0] != "PF" {
        return Err(bad(format!("not a colour PFM (starts `{}`)", lines[0])));
    }
    let size: Vec<u32> = lines[1]
        .split_whitespace()
        .filter_map(|s| s.parse().ok())
        .collect();
    let scale: f32 = lines[2].parse().map_err(|_| bad("no scale".into()))?;
    let [width, height] = size[..] else {
        return Err(bad(format!("bad size line `{}`", lines[1])));
    };
    if scale >= 0.0 {
        return Err(bad(
            "a big-endian PFM (the reference writes little-endian)".into()
        ));
    }
    let expected = width as usize * height as usize * 12;
    if bytes.len() - at != expected {
        return Err(bad(format!(
            "{width}×{height} needs {expected} bytes of pixels, the file has {}",
            bytes.len() - at
        )));
    }
    let floats: Vec<f32> = bytes[at..]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    // PFM rows run bottom to top.
    let mut pixels = Vec::with_capacity(floats.len() / 3);
    for row in (0..height as usize).rev() {
        let start = row * width as usize * 3;
        for p in floats[start..start + width as usize * 3].chunks_exact(3) {
            pixels.push(Vec3::new(p[0], p[1], p[2]));
        }
    }
    Ok(LinearImage {
        width,
        height,
        pixels,
    })
}

#[cfg(test)]
mod tests {
    use super::costs;

    /// The costs come from the script's last `seconds:` line, one a job; a line
    /// without them, or a figure that is no cost, gives none (and the run is refused
    /// as having written fewer images than asked). Seen failing against reading the
    /// first `seconds:` line (an earlier run's, in a log).
    #[test]
    fn each_images_cost_is_read_from_the_last_seconds_line() {
        let out = b"seconds: 9\nwrote a.pfm in 5.4 s\nwrote b.pfm in 5.1 s\nseconds: 5.38 5.07\n";
        assert_eq!(costs(out), vec![5.38, 5.07]);
        assert!(costs(b"wrote a.pfm in 5.4 s\n").is_empty());
        assert_eq!(costs(b"seconds: 1.5 NaN -2 fast 3\n"), vec![1.5, 3.0]);
    }
}
