//! Image quality against cost for each render setting, on the original demo's sphere
//! scene and the default blob: ꟻLIP and RMSE of a still frame against its supersampled
//! reference (see `quality.rs`), beside the frame's wall-clock time.

use std::fmt::Write as _;

use super::metrics::{flip, pareto_front, rmse};
use super::plot::{Plot, Series, PALETTE};
use super::quality::Shot;
use super::Bench;
use fur_core::render::{FurStyle, Primitive, Raster, Shading};
use fur_gpu::error::Result;

/// A setting to measure: its name, its drawing and the density multiplier.
struct Case {
    name: String,
    draw: FurStyle,
    density: f32,
}

fn cases(quick: bool) -> Vec<Case> {
    let default = FurStyle::default();
    let case = |name: &str, draw: FurStyle| Case {
        name: name.to_string(),
        draw,
        density: 1.0,
    };
    // The default's strands through the fixed-function rasteriser, at `samples` per
    // pixel as `primitive` with the vertex LOD `lod`.
    let with = |samples: u32, primitive: Primitive, lod: f32| FurStyle {
        samples,
        primitive,
        vertex_lod_px: lod,
        raster: Raster::Hardware,
        ..default.clone()
    };
    let lod = default.vertex_lod_px;
    if quick {
        return vec![
            case("reference quality", default.reference_quality()),
            case("default", default.clone()),
            case("4x ribbons", with(4, Primitive::Ribbons, lod)),
            case("1x lines", with(1, Primitive::Lines, lod)),
        ];
    }
    vec![
        case(
            "reference quality: 4x ribbons, fragment lighting, all vertices",
            default.reference_quality(),
        ),
        case(
            "4x ribbons, vertex lighting, all vertices",
            with(4, Primitive::Ribbons, 0.0),
        ),
        case(
            &format!(
                "default: compute strands, {} fragments in order, tiles of the device's side",
                default.nearest
            ),
            default.clone(),
        ),
        case(
            &format!("4x ribbons, vertex lighting, vertex LOD {lod} px"),
            with(4, Primitive::Ribbons, lod),
        ),
        case(
            &format!("4x ribbons, fragment lighting, vertex LOD {lod} px"),
            FurStyle {
                shading: Shading::Fragment,
                ..with(4, Primitive::Ribbons, lod)
            },
        ),
        case(
            "4x ribbons, vertex LOD 0.02 px",
            with(4, Primitive::Ribbons, 0.02),
        ),
        case(
            "4x ribbons, vertex LOD 0.1 px",
            with(4, Primitive::Ribbons, 0.1),
        ),
        case(
            "4x ribbons, vertex LOD 0.25 px",
            with(4, Primitive::Ribbons, 0.25),
        ),
        case(
            "4x lines (coverage as samples)",
            with(4, Primitive::Lines, lod),
        ),
        case("1x ribbons", with(1, Primitive::Ribbons, lod)),
        case(
            "1x lines (blended coverage)",
            with(1, Primitive::Lines, lod),
        ),
        case(
            "1x auto (lines under 1 px)",
            FurStyle {
                ribbon_above_px: 1.0,
                ..with(1, Primitive::Auto, lod)
            },
        ),
        case(
            "strand LOD from 1 radius, thickness compensated",
            FurStyle {
                lod_distance: 1.0,
                ..default.clone()
            },
        ),
        case(
            "strand LOD from 1 radius, not compensated",
            FurStyle {
                lod_distance: 1.0,
                thickness_compensation: false,
                ..default.clone()
            },
        ),
        Case {
            name: "density x0.5".into(),
            draw: default.clone(),
            density: 0.5,
        },
        Case {
            name: "density x0.25".into(),
            draw: default,
            density: 0.25,
        },
    ]
}

pub(super) fn tasks(quick: bool, scenes: usize) -> u64 {
    scenes as u64 * (1 + cases(quick).len() as u64)
}

impl Bench<'_> {
    pub(super) fn render_quality(&mut self) -> Result<()> {
        let extent = self.frame_extent();
        let factor = if self.quick { 2 } else { 4 };
        let _ = writeln!(
            self.md,
            "## Rendering: image quality against cost ({}×{})\n\nA still frame of each scene \
             drawn with each setting, against the same frame rendered at {factor}×{factor} the \
             pixels with 4× MSAA ribbons lit per fragment and box-filtered down in linear light \
             ({} samples per pixel). ꟻLIP is NVIDIA's perceptual error (mean over the image, 0 = \
             identical); RMSE is over RGB on a 0..1 scale. Frame ms: wall clock of the whole \
             still frame (clear, both passes, resolve, copy). Pareto: no other setting is both \
             cheaper and closer.\n",
            extent.width,
            extent.height,
            factor * factor * 4
        );
        let mut series = Vec::new();
        for (k, bench_scene) in self.scenes.clone().iter().enumerate() {
            let scene = &bench_scene.name;
            let shot = Shot::new(self.device, &bench_scene.scene, extent)?;
            let reference = shot.reference(factor)?;
            (self.progress)(&format!("{scene} reference"));
            let mut points = Vec::new();
            for case in cases(self.quick) {
                let style = FurStyle {
                    density: shot.settings.style.density * case.density,
                    ..shot.style(&case.draw)
                };
                let drawn = shot.draw(&style, self.frames())?;
                let counts = drawn.counts.unwrap_or_default();
                points.push((
                    case.name.clone(),
                    drawn.frame_ms,
                    flip(&reference, &drawn.image),
                    rmse(&reference, &drawn.image),
                    counts,
                ));
                (self.progress)(&format!("{scene}: {}", case.name));
            }
            let front = pareto_front(&points.iter().map(|p| (p.1, p.2)).collect::<Vec<_>>());
            let _ = writeln!(
                self.md,
                "### {scene}\n\n| setting | frame ms | ꟻLIP | RMSE | hairs | segments | Pareto |\n\
                 | --- | --- | --- | --- | --- | --- | --- |"
            );
            for (p, on_front) in points.iter().zip(&front) {
                let case = format!("{scene}: {}", p.0);
                self.row("render_quality", case.clone(), "frame_ms", p.1, "ms");
                self.row("render_quality", case.clone(), "flip", p.2, "0..1");
                self.row("render_quality", case.clone(), "rmse", p.3, "0..1");
                self.row(
                    "render_quality",
                    case.clone(),
                    "hairs_drawn",
                    p.4.hairs as f64,
                    "count",
                );
                self.row(
                    "render_quality",
                    case.clone(),
                    "segments_drawn",
                    p.4.segments as f64,
                    "count",
                );
                self.row(
                    "render_quality",
                    case,
                    "pareto",
                    f64::from(u8::from(*on_front)),
                    "bool",
                );
                let _ = writeln!(
                    self.md,
                    "| {} | {:.1} | {:.4} | {:.4} | {} | {} | {} |",
                    p.0,
                    p.1,
                    p.2,
                    p.3,
                    p.4.hairs,
                    p.4.segments,
                    if *on_front { "yes" } else { "" }
                );
            }
            self.md.push('\n');
            series.push(Series {
                name: scene.to_string(),
                points: points.iter().map(|p| (p.1, p.2)).collect(),
                color: PALETTE[k % PALETTE.len()],
                line: false,
            });
        }
        self.plots.push((
            "render_pareto.svg",
            Plot {
                title: "Rendering: ꟻLIP against frame time, one point per setting".into(),
                x_label: "frame ms (wall clock)".into(),
                y_label: "ꟻLIP against the supersampled reference".into(),
                log_x: true,
                log_y: true,
                series,
                highlight: None,
            },
        ));
        Ok(())
    }
}
