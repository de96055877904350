//! `fur bench`: what a frame costs on this device, what image quality and simulation
//! accuracy each setting buys, how cost scales, and what skipping unneeded work saves.
//! Writes `results.csv` (every measurement), `results.md` (tables) and SVG charts.
//!
//! Times are medians over repeated frames after warm-up frames (which pay lazy shader
//! compilation). Frame times are wall-clock, submission to fence, beside GPU timestamps
//! where the device has them. A pass is costed by running it alone: on a binning
//! rasteriser (lavapipe) a timestamp between two passes lands part-way through the
//! second's binning and misattributes.

mod animation;

/// The collision target on the walking critter that the animation section reports
/// against: the deepest strand vertex inside the posed body at most this fraction of the
/// hair length…
pub const DEPTH_TARGET: f64 = 0.01;
/// …at a cost of at most this share of the simulation step.
pub const COLLISION_COST_TARGET: f64 = 0.35;
mod collision;
mod docs;
mod flow;
mod frame;
mod grooms;
mod ladder;
mod looks;
pub mod metrics;
pub use docs::{check_docs, write_docs, DOCS_BEGIN, DOCS_END};
mod orbit;
pub mod plot;
pub mod quality;
mod raster;
mod render;
mod savings;
mod sim;
mod stages;
mod truth;

use std::fmt::Write as _;
use std::path::Path;
use std::sync::Arc;

use ash::vk;

use fur_core::scene_file::Scene;
use fur_gpu::error::{Error, Result};
use fur_gpu::gpu::Device;
use plot::Plot;

/// How much to measure.
#[derive(Clone, Debug)]
pub struct BenchOptions {
    /// A small, fast suite (for CI): fewer cases, frames and pixels.
    pub quick: bool,
    /// The sections to run, in order.
    pub sections: Vec<Section>,
    /// A scene (`fur bench --scene`) measured by the frame and render-quality sections
    /// instead of the blob and the original's sphere.
    pub scene: Option<(String, Scene)>,
    /// The image size (width, height) of the frame and quality measurements, instead
    /// of 1280×720 (160×90 in the quick suite).
    pub size: Option<(u32, u32)>,
    /// Where the `truth` section keeps its exports and path-traced references (the
    /// output folder), and the repository root it finds the reference renderer under.
    pub work: Option<(std::path::PathBuf, std::path::PathBuf)>,
}

/// A scene the frame and render-quality sections measure.
#[derive(Clone, Debug)]
pub(crate) struct BenchScene {
    pub name: String,
    pub scene: Scene,
}

impl BenchOptions {
    /// The scenes the frame and render-quality sections measure.
    pub(crate) fn scenes(&self) -> Vec<BenchScene> {
        use fur_core::scene::ModelSpec;
        match &self.scene {
            Some((name, scene)) => vec![BenchScene {
                name: name.clone(),
                scene: scene.clone(),
            }],
            None => [("blob", ModelSpec::Blob), ("sphere", ModelSpec::Sphere)]
                .into_iter()
                .map(|(name, model)| BenchScene {
                    name: name.into(),
                    scene: Scene::defaults(model),
                })
                .collect(),
        }
    }
}

/// The parts of the benchmark, runnable alone (`fur bench --only`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Section {
    Frame,
    RenderQuality,
    SimAccuracy,
    SimSteps,
    SimScaling,
    Collision,
    Savings,
    Looks,
    Ladder,
    Animation,
    Truth,
    Stages,
    Grooms,
    Flow,
    Raster,
}

impl Section {
    pub const ALL: [Section; 15] = [
        Self::Frame,
        Self::RenderQuality,
        Self::SimAccuracy,
        Self::SimSteps,
        Self::SimScaling,
        Self::Collision,
        Self::Savings,
        Self::Looks,
        Self::Ladder,
        Self::Animation,
        Self::Truth,
        Self::Stages,
        Self::Grooms,
        Self::Flow,
        Self::Raster,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Self::Frame => "frame",
            Self::RenderQuality => "render_quality",
            Self::SimAccuracy => "sim_accuracy",
            Self::SimSteps => "sim_steps",
            Self::SimScaling => "sim_scaling",
            Self::Collision => "collision",
            Self::Savings => "savings",
            Self::Looks => "looks",
            Self::Ladder => "ladder",
            Self::Animation => "animation",
            Self::Truth => "truth",
            Self::Stages => "stages",
            Self::Grooms => "grooms",
            Self::Flow => "flow",
            Self::Raster => "raster",
        }
    }

    pub fn about(self) -> &'static str {
        match self {
            Self::Frame => "steady-state frame time of the blob and the original's sphere scene, and each pass alone",
            Self::RenderQuality => "image error (FLIP, RMSE) against a supersampled reference, per render setting, with cost",
            Self::SimAccuracy => "simulation error against the converged CPU f64 reference, per iterations and substeps",
            Self::SimSteps => "cost of each simulation step, compiled in alone",
            Self::SimScaling => "simulation cost per strand from 1K to 100K strands",
            Self::Collision => "distance-field build cost and size, collision cost, penetration against resolution",
            Self::Savings => "what skipping work the scene does not need saves",
            Self::Looks => "cost and image effect of texture colour, secondary highlight, shadows and thin-hair AA",
            Self::Ladder => "frame time and image error of every rung of the frame-time budget's quality ladder",
            Self::Animation => "the walking critter: skinning cost, walking against standing, and each way of colliding with the deforming body",
            Self::Truth => "every quality rung and look against a path-traced reference (Mitsuba 3's hair model; needs tools/reference/setup.sh)",
            Self::Stages => "cost of each stage view (--show) against the lit frame",
            Self::Raster => "the two strand rasterisers (hardware, compute) on each scene: frame, fur and each compute pass, image error, pool counts",
            Self::Flow => "laying the fur's flow along the body: building the field and growing the master hairs on models up to 100K vertices",
            Self::Grooms => "reading a million guide curves as .usda, .usdc and .hair: time, and the decoding's memory against its limit",
        }
    }

    /// Sections named in `names` (all of them for an empty list), in suite order.
    pub fn parse_list(names: &[String]) -> Result<Vec<Section>> {
        for name in names {
            if !Self::ALL.iter().any(|s| s.name() == name) {
                let known: Vec<&str> = Self::ALL.iter().map(|s| s.name()).collect();
                return Err(Error::parameter(format!(
                    "unknown benchmark section `{name}`; the sections are {}",
                    known.join(", ")
                )));
            }
        }
        Ok(Self::ALL
            .into_iter()
            .filter(|s| names.is_empty() || names.iter().any(|n| n == s.name()))
            .collect())
    }
}

/// One measurement.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub section: &'static str,
    pub case: String,
    pub metric: &'static str,
    pub value: f64,
    pub unit: &'static str,
}

/// Everything the benchmark produced.
pub struct Report {
    pub device: String,
    pub rows: Vec<Row>,
    pub markdown: String,
    pub plots: Vec<(&'static str, Plot)>,
}

impl Report {
    /// Writes `results.csv`, `results.md` and the charts into `dir`.
    pub fn write(&self, dir: &Path) -> Result<()> {
        std::fs::create_dir_all(dir).map_err(|e| Error::io("create the folder", dir, e))?;
        let mut csv = String::from("section,case,metric,value,unit\n");
        for r in &self.rows {
            let _ = writeln!(
                csv,
                "{},{},{},{},{}",
                r.section,
                csv_field(&r.case),
                r.metric,
                r.value,
                csv_field(r.unit)
            );
        }
        let write = fur_core::files::write_output;
        write(&dir.join("results.csv"), csv.as_bytes(), "write")?;
        write(&dir.join("results.md"), self.markdown.as_bytes(), "write")?;
        for (name, plot) in &self.plots {
            write(&dir.join(name), plot.render()?.as_bytes(), "write")?;
        }
        Ok(())
    }
}

/// Quotes a CSV field when it holds a comma or a quote.
fn csv_field(text: &str) -> String {
    if text.contains([',', '"']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// The work of one run: the device, what is measured so far, and progress.
struct Bench<'a> {
    device: &'a Arc<Device>,
    quick: bool,
    size: Option<(u32, u32)>,
    scenes: Vec<BenchScene>,
    /// Whether `scenes` are the built-in ones (no `--scene` file): the truth section
    /// then adds the walking critter.
    default_scenes: bool,
    work: Option<(std::path::PathBuf, std::path::PathBuf)>,
    rows: Vec<Row>,
    md: String,
    plots: Vec<(&'static str, Plot)>,
    progress: &'a mut dyn FnMut(&str),
}

/// The number of progress ticks `run` reports.
pub fn task_count(options: &BenchOptions) -> u64 {
    options
        .sections
        .iter()
        .map(|s| match s {
            Section::Frame => frame::tasks(options.scenes().len()),
            Section::RenderQuality => render::tasks(options.quick, options.scenes().len()),
            Section::SimAccuracy => sim::accuracy_tasks(options.quick),
            Section::SimSteps => 1,
            Section::SimScaling => sim::scaling_tasks(options.quick),
            Section::Collision => collision::tasks(options.quick),
            Section::Savings => savings::TASKS,
            Section::Looks => looks::tasks(options.quick),
            Section::Ladder => ladder::tasks(options.scenes().len()) + 2,
            Section::Animation => animation::tasks(),
            Section::Truth => truth::tasks(
                options.quick,
                options.scenes().len() + 2 * usize::from(options.scene.is_none()),
            ),
            Section::Stages => stages::tasks(),
            Section::Grooms => grooms::TASKS,
            Section::Flow => flow::tasks(options.quick),
            Section::Raster => raster::tasks(options.scenes().len()),
        })
        .sum()
}

/// Runs the chosen sections on `device`, calling `progress` once per finished task.
pub fn run(
    device: &Arc<Device>,
    options: &BenchOptions,
    progress: &mut dyn FnMut(&str),
) -> Result<Report> {
    let mut bench = Bench {
        device,
        quick: options.quick,
        size: options.size,
        scenes: options.scenes(),
        default_scenes: options.scene.is_none(),
        work: options.work.clone(),
        rows: Vec::new(),
        md: String::new(),
        plots: Vec::new(),
        progress,
    };
    let name = &device.info().name;
    let _ = writeln!(
        bench.md,
        "# fur bench\n\nDevice: {name}, driver {}. Medians over repeated frames after \
         warm-up.{}\n",
        device.info().driver,
        if options.quick { " Quick suite." } else { "" }
    );
    for section in &options.sections {
        match section {
            Section::Frame => bench.frame()?,
            Section::RenderQuality => bench.render_quality()?,
            Section::SimAccuracy => bench.simulation_accuracy()?,
            Section::SimSteps => bench.simulation_steps()?,
            Section::SimScaling => bench.simulation_scaling()?,
            Section::Collision => bench.collision()?,
            Section::Savings => bench.savings()?,
            Section::Looks => bench.looks()?,
            Section::Ladder => bench.ladder()?,
            Section::Animation => bench.animation()?,
            Section::Truth => bench.truth()?,
            Section::Stages => bench.stages()?,
            Section::Grooms => bench.grooms()?,
            Section::Flow => bench.flow()?,
            Section::Raster => bench.raster()?,
        }
    }
    Ok(Report {
        device: name.clone(),
        rows: bench.rows,
        markdown: bench.md,
        plots: bench.plots,
    })
}

impl Bench<'_> {
    fn row(
        &mut self,
        section: &'static str,
        case: impl Into<String>,
        metric: &'static str,
        value: f64,
        unit: &'static str,
    ) {
        self.rows.push(Row {
            section,
            case: case.into(),
            metric,
            value,
            unit,
        });
    }

    /// The image size of the frame and quality measurements.
    fn frame_extent(&self) -> vk::Extent2D {
        if let Some((width, height)) = self.size {
            vk::Extent2D { width, height }
        } else if self.quick {
            vk::Extent2D {
                width: 160,
                height: 90,
            }
        } else {
            vk::Extent2D {
                width: 1280,
                height: 720,
            }
        }
    }

    /// The frames a drawing is measured over.
    fn frames(&self) -> metrics::Frames {
        let (warm, measured) = if self.quick { (1, 3) } else { (3, 15) };
        metrics::Frames { warm, measured }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fur_core::scene::ModelSpec;

    #[test]
    fn a_scene_file_is_measured_with_its_own_simulation_motion_and_drawing() {
        let mut scene = Scene::defaults(ModelSpec::Blob);
        scene.sim.substeps = 3;
        scene.motion.rate = 2.5;
        scene.options.draw.hair_width *= 2.0;
        let options = BenchOptions {
            work: None,
            quick: true,
            sections: vec![Section::Frame],
            scene: Some(("mine".into(), scene.clone())),
            size: None,
        };
        let scenes = options.scenes();
        assert_eq!(scenes.len(), 1);
        assert_eq!(scenes[0].name, "mine");
        assert_eq!(scenes[0].scene, scene);
        // Reference quality changes how hair is drawn, not the hair.
        let reference = scene.options.draw.reference_quality();
        assert_eq!(reference.hair_width, scene.options.draw.hair_width);
        assert_eq!(reference.samples, 4);
        // Without a scene: the blob and the original's sphere with their defaults.
        let built_in = BenchOptions {
            work: None,
            scene: None,
            ..options
        }
        .scenes();
        let names: Vec<&str> = built_in.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, ["blob", "sphere"]);
        assert_eq!(built_in[1].scene, Scene::defaults(ModelSpec::Sphere));
    }
}
