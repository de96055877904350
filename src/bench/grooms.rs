//! Reading groom files: a million guide curves as USD text, binary USD and cyHair, read
//! the way `--groom` reads them (USD decoded in a child process under its stated
//! limits): the time a read takes, and the memory the decoding took against the file's
//! size and the limit.

use std::fmt::Write as _;
use std::time::Instant;

use glam::Vec3;

use super::metrics::median;
use super::Bench;
use fur_core::groom_file::{
    parse_cyhair, parse_usd_measured, usd_limits, usdc_from_text, write_cyhair, write_usda,
    GroomFormat, Guides,
};
use fur_gpu::error::{Error, Result};

pub(super) const TASKS: u64 = 3;

/// Vertices per guide curve.
const VERTICES: usize = 4;

/// `curves` guides of [`VERTICES`] vertices with widths and per-vertex colours.
fn guides(curves: usize) -> Guides {
    let n = curves * VERTICES;
    Guides {
        counts: vec![VERTICES as u32; curves],
        points: (0..n)
            .map(|i| {
                let (c, k) = ((i / VERTICES) as f32, (i % VERTICES) as f32);
                Vec3::new(c.sin(), 0.01 * k, c.cos())
            })
            .collect(),
        widths: Some(vec![0.001; n]),
        colors: Some(vec![Vec3::new(0.4, 0.3, 0.2); n]),
        notes: Vec::new(),
    }
}

/// `n` with its thousands grouped by commas, as the documents write counts.
pub(super) fn grouped(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

impl Bench<'_> {
    pub(super) fn grooms(&mut self) -> Result<()> {
        let curves = if self.quick { 10_000 } else { 1_000_000 };
        let reads = if self.quick { 1 } else { 3 };
        let _ = writeln!(
            self.md,
            "## Reading groom files\n\n{} curves of {VERTICES} vertices with widths and \
             colours, read as `--groom` reads them (median of {reads}); USD is decoded in a \
             child process under its limits (docs/robustness.md); its peak is the new address \
             space it took (memory the process had freed before is reused uncounted: run the \
             section alone for the decoding's whole cost).\n\n\
             | format | file MiB | read s | decoding's peak MiB | peak ÷ file | limit MiB |\n\
             | --- | --- | --- | --- | --- | --- |",
            grouped(curves)
        );
        let g = guides(curves);
        let bad = |m: String| Error::parameter(format!("the groom benchmark: {m}"));
        let text = write_usda(&g, "fur bench").map_err(bad)?;
        let binary = usdc_from_text(&text).map_err(bad)?;
        let hair = write_cyhair(&g, "fur bench").map_err(bad)?;
        let cases = [
            ("usda", text.into_bytes(), Some(GroomFormat::Usda)),
            ("usdc", binary, Some(GroomFormat::Usdc)),
            ("hair", hair, None),
        ];
        for (name, bytes, format) in cases {
            let mut seconds = Vec::new();
            let mut peak = 0u64;
            for _ in 0..reads {
                let started = Instant::now();
                let read = match format {
                    Some(format) => parse_usd_measured(&bytes, format).map(|(g, p)| {
                        peak = peak.max(p);
                        g
                    }),
                    None => parse_cyhair(&bytes),
                }
                .map_err(|m| bad(format!("reading the .{name} file: {m}")))?;
                seconds.push(started.elapsed().as_secs_f64());
                if read.count() != curves {
                    return Err(bad(format!(".{name}: {} curves read", read.count())));
                }
            }
            let mib = |b: u64| b as f64 / f64::from(1 << 20);
            let file = mib(bytes.len() as u64);
            let s = median(&seconds);
            self.row("grooms", name, "file_mib", file, "MiB");
            self.row("grooms", name, "read_s", s, "s");
            let (peak_text, ratio, limit) = if format.is_some() {
                let limit = usd_limits(bytes.len()).memory;
                self.row("grooms", name, "peak_mib", mib(peak), "MiB");
                (
                    format!("{:.0}", mib(peak)),
                    format!("{:.1}", peak as f64 / bytes.len() as f64),
                    format!("{:.0}", mib(limit)),
                )
            } else {
                ("(in process)".into(), "—".into(), "—".into())
            };
            let _ = writeln!(
                self.md,
                "| .{name} | {file:.1} | {s:.2} | {peak_text} | {ratio} | {limit} |"
            );
            (self.progress)(name);
        }
        self.md.push('\n');
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn counts_are_grouped_by_thousands() {
        assert_eq!(super::grouped(1_000_000), "1,000,000");
        assert_eq!(super::grouped(10_000), "10,000");
        assert_eq!(super::grouped(999), "999");
    }
}
